// The paper's spatial decoder (Cao et al., "Realtime Multi-Person 2D Pose Estimation using Part
// Affinity Fields", CVPR 2017) for any model that outputs joint belief maps and Part Affinity
// Fields (PAFs).
//
// Tensor layout:
//   beliefs {1, J, H, W}: channel j = belief map of COCO joint j (J >= 17; channels beyond 17,
//           e.g. a background map, are ignored), values in [0, 1];
//   pafs    {1, 2L, H, W}: channels 2l and 2l+1 = x and y components of the unit-vector field of
//           limb l of the limb list, pointing from limb.first to limb.second.
// Decoding, on the grid (cells):
//   1. joint candidates: cells whose belief is > nms_threshold (tau_NMS) and >= their 8
//      neighbours (3x3 non-maximum suppression); the position is refined to sub-cell accuracy by
//      a parabola through the log-beliefs of the peak and its two neighbours per axis (exact for
//      a Gaussian peak);
//   2. limb candidates: for every pair of candidates of a limb's two joints, the PAF line
//      integral E = mean over `line_samples` points p(u) of <L(p(u)), d/|d|> (Cao et al. Eq. 10,
//      sampled as in their implementation), plus the distance prior min(0, 0.5 H / |d| - 1);
//      kept when E > 0 and more than 80 % of the samples exceed paf_threshold;
//   3. greedy bipartite matching per limb: candidates sorted by E, each joint used at most once
//      (Cao et al. Sec. 2.4);
//   4. person assembly over the limbs in list order: a connection extends the person holding one
//      of its joints, merges two persons that share no joint type, or starts a new person;
//      persons with fewer than min_parts joints are dropped.
// The limb list may contain cycles (the COCO skeleton does); redundant limbs only confirm.
#pragma once

#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/types.hpp"

namespace jointflow {

struct OpenPoseDecodeOptions {
  std::vector<std::pair<int, int>> limbs = kCocoSkeleton;  ///< PAF channel order
  float nms_threshold = 0.2f;                              ///< tau_NMS (paper default)
  float paf_threshold = 0.05f;  ///< per-sample PAF score (Cao et al.'s implementation)
  int line_samples = 10;
  int min_parts = 3;
  int max_persons = 100;  ///< as SpatialOptions::max_persons
};

/// Decoded poses, keypoints in grid cells, highest person score first. Person score = mean of
/// the belief peaks of its joints; box = tight box of the keypoints. Throws jointflow::Error when
/// the tensors' shapes disagree with each other or with the limb list.
Poses decodeOpenPose(const cv::Mat& beliefs, const cv::Mat& pafs,
                     const OpenPoseDecodeOptions& options);

}  // namespace jointflow
