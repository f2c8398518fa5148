#include "linear_assignment.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "jointflow/matching.hpp"

namespace jointflow::eval {

std::vector<int> motAssignment(const std::vector<double>& distances, int rows, int cols) {
  std::vector<int> col_of_row(rows, -1);
  double largest = -1.0;
  for (double d : distances) {
    if (std::isfinite(d)) largest = std::max(largest, std::fabs(d));
  }
  if (rows == 0 || cols == 0 || largest < 0.0) return col_of_row;
  // motmetrics gives forbidden pairs the cost 2 r c + 1 (c = 1 + the largest |distance|,
  // r = min(rows, cols)), so that fewer forbidden pairs always win. The same objective on a
  // square matrix padded with free pairs: allowed pairs cost d - (2 r c + 1), all others 0.
  const double bonus = 2.0 * std::min(rows, cols) * (largest + 1.0) + 1.0;
  const int n = std::max(rows, cols);
  std::vector<double> cost(static_cast<std::size_t>(n) * n, 0.0);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const double d = distances[static_cast<std::size_t>(r) * cols + c];
      if (std::isfinite(d)) cost[static_cast<std::size_t>(r) * n + c] = d - bonus;
    }
  }
  const std::vector<int> assigned = minCostPerfectAssignment(cost, n);
  for (int r = 0; r < rows; ++r) {
    const int c = assigned[r];
    if (c < cols && std::isfinite(distances[static_cast<std::size_t>(r) * cols + c])) {
      col_of_row[r] = c;
    }
  }
  return col_of_row;
}

std::vector<int> maxScoreAssignment(const std::vector<double>& scores, int rows, int cols) {
  std::vector<int> col_of_row(rows, -1);
  if (rows == 0 || cols == 0) return col_of_row;
  // Padding to a square with zero scores keeps the optimum: a real pair never scores below 0.
  const int n = std::max(rows, cols);
  std::vector<double> cost(static_cast<std::size_t>(n) * n, 0.0);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      cost[static_cast<std::size_t>(r) * n + c] = -scores[static_cast<std::size_t>(r) * cols + c];
    }
  }
  const std::vector<int> assigned = minCostPerfectAssignment(cost, n);
  for (int r = 0; r < rows; ++r) {
    if (assigned[r] < cols) col_of_row[r] = assigned[r];
  }
  return col_of_row;
}

std::int64_t identityTruePositives(
    const std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t>& pair_frames) {
  // Weighted bipartite graph: objects x hypotheses, weight = frames in reach.
  std::map<std::int64_t, int> object_index, hypothesis_index;
  for (const auto& [pair, frames] : pair_frames) {
    object_index.emplace(pair.first, 0);
    hypothesis_index.emplace(pair.second, 0);
  }
  if (pair_frames.empty()) return 0;
  int next = 0;
  for (auto& entry : object_index) entry.second = next++;
  next = 0;
  for (auto& entry : hypothesis_index) entry.second = next++;
  // Make the rows the smaller side.
  const bool objects_are_rows = object_index.size() <= hypothesis_index.size();
  const int rows =
      static_cast<int>(objects_are_rows ? object_index.size() : hypothesis_index.size());
  std::vector<std::vector<std::pair<std::int64_t, int>>> edges(rows);  // (weight, column)
  for (const auto& [pair, frames] : pair_frames) {
    const int o = object_index.at(pair.first), h = hypothesis_index.at(pair.second);
    edges[objects_are_rows ? o : h].emplace_back(frames, objects_are_rows ? h : o);
  }
  // With r rows, a row never needs more than its r heaviest columns: were it paired with another,
  // one of those r would be free (the other r - 1 rows hold at most r - 1) and no lighter. The
  // union of these columns keeps the optimum and bounds the matrix by r^2 columns, however many
  // ids a broken tracker makes.
  std::set<int> kept_columns;
  for (auto& row : edges) {
    std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    if (static_cast<int>(row.size()) > rows) row.resize(rows);
    for (const auto& e : row) kept_columns.insert(e.second);
  }
  std::map<int, int> column_of;
  for (int c : kept_columns) column_of.emplace(c, static_cast<int>(column_of.size()));
  const int n = std::max(rows, static_cast<int>(column_of.size()));
  std::vector<double> cost(static_cast<std::size_t>(n) * n, 0.0);
  for (int r = 0; r < rows; ++r) {
    for (const auto& [weight, c] : edges[r]) {
      cost[static_cast<std::size_t>(r) * n + column_of.at(c)] = -static_cast<double>(weight);
    }
  }
  const std::vector<int> assigned = minCostPerfectAssignment(cost, n);
  std::int64_t covered = 0;
  for (int r = 0; r < rows; ++r) {
    covered += static_cast<std::int64_t>(-cost[static_cast<std::size_t>(r) * n + assigned[r]]);
  }
  return covered;
}

}  // namespace jointflow::eval
