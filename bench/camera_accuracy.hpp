// The camera motion estimate (CameraMotionTracker, core/tracking/camera_motion.hpp) against the
// exact camera motion of a benchmark variant: the error of the estimated frame-to-frame transform
// in pixels, and its cost. The id-switch figures of the identity benchmark respond to small
// changes of the estimate in both directions (one more or one fewer switch on a frame where it
// erred); this measures the estimate itself, so that a faster one can be judged on what it does.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/posetrack.hpp"
#include "variants.hpp"

namespace jointflow::bench {

struct CameraAccuracy {
  /// Per frame after the first: mean distance, over a 5 x 5 grid of points spanning the frame,
  /// between where the estimate and where the variant's warps move each point, px.
  std::vector<double> error_px;
  /// CPU ms of CameraMotionTracker::update per frame, one thread (cv::setNumThreads(1)).
  std::vector<double> update_ms;
};

/// Renders the variant's frames from `images` (its source frames), grey, and runs the tracker on
/// them with the ground-truth people of this and the previous frame left out, as the associator
/// leaves out detections and tracks. The truth is W_k W_{k-1}^-1: the source camera stands still
/// (the still-s1 case shows the error where nothing moved but the people).
CameraAccuracy measureCameraEstimate(const std::vector<cv::Mat>& images,
                                     const posetrack::Sequence& ground_truth,
                                     const Variant& variant);

}  // namespace jointflow::bench
