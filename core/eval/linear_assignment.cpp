#include "linear_assignment.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace jointflow::eval
