#include "camera_motion.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace jointflow {
namespace {

const cv::Matx23f kIdentity(1, 0, 0, 0, 1, 0);

cv::Matx23f robustSimilarity(const std::vector<cv::Point2f>& from,
                             const std::vector<cv::Point2f>& to, double threshold_px) {
  if (from.size() < 3) return kIdentity;
  const cv::Mat m = cv::estimateAffinePartial2D(from, to, cv::noArray(), cv::RANSAC, threshold_px);
  if (m.empty()) return kIdentity;
  cv::Matx23f out;
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c) out(r, c) = static_cast<float>(m.at<double>(r, c));
  return out;
}

}  // namespace

// Corners and their flow are found on frames of at most kMotionSide pixels on the longer side,
// then mapped back to frame pixels for the fit: a global fit over hundreds of points needs no more
// detail, and on full 768x576 frames the search cost 7.8 ms per frame against 1.8 ms at half
// size, a third of a 256x256 MoveNet pass (docs/benchmarks.md, issue 7); at 4K it grew with the
// pixel count.
constexpr int kMotionSide = 400;

MotionImage motionImage(const cv::Mat& grey) {
  MotionImage m;
  m.full = grey.size();
  if (grey.empty()) return m;
  const double shrink =
      std::max(1.0, std::max(m.full.width, m.full.height) / static_cast<double>(kMotionSide));
  if (shrink > 1.0) {
    const cv::Size small(std::max(1, static_cast<int>(std::lround(m.full.width / shrink))),
                         std::max(1, static_cast<int>(std::lround(m.full.height / shrink))));
    cv::resize(grey, m.small, small, 0, 0, cv::INTER_AREA);
  } else {
    m.small = grey.clone();  // the caller's frame may be gone when this serves as the previous
  }
  return m;
}

cv::Matx23f cameraMotionFromImages(const cv::Mat& previous_grey, const cv::Mat& grey,
                                   const std::vector<Box>& exclude) {
  if (previous_grey.empty() || grey.empty() || previous_grey.size() != grey.size())
    return kIdentity;
  return cameraMotionFromImages(motionImage(previous_grey), motionImage(grey), exclude);
}

cv::Matx23f cameraMotionFromImages(const MotionImage& previous, const MotionImage& current,
                                   const std::vector<Box>& exclude) {
  if (previous.empty() || current.empty() || previous.full != current.full ||
      previous.small.size() != current.small.size())
    return kIdentity;
  const cv::Mat& a = previous.small;
  const cv::Mat& b = current.small;
  const cv::Size full = current.full;
  const double shrink =
      std::max(1.0, std::max(full.width, full.height) / static_cast<double>(kMotionSide));
  const float sx = static_cast<float>(full.width) / a.cols;
  const float sy = static_cast<float>(full.height) / a.rows;
  auto toFrame = [&](cv::Point2f p) {
    return cv::Point2f((p.x + 0.5f) * sx - 0.5f, (p.y + 0.5f) * sy - 0.5f);
  };
  cv::Mat mask(a.size(), CV_8U, cv::Scalar(255));
  for (const Box& b : exclude)
    cv::rectangle(
        mask,
        cv::Rect(cv::Point(static_cast<int>(b.x / sx), static_cast<int>(b.y / sy)),
                 cv::Size(static_cast<int>(b.w / sx) + 1, static_cast<int>(b.h / sy) + 1)),
        cv::Scalar(0), cv::FILLED);
  // Where the people cover most of the frame, the background that is left decides, or nothing.
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(a, corners, 300, 0.01, std::max(1.0, 8.0 / shrink), mask);
  if (corners.size() < 8) return kIdentity;
  std::vector<cv::Point2f> tracked;
  std::vector<unsigned char> ok;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(a, b, corners, tracked, ok, error);
  std::vector<cv::Point2f> from, to;
  for (size_t i = 0; i < corners.size(); ++i) {
    if (!ok[i]) continue;
    from.push_back(toFrame(corners[i]));
    to.push_back(toFrame(tracked[i]));
  }
  return robustSimilarity(from, to, 2.0);
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
