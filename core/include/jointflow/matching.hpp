// Bipartite matching of previous poses (rows) to current poses (columns) on a potential matrix,
// paper Eq. 1: maximise the sum of Psi over the chosen pairs, each row and each column used at
// most once. A pair is eligible only when its Psi > 0 and its per-joint potential is >=
// min_potential; rows and columns left over start or end tracks.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/setting_enums.hpp"

namespace jointflow {

struct Match {
  int row = -1;  ///< previous pose / track
  int col = -1;  ///< current pose
};

/// The paper's greedy solution (Sec. 4.2 "Inference"): pairs in decreasing Psi, taken when both
/// ends are still free. Ties are broken by row then column, so the result is deterministic.
std::vector<Match> matchGreedy(const cv::Mat& psi, const cv::Mat& per_joint, float min_potential);

/// The optimal solution of Eq. 1 (maximum-weight bipartite matching by the Hungarian method).
std::vector<Match> matchOptimal(const cv::Mat& psi, const cv::Mat& per_joint, float min_potential);

/// Minimum-cost perfect assignment of an n x n row-major cost matrix (all entries finite):
/// returns the column of each row. The solver behind matchOptimal, also used by the evaluation.
std::vector<int> minCostPerfectAssignment(const std::vector<double>& cost, int n);

/// The chosen matcher's solution.
std::vector<Match> matchPoses(Matcher matcher, const cv::Mat& psi, const cv::Mat& per_joint,
                              float min_potential);

}  // namespace jointflow
