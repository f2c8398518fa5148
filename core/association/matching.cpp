// Greedy and optimal bipartite matching (paper Eq. 1).
#include "jointflow/matching.hpp"

#include <algorithm>
#include <limits>
#include <tuple>

#include "jointflow/error.hpp"

namespace jointflow {
namespace {

void checkInputs(const cv::Mat& psi, const cv::Mat& per_joint) {
  if (psi.type() != CV_32F || per_joint.type() != CV_32F || psi.size() != per_joint.size())
    throw Error("matching: Psi and the per-joint potentials must be CV_32F matrices of one size");
}

bool eligible(const cv::Mat& psi, const cv::Mat& per_joint, int r, int c, float min_potential) {
  return psi.at<float>(r, c) > 0.f && per_joint.at<float>(r, c) >= min_potential;
}

}  // namespace

// Minimum-cost perfect assignment of an n x n cost matrix (Hungarian method with row/column
// potentials and shortest augmenting paths, O(n^3)). Returns the column of each row.
// Hand-written on purpose: OpenCV and Eigen, the libraries the core already uses, have no
// assignment solver, and ~40 lines beat a new dependency (dlib, OR-tools) for one function.
std::vector<int> minCostPerfectAssignment(const std::vector<double>& cost, int n) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(n + 1, 0.0);
  std::vector<int> row_of(n + 1, 0), way(n + 1, 0);  // column -> row (1-based, 0 = none)
  for (int i = 1; i <= n; ++i) {
    row_of[0] = i;
    int j0 = 0;
    std::vector<double> minv(n + 1, inf);
    std::vector<bool> used(n + 1, false);
    do {  // grow the alternating tree from row i until it reaches a free column
      used[j0] = true;
      const int i0 = row_of[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= n; ++j) {
        if (used[j]) continue;
        const double reduced = cost[(i0 - 1) * n + (j - 1)] - u[i0] - v[j];
        if (reduced < minv[j]) {
          minv[j] = reduced;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= n; ++j) {
        if (used[j]) {
          u[row_of[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (row_of[j0] != 0);
    do {  // flip the augmenting path
      const int j1 = way[j0];
      row_of[j0] = row_of[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> col_of(n, -1);
  for (int j = 1; j <= n; ++j)
    if (row_of[j] > 0) col_of[row_of[j] - 1] = j - 1;
  return col_of;
}

std::vector<Match> matchGreedy(const cv::Mat& psi, const cv::Mat& per_joint, float min_potential) {
  checkInputs(psi, per_joint);
  std::vector<std::tuple<float, int, int>> edges;
  for (int r = 0; r < psi.rows; ++r)
    for (int c = 0; c < psi.cols; ++c)
      if (eligible(psi, per_joint, r, c, min_potential))
        edges.emplace_back(psi.at<float>(r, c), r, c);
  std::sort(edges.begin(), edges.end(), [](const auto& a, const auto& b) {
    if (std::get<0>(a) != std::get<0>(b)) return std::get<0>(a) > std::get<0>(b);
    return std::make_pair(std::get<1>(a), std::get<2>(a)) <
           std::make_pair(std::get<1>(b), std::get<2>(b));
  });
  std::vector<bool> row_used(psi.rows, false), col_used(psi.cols, false);
  std::vector<Match> matches;
  for (const auto& [value, r, c] : edges) {
    if (row_used[r] || col_used[c]) continue;
    row_used[r] = col_used[c] = true;
    matches.push_back({r, c});
  }
  return matches;
}

std::vector<Match> matchOptimal(const cv::Mat& psi, const cv::Mat& per_joint, float min_potential) {
  checkInputs(psi, per_joint);
  const int n = std::max(psi.rows, psi.cols);
  if (n == 0) return {};
  // Maximising the sum of eligible Psi (all > 0) with "at most one" constraints equals a perfect
  // assignment on the square matrix of costs -Psi, with 0 for ineligible or padded pairs.
  std::vector<double> cost(static_cast<size_t>(n) * n, 0.0);
  for (int r = 0; r < psi.rows; ++r)
    for (int c = 0; c < psi.cols; ++c)
      if (eligible(psi, per_joint, r, c, min_potential))
        cost[static_cast<size_t>(r) * n + c] = -static_cast<double>(psi.at<float>(r, c));
  const std::vector<int> col_of = minCostPerfectAssignment(cost, n);
  std::vector<Match> matches;
  for (int r = 0; r < psi.rows; ++r) {
    const int c = col_of[r];
    if (c >= 0 && c < psi.cols && eligible(psi, per_joint, r, c, min_potential))
      matches.push_back({r, c});
  }
  return matches;
}

std::vector<Match> matchPoses(Matcher matcher, const cv::Mat& psi, const cv::Mat& per_joint,
                              float min_potential) {
  return matcher == Matcher::kOptimal ? matchOptimal(psi, per_joint, min_potential)
                                      : matchGreedy(psi, per_joint, min_potential);
}

}  // namespace jointflow
