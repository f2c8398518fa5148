// The one motion model of a track: a constant-velocity Kalman filter (cv::KalmanFilter) on the
// person's centre, in pixels of the current frame and seconds of stream time, with the pose
// carried rigidly along. It predicts a track's pose while the track is matched, while it is lost
// and on the frames the networks skip (inference-interval), and it follows the camera: a camera
// motion moves the state, so the velocity holds the person's own motion only.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include "jointflow/types.hpp"

namespace jointflow {

/// The centre a motion model follows: the middle of the box of the scored keypoints, or of the
/// pose's box where no keypoint is scored. The position gates measure poses by it too, so that
/// a pose and a track's prediction are compared centre to centre.
cv::Point2f poseCentre(const Pose& p);

class MotionModel {
 public:
  /// Starts at a detection with zero velocity (its uncertainty large).
  explicit MotionModel(const Pose& detection);

  /// Moves the state by a camera motion (2x3, previous -> current frame pixels): the pose, the
  /// centre, and the velocity by the motion's linear part.
  void applyCamera(const cv::Matx23f& camera);

  /// Advances the state by dt seconds (dt >= 0).
  void predict(double dt);

  /// Corrects the state with a detection made at the predicted time. The measured centre is the
  /// predicted one plus the mean displacement of the joints seen in both poses, so joints that
  /// appear or vanish do not move the centre. After frames without a correction (a lost track
  /// taken back) the velocity becomes the mean motion over the gap instead (reacquire).
  void correct(const Pose& detection);

  /// The last detection moved with the state to the predicted centre.
  Pose pose() const;
  /// The pose dt seconds after the current state, the state left as it is (for the frames the
  /// networks skip).
  Pose poseAfter(double dt) const;
  cv::Point2f centre() const;
  cv::Point2f velocity() const;  ///< px per second, camera motion removed
  /// Where the person was last seen: the filtered centre at the last detection, moved with the
  /// camera since (equal to centre() on a frame with a match).
  cv::Point2f lastSeenCentre() const { return anchor_centre_; }
  /// Standard deviation of the predicted centre, px (sqrt of the mean positional variance).
  float positionSigma() const;
  float height() const { return height_; }  ///< the person's height, px (noise scale)

 private:
  void reacquire(cv::Point2f z, float measurement_sigma);

  cv::KalmanFilter kf_;
  Pose anchor_;                ///< the last detection, in current-frame pixels
  cv::Point2f anchor_centre_;  ///< the filtered centre when anchor_ was detected
  float height_ = 1.f;
  int predictions_ = 0;           ///< since the last correction (1 on a frame with a match)
  double coasted_seconds_ = 0.0;  ///< stream time since the last correction
};

}  // namespace jointflow
