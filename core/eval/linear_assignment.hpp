// Optimal assignment for the MOT accumulator, as py-motmetrics solves it with
// scipy.optimize.linear_sum_assignment (through its add_expensive_edges).
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace jointflow::eval {

/// motmetrics' linear_sum_assignment on a rows x cols row-major distance matrix whose NaN or
/// infinite entries cannot pair: the most pairs, and among those the least total distance.
/// Returns, for each row, its column or -1.
std::vector<int> motAssignment(const std::vector<double>& distances, int rows, int cols);

/// py-motmetrics' id_global_assignment, reduced to what it decides: the most frames covered by
/// pairing each object id with at most one hypothesis id, given the frames each (object,
/// hypothesis) pair was within the threshold. (motmetrics minimises IDFP + IDFN over an (objects
/// + hypotheses)^2 matrix; that sum is all appearances minus 2 x the covered frames, so both
/// optima agree.) Returns IDTP.
std::int64_t identityTruePositives(
    const std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t>& pair_frames);

/// scipy's linear_sum_assignment(-scores) on a rows x cols row-major matrix of scores >= 0, as
/// TrackEval calls it: min(rows, cols) pairs of the largest total score. Returns, for each row,
/// its column or -1 (rows left over when rows > cols). Pairs of score 0 may be among them; the
/// callers keep only pairs above their threshold, as TrackEval does.
std::vector<int> maxScoreAssignment(const std::vector<double>& scores, int rows, int cols);

}  // namespace jointflow::eval
