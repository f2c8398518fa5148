// Global camera motion between two frames as a 2x3 similarity transform (rotation, uniform scale,
// translation), previous -> current frame pixels. Every track is carried along with it before it
// is compared with the new poses, so a pan, a zoom or a shake does not leave the tracks behind.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/types.hpp"

namespace jointflow {

/// A grey frame as the search below uses it: shrunk to at most 400 pixels on the longer side
/// (its own copy). Made once per frame, so that it serves again as the next frame's previous one:
/// the shrinking was a quarter of the estimate's time.
struct MotionImage {
  cv::Mat small;  ///< CV_8U, owned
  cv::Size full;  ///< the frame's size
  bool empty() const { return small.empty(); }
};
MotionImage motionImage(const cv::Mat& grey);

/// From the two grey frames: sparse corners tracked with pyramidal Lucas-Kanade, then a robust
/// (RANSAC) fit. Corners inside `exclude` (the people, who move on their own) are left out.
/// Identity when too few points track.
cv::Matx23f cameraMotionFromImages(const MotionImage& previous, const MotionImage& current,
                                   const std::vector<Box>& exclude = {});
/// The same from the grey frames themselves.
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
