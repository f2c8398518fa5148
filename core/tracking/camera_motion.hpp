// Global camera motion between two frames as a 2x3 similarity transform (rotation, uniform scale,
// translation), previous -> current frame pixels. Coasting tracks are carried along with it, so a
// camera pan does not leave their predictions behind.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/types.hpp"

namespace jointflow {

/// From the two grey frames: sparse corners tracked with pyramidal Lucas-Kanade, then a robust
/// (RANSAC) fit. Identity when too few points track.
cv::Matx23f cameraMotionFromImages(const cv::Mat& previous_grey, const cv::Mat& grey);

/// From the keypoints of the persons matched between the two frames (previous -> current), by a
/// robust fit; identity with fewer than `min_persons` persons, since the motion of one or two
/// persons cannot be told from the camera's.
cv::Matx23f cameraMotionFromPoses(const std::vector<std::pair<Pose, Pose>>& matched,
                                  float joint_threshold, int min_persons = 3);

cv::Point2f applyMotion(const cv::Matx23f& m, cv::Point2f p);

/// Moves every keypoint of a pose by m, then by shift; the box follows.
Pose movePose(const Pose& pose, const cv::Matx23f& m, cv::Point2f shift);

/// Mean of to - m(from) over the keypoints with score > 0 in both poses ((0,0) when none): the
/// motion of a person with the camera motion m removed, unbiased by joints missing in one pose.
cv::Point2f meanMotion(const Pose& from, const Pose& to, const cv::Matx23f& m);

}  // namespace jointflow
