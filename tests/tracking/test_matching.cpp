// Greedy (paper) and optimal bipartite matching of Eq. 1; the optimum against brute force.
#include <algorithm>
#include <numeric>
#include <random>

#include <catch2/catch.hpp>

#include "jointflow/error.hpp"
#include "jointflow/matching.hpp"

using namespace jointflow;

namespace {

cv::Mat mat(int rows, int cols, std::initializer_list<float> v) {
  cv::Mat m(rows, cols, CV_32F);
  std::copy(v.begin(), v.end(), m.ptr<float>());
  return m;
}

float total(const cv::Mat& psi, const std::vector<Match>& matches) {
  float sum = 0.f;
  for (const Match& m : matches) sum += psi.at<float>(m.row, m.col);
  return sum;
}

// Best total over every partial assignment of rows to distinct columns (or none).
float bruteForce(const cv::Mat& psi, const cv::Mat& per_joint, float min_potential, int row,
                 std::vector<bool>& used) {
  if (row == psi.rows) return 0.f;
  float best = bruteForce(psi, per_joint, min_potential, row + 1, used);  // row unmatched
  for (int c = 0; c < psi.cols; ++c) {
    if (used[c] || !(psi.at<float>(row, c) > 0.f) || per_joint.at<float>(row, c) < min_potential)
      continue;
    used[c] = true;
    best = std::max(
        best, psi.at<float>(row, c) + bruteForce(psi, per_joint, min_potential, row + 1, used));
    used[c] = false;
  }
  return best;
}

}  // namespace

TEST_CASE("greedy matching takes pairs in decreasing Psi", "[tracking][matching]") {
  const cv::Mat psi = mat(2, 2, {10, 9, 9, 0});
  const auto greedy = matchGreedy(psi, psi, 0.f);
  REQUIRE(greedy.size() == 1);  // (0,0) first; (1,1) has Psi 0 and is not eligible
  CHECK(greedy[0].row == 0);
  CHECK(greedy[0].col == 0);
  // The optimum pairs crosswise: 9 + 9 > 10.
  const auto optimal = matchOptimal(psi, psi, 0.f);
  CHECK(optimal.size() == 2);
  CHECK(total(psi, optimal) == 18.f);
}

TEST_CASE("no match below the minimum potential or at Psi <= 0", "[tracking][matching]") {
  const cv::Mat psi = mat(2, 3, {4, -1, 0, 0.5f, 3, 2});
  const cv::Mat per_joint = mat(2, 3, {0.4f, -0.1f, 0, 0.5f, 0.3f, 0.2f});
  for (const Matcher matcher : {Matcher::kGreedy, Matcher::kOptimal}) {
    const auto m = matchPoses(matcher, psi, per_joint, 0.35f);
    REQUIRE(m.size() == 1);  // only (0,0) and (1,0) qualify, and both need column 0
    CHECK(total(psi, m) == 4.f);
  }
  CHECK(matchGreedy(psi, per_joint, 0.f).size() == 2);
  CHECK(matchGreedy(cv::Mat::zeros(0, 3, CV_32F), cv::Mat::zeros(0, 3, CV_32F), 0.f).empty());
  CHECK(matchOptimal(cv::Mat::zeros(3, 0, CV_32F), cv::Mat::zeros(3, 0, CV_32F), 0.f).empty());
  CHECK_THROWS_WITH(parseEnum<Matcher>("auction"), Catch::Contains("greedy or optimal"));
  CHECK_THROWS_AS(matchGreedy(psi, cv::Mat::zeros(3, 3, CV_32F), 0.f), Error);
}

TEST_CASE("optimal matching equals brute force on small random cases", "[tracking][matching]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-2.f, 10.f);
  std::uniform_int_distribution<int> size(1, 6);
  int greedy_worse = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int rows = size(rng), cols = size(rng);
    cv::Mat psi(rows, cols, CV_32F), per_joint(rows, cols, CV_32F);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        psi.at<float>(r, c) = std::round(value(rng));  // integers make ties likely
        per_joint.at<float>(r, c) = psi.at<float>(r, c) / 10.f;
      }
    const float min_potential = trial % 3 == 0 ? 0.3f : 0.f;
    std::vector<bool> used(cols, false);
    const float best = bruteForce(psi, per_joint, min_potential, 0, used);
    const auto optimal = matchOptimal(psi, per_joint, min_potential);
    CHECK(total(psi, optimal) == Approx(best));
    // Each row and column at most once, every pair eligible.
    std::vector<int> rows_seen, cols_seen;
    for (const Match& m : optimal) {
      rows_seen.push_back(m.row);
      cols_seen.push_back(m.col);
      CHECK(psi.at<float>(m.row, m.col) > 0.f);
      CHECK(per_joint.at<float>(m.row, m.col) >= min_potential);
    }
    std::sort(rows_seen.begin(), rows_seen.end());
    std::sort(cols_seen.begin(), cols_seen.end());
    CHECK(std::adjacent_find(rows_seen.begin(), rows_seen.end()) == rows_seen.end());
    CHECK(std::adjacent_find(cols_seen.begin(), cols_seen.end()) == cols_seen.end());
    const float greedy = total(psi, matchGreedy(psi, per_joint, min_potential));
    CHECK(greedy <= best + 1e-4f);
    greedy_worse += greedy < best - 1e-4f;
  }
  CHECK(greedy_worse > 0);  // the cases do tell the two apart
}
