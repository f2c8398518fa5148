// PoseNet's standard multi-person decoding (Papandreou et al., "PersonLab", ECCV 2018; the
// algorithm of the TensorFlow.js posenet package), on its raw head tensors.
//
//   1. part candidates: every (cell, joint) whose score is >= part_threshold and is the maximum
//      of its joint's (2r+1)^2 neighbourhood (r = local_maximum_radius), in a max-priority queue;
//   2. pop the best candidate as a root; skip it when the same joint of an already decoded pose
//      lies within nms_radius pixels of its position (cell * stride + offset);
//   3. from the root, follow the 16 edges of the part tree, backwards (displacement_bwd) then
//      forwards (displacement_fwd): target = source + displacement at the source's nearest
//      cell, then refine_steps times: target = nearest cell * stride + offset there; its score
//      is the score at its nearest cell;
//   4. pose score = sum of the scores of the joints not within nms_radius of the same joint of
//      an earlier pose, / 17; stop after max_persons poses.
// Layouts (models/README.md): scores {1,17,H,W} (sigmoid of the heatmap logits); offsets
// {1,34,H,W}: 0-16 dy, 17-33 dx in input pixels; displacements {1,32,H,W}: 0-15 dy, 16-31 dx in
// input pixels, edge e of kPoseNetEdges. Cell (i, j) is input pixel stride * (i, j).
#pragma once

#include <array>
#include <utility>

#include <opencv2/core.hpp>

#include "jointflow/types.hpp"

namespace jointflow {

/// The part tree PoseNet's displacements follow: (parent, child), edge e = displacement e.
extern const std::array<std::pair<int, int>, 16> kPoseNetEdges;

struct PoseNetHeads {
  cv::Mat scores;            ///< {1, 17, H, W}, in [0, 1]
  cv::Mat offsets;           ///< {1, 34, H, W}
  cv::Mat displacement_fwd;  ///< {1, 32, H, W}
  cv::Mat displacement_bwd;  ///< {1, 32, H, W}
};

struct PoseNetDecodeOptions {
  float stride = 16.f;
  int max_persons = 100;  ///< as SpatialOptions::max_persons
  float part_threshold = 0.5f;  ///< tfjs posenet's scoreThreshold
  float nms_radius = 20.f;      ///< input pixels (tfjs: 20)
  int local_maximum_radius = 1;
  int refine_steps = 2;
};

/// Decoded poses, keypoints in grid cells (input pixels / stride), best pose first by decoding
/// order (the order of their root scores). Box = tight box of the keypoints.
/// Throws jointflow::Error when the tensors' shapes disagree.
Poses decodePoseNet(const PoseNetHeads& heads, const PoseNetDecodeOptions& options);

}  // namespace jointflow
