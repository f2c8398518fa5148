// MotionModel (motion_model.hpp).
#include "motion_model.hpp"

#include <algorithm>
#include <cmath>

#include "camera_motion.hpp"

namespace jointflow {
namespace {

// Noise scales relative to the person's height h, per second of stream time: positions are
// measured to about 5 % of h, a walking person changes speed by about half its height per second.
// (ByteTrack scales its Kalman noise with the box height the same way.)
constexpr float kMeasurementSigma = 0.05f;  // x h
// People stop, start and turn: a walker at 1.4 m/s stops within about half a second, some 1.6
// of its heights per s^2, so the process noise (white acceleration) allows 2 heights per s^2.
constexpr float kAccelerationSigma = 2.0f;  // x h / s^2
constexpr float kInitialSpeedSigma = 1.0f;  // x h / s, a new track's velocity uncertainty

float heightOf(const Pose& p) {
  const Box b = p.keypointBox(1e-12f);
  return std::max({b.h, p.box.h, 1.f});
}

}  // namespace

cv::Point2f poseCentre(const Pose& p) {
  const Box b = p.keypointBox(1e-12f);
  if (b.w > 0.f || b.h > 0.f) return {b.x + b.w / 2, b.y + b.h / 2};
  return {p.box.x + p.box.w / 2, p.box.y + p.box.h / 2};
}

MotionModel::MotionModel(const Pose& detection)
    : kf_(4, 2, 0, CV_32F), anchor_(detection), height_(heightOf(detection)) {
  const cv::Point2f c = poseCentre(detection);
  anchor_centre_ = c;
  kf_.statePost = (cv::Mat_<float>(4, 1) << c.x, c.y, 0.f, 0.f);
  const float pos = kMeasurementSigma * height_, vel = kInitialSpeedSigma * height_;
  kf_.errorCovPost =
      cv::Mat::diag((cv::Mat_<float>(4, 1) << pos * pos, pos * pos, vel * vel, vel * vel));
  kf_.measurementMatrix = (cv::Mat_<float>(2, 4) << 1, 0, 0, 0, 0, 1, 0, 0);
  kf_.transitionMatrix = cv::Mat::eye(4, 4, CV_32F);
  kf_.statePre = kf_.statePost.clone();
  kf_.errorCovPre = kf_.errorCovPost.clone();
}

void MotionModel::applyCamera(const cv::Matx23f& m) {
  anchor_ = movePose(anchor_, m, {0, 0});
  anchor_centre_ = applyMotion(m, anchor_centre_);
  cv::Mat& x = kf_.statePost;
  const cv::Point2f c = applyMotion(m, {x.at<float>(0), x.at<float>(1)});
  const float vx = x.at<float>(2), vy = x.at<float>(3);
  x.at<float>(0) = c.x;
  x.at<float>(1) = c.y;
  x.at<float>(2) = m(0, 0) * vx + m(0, 1) * vy;
  x.at<float>(3) = m(1, 0) * vx + m(1, 1) * vy;
  // A zoom scales the person and the spread of the state alike.
  const float scale2 = m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0);
  if (scale2 > 0.f) {
    kf_.errorCovPost *= scale2;
    height_ *= std::sqrt(scale2);
  }
}

void MotionModel::predict(double dt_seconds) {
  const float dt = static_cast<float>(std::max(0.0, dt_seconds));
  kf_.transitionMatrix =
      (cv::Mat_<float>(4, 4) << 1, 0, dt, 0, 0, 1, 0, dt, 0, 0, 1, 0, 0, 0, 0, 1);
  // Discrete white-noise acceleration model.
  const float q = kAccelerationSigma * height_;
  const float q2 = q * q, dt2 = dt * dt, dt3 = dt2 * dt, dt4 = dt3 * dt;
  kf_.processNoiseCov = (cv::Mat_<float>(4, 4) << dt4 / 4 * q2, 0, dt3 / 2 * q2, 0,  //
                         0, dt4 / 4 * q2, 0, dt3 / 2 * q2,                           //
                         dt3 / 2 * q2, 0, dt2 * q2, 0,                               //
                         0, dt3 / 2 * q2, 0, dt2 * q2);
  kf_.predict();
  ++predictions_;
  coasted_seconds_ += dt;
  // Without a correction the prediction is the new state (a lost track keeps moving).
  kf_.statePre.copyTo(kf_.statePost);
  kf_.errorCovPre.copyTo(kf_.errorCovPost);
}

void MotionModel::correct(const Pose& detection) {
  const Pose predicted = pose();
  const cv::Point2f z = centre() + meanMotion(predicted, detection, cv::Matx23f(1, 0, 0, 0, 1, 0));
  height_ = heightOf(detection);
  const float r = kMeasurementSigma * height_;
  kf_.measurementNoiseCov = cv::Mat::eye(2, 2, CV_32F) * (r * r);
  if (predictions_ >= 2 && coasted_seconds_ > 0.0) {
    reacquire(z, r);
  } else {
    kf_.statePre = kf_.statePost.clone();
    kf_.errorCovPre = kf_.errorCovPost.clone();
    kf_.correct((cv::Mat_<float>(2, 1) << z.x, z.y));
  }
  predictions_ = 0;
  coasted_seconds_ = 0.0;
  anchor_ = detection;
  anchor_centre_ = centre();
}

// Observation-centric re-update (OC-SORT, Cao et al., CVPR 2023): after frames without a match,
// a Kalman correction would put the whole error of the coasted prediction into the velocity (its
// gain is about 2 / T after T seconds): on the identity benchmark's occluder, tracks of people
// on paddle boards, who barely move, came out of their first match after a loss of about a
// second with 100-300 px/s, their next prediction left the person, and the person's next view
// started a new track beside it. The velocity is instead the mean motion over the gap, from the
// last observation (moved with the camera) to this one, and the state starts again from the
// measurement. Identity benchmark, oks: zoom 146 -> 119 and occluder 129 -> 119 joint id
// switches, the other cases unchanged (docs/identity.md).
void MotionModel::reacquire(cv::Point2f z, float measurement_sigma) {
  const auto gap = static_cast<float>(coasted_seconds_);
  const cv::Point2f v = (z - anchor_centre_) / gap;
  kf_.statePost = (cv::Mat_<float>(4, 1) << z.x, z.y, v.x, v.y);
  // The mean velocity's error: two positions' over the gap, plus how far the person's speed may
  // have changed within it.
  const float r2 = measurement_sigma * measurement_sigma;
  const float q = kAccelerationSigma * height_ * gap / 2.f;
  const float v2 = 2.f * r2 / (gap * gap) + q * q;
  kf_.errorCovPost = cv::Mat::diag((cv::Mat_<float>(4, 1) << r2, r2, v2, v2));
  kf_.statePre = kf_.statePost.clone();
  kf_.errorCovPre = kf_.errorCovPost.clone();
}

Pose MotionModel::pose() const {
  return movePose(anchor_, cv::Matx23f(1, 0, 0, 0, 1, 0), centre() - anchor_centre_);
}

Pose MotionModel::poseAfter(double dt) const {
  return movePose(anchor_, cv::Matx23f(1, 0, 0, 0, 1, 0),
                  centre() + velocity() * static_cast<float>(std::max(0.0, dt)) - anchor_centre_);
}

cv::Point2f MotionModel::centre() const {
  return {kf_.statePost.at<float>(0), kf_.statePost.at<float>(1)};
}

cv::Point2f MotionModel::velocity() const {
  return {kf_.statePost.at<float>(2), kf_.statePost.at<float>(3)};
}

float MotionModel::positionSigma() const {
  return std::sqrt(0.5f * (kf_.errorCovPost.at<float>(0, 0) + kf_.errorCovPost.at<float>(1, 1)));
}

}  // namespace jointflow
