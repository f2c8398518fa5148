// Optimal assignment for the MOT accumulator, as py-motmetrics solves it with
// scipy.optimize.linear_sum_assignment (through its add_expensive_edges).
#pragma once

#include <vector>

namespace jointflow::eval {

/// motmetrics' linear_sum_assignment on a rows x cols row-major distance matrix whose NaN or
/// infinite entries cannot pair: the most pairs, and among those the least total distance.
/// Returns, for each row, its column or -1.
std::vector<int> motAssignment(const std::vector<double>& distances, int rows, int cols);

}  // namespace jointflow::eval
