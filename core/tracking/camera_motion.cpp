#include "camera_motion.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace jointflow {
namespace {

const cv::Matx23f kIdentity(1, 0, 0, 0, 1, 0);

/// The similarity from -> to; `inliers` (when given) gets one flag per point.
cv::Matx23f robustSimilarity(const std::vector<cv::Point2f>& from,
                             const std::vector<cv::Point2f>& to, double threshold_px,
                             std::vector<unsigned char>* inliers = nullptr) {
  if (from.size() < 3) return kIdentity;
  std::vector<unsigned char> flags;
  const cv::Mat m = cv::estimateAffinePartial2D(from, to, flags, cv::RANSAC, threshold_px);
  if (m.empty()) return kIdentity;
  if (inliers) *inliers = std::move(flags);
  cv::Matx23f out;
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c) out(r, c) = static_cast<float>(m.at<double>(r, c));
  return out;
}

// Corners and their flow are found on frames of at most kMotionSide pixels on the longer side,
// then mapped back to frame pixels for the fit: a global fit over hundreds of points needs no more
// detail, and on full 768x576 frames the search cost 7.8 ms per frame against 1.8 ms at half
// size, a third of a 256x256 MoveNet pass (docs/benchmarks.md, issue 7); at 4K it grew with the
// pixel count.
constexpr int kMotionSide = 400;
constexpr int kMotionPoints = 300;
// Lucas-Kanade's window and pyramid (OpenCV's defaults): 3 levels above the frame follow shifts
// of about 100 px at kMotionSide (a shaken camera, issue 11).
const cv::Size kWindow(21, 21);
constexpr int kLevels = 3;

double shrinkOf(cv::Size full) {
  return std::max(1.0, std::max(full.width, full.height) / static_cast<double>(kMotionSide));
}

cv::Mat shrunk(const cv::Mat& grey) {
  const double shrink = shrinkOf(grey.size());
  if (shrink <= 1.0) return grey.clone();  // the caller's frame may be gone by the next frame
  cv::Mat small;
  const cv::Size size(std::max(1, static_cast<int>(std::lround(grey.cols / shrink))),
                      std::max(1, static_cast<int>(std::lround(grey.rows / shrink))));
  cv::resize(grey, small, size, 0, 0, cv::INTER_AREA);
  return small;
}

/// The people's boxes in search-image pixels.
std::vector<cv::Rect> excludedRects(const std::vector<Box>& exclude, float sx, float sy) {
  std::vector<cv::Rect> out;
  for (const Box& b : exclude)
    out.emplace_back(cv::Point(static_cast<int>(b.x / sx), static_cast<int>(b.y / sy)),
                     cv::Size(static_cast<int>(b.w / sx) + 1, static_cast<int>(b.h / sy) + 1));
  return out;
}

}  // namespace

void CameraMotionTracker::reset() {
  full_ = {};
  pyramid_.clear();
  points_.clear();
}

cv::Matx23f CameraMotionTracker::update(const cv::Mat& grey, const std::vector<Box>& exclude) {
  if (grey.empty()) {
    reset();
    return kIdentity;
  }
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(shrunk(grey), pyramid, kWindow, kLevels);
  if (grey.size() != full_ || pyramid_.empty()) {
    reset();
    full_ = grey.size();
    pyramid_ = std::move(pyramid);
    return kIdentity;
  }
  const cv::Mat& a = pyramid_[0];
  const float sx = static_cast<float>(full_.width) / a.cols;
  const float sy = static_cast<float>(full_.height) / a.rows;
  const std::vector<cv::Rect> people = excludedRects(exclude, sx, sy);
  auto excluded = [&](cv::Point2f p) {
    for (const cv::Rect& r : people)
      if (r.contains(cv::Point(static_cast<int>(p.x), static_cast<int>(p.y)))) return true;
    return false;
  };
  std::vector<cv::Point2f> from;
  for (const cv::Point2f& p : points_)
    if (!excluded(p)) from.push_back(p);
  if (static_cast<int>(from.size()) < kMotionPoints / 2) {
    // Where the people cover most of the frame, the background that is left decides, or nothing.
    const double min_distance = std::max(1.0, 8.0 / shrinkOf(full_));
    cv::Mat mask(a.size(), CV_8U, cv::Scalar(255));
    for (const cv::Rect& r : people) cv::rectangle(mask, r, cv::Scalar(0), cv::FILLED);
    for (const cv::Point2f& p : from)
      cv::circle(mask, p, static_cast<int>(std::ceil(min_distance)), cv::Scalar(0), cv::FILLED);
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(a, corners, kMotionPoints - static_cast<int>(from.size()), 0.01,
                            min_distance, mask);
    from.insert(from.end(), corners.begin(), corners.end());
    ++corner_searches_;
  }
  points_.clear();
  cv::Matx23f motion = kIdentity;
  if (from.size() >= 8) {
    std::vector<cv::Point2f> tracked;
    std::vector<unsigned char> ok;
    std::vector<float> error;
    cv::calcOpticalFlowPyrLK(pyramid_, pyramid, from, tracked, ok, error, kWindow, kLevels);
    auto toFrame = [&](cv::Point2f p) {
      return cv::Point2f((p.x + 0.5f) * sx - 0.5f, (p.y + 0.5f) * sy - 0.5f);
    };
    const cv::Rect inside(0, 0, a.cols, a.rows);
    std::vector<cv::Point2f> frame_from, frame_to, small_to;
    for (size_t i = 0; i < from.size(); ++i) {
      if (!ok[i]) continue;
      frame_from.push_back(toFrame(from[i]));
      frame_to.push_back(toFrame(tracked[i]));
      small_to.push_back(tracked[i]);
    }
    std::vector<unsigned char> inliers;
    motion = robustSimilarity(frame_from, frame_to, 2.0, &inliers);
    // The points that moved with the camera are background: they go on into the next frame.
    for (size_t i = 0; i < inliers.size(); ++i)
      if (inliers[i] && inside.contains(cv::Point(static_cast<int>(small_to[i].x),
                                                  static_cast<int>(small_to[i].y))))
        points_.push_back(small_to[i]);
  }
  pyramid_ = std::move(pyramid);
  return motion;
}

cv::Matx23f cameraMotionFromImages(const cv::Mat& previous_grey, const cv::Mat& grey,
                                   const std::vector<Box>& exclude) {
  if (previous_grey.empty() || grey.empty() || previous_grey.size() != grey.size())
    return kIdentity;
  CameraMotionTracker tracker;
  tracker.update(previous_grey);
  return tracker.update(grey, exclude);
}

cv::Matx23f cameraMotionFromFlow(const cv::Mat& flow, const std::vector<Box>& exclude) {
  if (flow.empty() || flow.type() != CV_32FC2) return kIdentity;
  // About 40 x 30 points: plenty for a global fit of four parameters.
  const int step = std::max(4, std::max(flow.cols, flow.rows) / 40);
  auto excluded = [&](int x, int y) {
    for (const Box& b : exclude)
      if (x >= b.x && x <= b.x + b.w && y >= b.y && y <= b.y + b.h) return true;
    return false;
  };
  std::vector<cv::Point2f> from, to;
  for (int y = step / 2; y < flow.rows; y += step)
    for (int x = step / 2; x < flow.cols; x += step) {
      if (excluded(x, y)) continue;
      const cv::Vec2f f = flow.at<cv::Vec2f>(y, x);
      from.emplace_back(static_cast<float>(x), static_cast<float>(y));
      to.emplace_back(x + f[0], y + f[1]);
    }
  return robustSimilarity(from, to, 2.0);
}

cv::Point2f applyMotion(const cv::Matx23f& m, cv::Point2f p) {
  return {m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2), m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2)};
}

Pose movePose(const Pose& pose, const cv::Matx23f& m, cv::Point2f shift) {
  Pose out = pose;
  for (Keypoint& k : out.keypoints) {
    const cv::Point2f p = applyMotion(m, {k.x, k.y}) + shift;
    k.x = p.x;
    k.y = p.y;
  }
  const cv::Point2f tl = applyMotion(m, {pose.box.x, pose.box.y}) + shift;
  const float scale = std::sqrt(m(0, 0) * m(0, 0) + m(1, 0) * m(1, 0));
  out.box = {tl.x, tl.y, pose.box.w * scale, pose.box.h * scale};
  return out;
}

cv::Point2f meanMotion(const Pose& from, const Pose& to, const cv::Matx23f& m) {
  cv::Point2f sum(0, 0);
  int n = 0;
  for (int j = 0; j < kNumJoints; ++j) {
    const Keypoint& a = from.keypoints[j];
    const Keypoint& b = to.keypoints[j];
    if (a.score <= 0.f || b.score <= 0.f) continue;
    sum += cv::Point2f(b.x, b.y) - applyMotion(m, {a.x, a.y});
    ++n;
  }
  return n ? sum / n : sum;
}

}  // namespace jointflow
