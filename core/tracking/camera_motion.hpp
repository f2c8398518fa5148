// Global camera motion between two frames as a 2x3 similarity transform (rotation, uniform scale,
// translation), previous -> current frame pixels. Every track is carried along with it before it
// is compared with the new poses, so a pan, a zoom or a shake does not leave the tracks behind.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/types.hpp"

namespace jointflow {

/// The camera motion frame after frame, from the grey frames: background points tracked with
/// pyramidal Lucas-Kanade from the previous frame to this one, then a robust (RANSAC) fit.
/// Points inside `exclude` (the people, who move on their own) are left out. Each frame is
/// shrunk and its pyramid built once, and it serves again as the next frame's previous one; the
/// points that fit this frame's motion (background) are tracked on into the next frame, and
/// corners are searched again only where fewer than half of the 300 points are left: the corner
/// search and the second pyramid were half of the estimate's time (5.6 ms -> 3.0 ms per 768x576
/// vtest frame, build/bench/jointflow-bench; on the identity benchmark the oks figures moved
/// within a person switch either way, docs/identity.md). A jump that Lucas-Kanade loses is found
/// by phase correlation (see update()).
class CameraMotionTracker {
 public:
  /// The motion previous -> this frame (identity on the first frame, after a size change, or
  /// when too few points track). Where Lucas-Kanade loses most points, it tracks them again from
  /// the global shift phase correlation finds on a coarse level; where they still disagree, that
  /// shift alone is the motion.
  cv::Matx23f update(const cv::Mat& grey, const std::vector<Box>& exclude = {});
  void reset();
  /// Background points carried into the next frame (corners are searched anew when fewer than
  /// 150 of them are left outside the people).
  int carriedPoints() const { return static_cast<int>(points_.size()); }
  /// Corner searches so far (for tests and benchmarks).
  int cornerSearches() const { return corner_searches_; }

 private:
  cv::Size full_;                    ///< the frames' size
  std::vector<cv::Mat> pyramid_;     ///< of the previous frame, shrunk (owned copies)
  std::vector<cv::Point2f> points_;  ///< background points of the previous frame, shrunk px
  int corner_searches_ = 0;
};

/// The same for one pair of frames, with no state (corners searched on `previous_grey`).
cv::Matx23f cameraMotionFromImages(const cv::Mat& previous_grey, const cv::Mat& grey,
                                   const std::vector<Box>& exclude = {});

/// From a dense optical flow previous -> current (CV_32FC2, frame size), read on a regular grid
/// outside `exclude`, by the same robust fit: the similarity "flow" computes the flow anyway.
cv::Matx23f cameraMotionFromFlow(const cv::Mat& flow, const std::vector<Box>& exclude = {});

cv::Point2f applyMotion(const cv::Matx23f& m, cv::Point2f p);

/// Moves every keypoint of a pose by m, then by shift; the box follows.
Pose movePose(const Pose& pose, const cv::Matx23f& m, cv::Point2f shift);

/// Mean of to - m(from) over the keypoints with score > 0 in both poses ((0,0) when none): the
/// motion of a person with the camera motion m removed, unbiased by joints missing in one pose.
cv::Point2f meanMotion(const Pose& from, const Pose& to, const cv::Matx23f& m);

}  // namespace jointflow
