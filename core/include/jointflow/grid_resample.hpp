// Multi-scale inference: bringing a network output computed on one grid onto another.
//
// Each scale's output grid maps to the frame by its own GridTransform. A map is moved onto the
// reference grid by sampling it (bilinearly) at the position of every reference cell in the
// source grid; displacement fields (offsets, regressions, PoseNet's displacements, box sizes)
// are also rescaled into reference cells, since a displacement of d source cells spans
// d * from.scale / to.scale reference cells. Unit-vector fields (Part Affinity Fields) keep their
// direction under the uniform resize and are not rescaled.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/spatial_model.hpp"

namespace jointflow {

/// A displacement field stored in two channels of a tensor (either may be -1 when absent).
struct DisplacementChannels {
  int x_channel = -1;
  int y_channel = -1;
};

/// Resamples a CV_32F {1, C, H, W} tensor from the grid `from` onto the grid `to` of size
/// `to_size` (width = columns). Cells of `to` outside the source grid take the nearest border
/// value. Channels listed in `displacements` are rescaled as described above.
cv::Mat resampleToGrid(const cv::Mat& tensor, const GridTransform& from, const GridTransform& to,
                       cv::Size to_size, const std::vector<DisplacementChannels>& displacements);

}  // namespace jointflow
