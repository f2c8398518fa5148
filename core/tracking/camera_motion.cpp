#include "camera_motion.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "jointflow/image_shrink.hpp"

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
// pixel count. (The shrink is shrinkImage's: INTER_AREA by a fractional factor took 2.3 ms of one
// core for 768x576 -> 400x300. A whole factor instead, 960x540 -> 480x270, erred less on the
// camera estimate table of docs/identity.md, but on the tracking cases it cost id switches:
// oks still-s3 2 -> 28, shake 4 -> 18, zoom IDF1 77.5 -> 75.1; so the side stays 400.)
constexpr int kMotionSide = 400;
// (150 points instead: one thread's estimate 3.1 -> 2.3 ms a frame, but oks on the occluder case
// 36 -> 49 joint id switches, IDF1 89.1 -> 80.0, zoom 98 -> 106, shake 95th percentile error
// 9.4 -> 20.5 px. Not kept.)
constexpr int kMotionPoints = 300;
// Lucas-Kanade's window and pyramid (OpenCV's defaults). OpenCV builds fewer levels where the
// top one would be smaller than the window: a 400x225 frame gets 3 above it; a shaken camera
// jumps further than they follow (the phase correlation below). (An 11x11 window on every level
// cost a third of the time, 3.6 -> 1.4 ms of Lucas-Kanade per frame, and erred less on the camera
// estimate table, shake 95th percentile 12.4 -> 8.3 px; but on the tracking cases oks lost ids:
// dropped 38 -> 70, zoom 106 -> 136, occluder 52 -> 68 joint id switches, back under the same id
// 10 -> 8 of 10. So the full level keeps this window.)
const cv::Size kWindow(21, 21);
constexpr int kLevels = 3;
// Lucas-Kanade runs in two passes (trackAndFit): every point on the coarse levels 1 to kLevels
// with a small window, which finds where the points went to within a fraction of a pixel and
// which of them move with the camera; then kFinePoints of those again on the full level with
// kWindow, which makes the motion exact. On the full level a point costs 2.6 us against 0.6 us on
// a coarse one (one thread, 400x300), and a motion of four parameters needs no more points there.
// A still vtest.avi frame: 1.9 ms for one pass of all points on all levels, 0.72 ms for two; the
// motion differs from one pass's by 0.01 px (median over the frame; 0.05-0.1 px panned, zoomed or
// shaken), and a known zoom, turn and pan of a pattern is found to within 0.1 px by either
// (tests/tracking). The identity benchmark's ids are the same but on the knife-edge zoom case,
// whose id switches moved either way with the window (8-11) and the points (48-96): oks 88-114
// against 98 with one pass, tff 23-41 against 23 (docs/identity.md). 9 and 48 kept oks's figures
// closest.
const cv::Size kCoarseWindow(9, 9);
constexpr size_t kFinePoints = 48;
// Phase correlation for a jump Lucas-Kanade lost runs on a pyramid level no larger than this:
// a global shift needs little detail, and its cost grows with the pixels.
constexpr int kCoarseSide = 130;
// A refit from the phase correlation's shift is taken where it moves the frame's centre by no
// more than this from that shift, shrunk px (a coarse pixel is 2-4 shrunk px).
constexpr float kCoarseAgreement = 8.f;

double shrinkOf(cv::Size full) {
  return std::max(1.0, std::max(full.width, full.height) / static_cast<double>(kMotionSide));
}

/// The people's boxes in search-image pixels.
std::vector<cv::Rect> excludedRects(const std::vector<Box>& exclude, float sx, float sy) {
  std::vector<cv::Rect> out;
  for (const Box& b : exclude)
    out.emplace_back(cv::Point(static_cast<int>(b.x / sx), static_cast<int>(b.y / sy)),
                     cv::Size(static_cast<int>(b.w / sx) + 1, static_cast<int>(b.h / sy) + 1));
  return out;
}

/// Lucas-Kanade from the previous pyramid to this one, then the robust fit in frame pixels.
struct Fit {
  cv::Matx23f motion = kIdentity;
  std::vector<cv::Point2f> inliers;  ///< where the inlier points are now, shrunk px
  float scale = 1.f;
  /// At least 8 points agree, and the scale is one a camera makes in a frame.
  bool usable() const { return inliers.size() >= 8 && scale > 0.8f && scale < 1.25f; }
  /// Usable, and a quarter of the `points` tracked agree.
  bool plausible(size_t points) const { return usable() && inliers.size() * 4 >= points; }
};

/// Lucas-Kanade of `from` (shrunk px) on the pyramids from `first_level` up to `last_level`, with
/// `window`; `to` holds where each search starts (level-0 px) and gets the result; `ok` its flags.
/// OpenCV's pyramids interleave each level with its derivatives, so level l starts at 2 l.
void lucasKanade(const std::vector<cv::Mat>& previous, const std::vector<cv::Mat>& current,
                 int first_level, int last_level, cv::Size window,
                 const std::vector<cv::Point2f>& from, std::vector<cv::Point2f>& to,
                 std::vector<unsigned char>& ok, bool guess) {
  const float scale = 1.f / static_cast<float>(1 << first_level);
  const auto level = static_cast<std::ptrdiff_t>(2 * first_level);
  const std::vector<cv::Mat> a(previous.begin() + level, previous.end());
  const std::vector<cv::Mat> b(current.begin() + level, current.end());
  std::vector<cv::Point2f> f(from.size());
  for (size_t i = 0; i < from.size(); ++i) {
    f[i] = from[i] * scale;
    to[i] *= scale;
  }
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(
      a, b, f, to, ok, error, window, last_level - first_level,
      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 30, 0.01),
      guess ? cv::OPTFLOW_USE_INITIAL_FLOW : 0);
  for (cv::Point2f& p : to) p /= scale;
}

/// `shift` (shrunk px) is where Lucas-Kanade starts looking: every point moved by it. `shrink`:
/// frame px per shrunk px in x and y. Two passes (see kCoarseWindow): all points on the coarse
/// levels and a first fit, which picks the background; then kFinePoints of its inliers, spread
/// over the list, on the full level, and the motion fitted to them.
Fit trackAndFit(const std::vector<cv::Mat>& previous, const std::vector<cv::Mat>& current,
                const std::vector<cv::Point2f>& from, cv::Point2f shrink, cv::Point2f shift) {
  auto toFrame = [&](cv::Point2f p) {
    return cv::Point2f((p.x + 0.5f) * shrink.x - 0.5f, (p.y + 0.5f) * shrink.y - 0.5f);
  };
  const bool guess = shift != cv::Point2f(0.f, 0.f);
  // A frame too small for a level above the full one gets one pass on the full level.
  const int top = static_cast<int>(std::min(previous.size(), current.size()) / 2) - 1;
  const bool two_passes = top >= 1;
  std::vector<cv::Point2f> tracked(from.size());
  for (size_t i = 0; i < from.size(); ++i) tracked[i] = from[i] + shift;
  std::vector<unsigned char> ok;
  if (two_passes)
    lucasKanade(previous, current, 1, top, kCoarseWindow, from, tracked, ok, guess);
  else
    lucasKanade(previous, current, 0, top, kWindow, from, tracked, ok, guess);
  const cv::Mat& image = current[0];
  const cv::Rect inside(0, 0, image.cols, image.rows);
  std::vector<size_t> kept;  // the points Lucas-Kanade found
  std::vector<cv::Point2f> frame_from, frame_to;
  for (size_t i = 0; i < from.size(); ++i) {
    if (!ok[i]) continue;
    kept.push_back(i);
    frame_from.push_back(toFrame(from[i]));
    frame_to.push_back(toFrame(tracked[i]));
  }
  Fit fit;
  std::vector<unsigned char> flags;
  fit.motion = robustSimilarity(frame_from, frame_to, 2.0, &flags);
  std::vector<size_t> background;  // indices into `from` of the inliers
  for (size_t k = 0; k < flags.size(); ++k)
    if (flags[k]) background.push_back(kept[k]);
  if (two_passes && !background.empty()) {
    const size_t n = std::min(kFinePoints, background.size());
    std::vector<cv::Point2f> fine_from(n), fine_to(n);
    std::vector<size_t> fine(n);
    for (size_t k = 0; k < n; ++k) {
      fine[k] = background[k * background.size() / n];
      fine_from[k] = from[fine[k]];
      fine_to[k] = tracked[fine[k]];
    }
    std::vector<unsigned char> fine_ok;
    lucasKanade(previous, current, 0, 0, kWindow, fine_from, fine_to, fine_ok, true);
    std::vector<cv::Point2f> exact_from, exact_to;
    for (size_t k = 0; k < n; ++k) {
      if (!fine_ok[k]) continue;
      tracked[fine[k]] = fine_to[k];
      exact_from.push_back(toFrame(fine_from[k]));
      exact_to.push_back(toFrame(fine_to[k]));
    }
    // Where too few points follow on the full level, the coarse fit stands.
    if (exact_from.size() >= 8) fit.motion = robustSimilarity(exact_from, exact_to, 2.0);
  }
  fit.scale = std::sqrt(fit.motion(0, 0) * fit.motion(0, 0) + fit.motion(1, 0) * fit.motion(1, 0));
  for (size_t i : background)
    if (inside.contains(cv::Point(static_cast<int>(tracked[i].x), static_cast<int>(tracked[i].y))))
      fit.inliers.push_back(tracked[i]);
  return fit;
}

/// The global shift previous -> current in shrunk px, by phase correlation on the pyramids'
/// coarsest level of at most kCoarseSide px (a Hann window keeps the frame's edges out).
cv::Point2f coarseShift(const std::vector<cv::Mat>& previous, const std::vector<cv::Mat>& current) {
  // buildOpticalFlowPyramid interleaves each level with its derivatives: images at 0, 2, 4, ...
  size_t level = 0;
  while (level + 2 < previous.size() && level + 2 < current.size() &&
         std::max(previous[level].cols, previous[level].rows) > kCoarseSide)
    level += 2;
  cv::Mat a, b;
  previous[level].convertTo(a, CV_32F);
  current[level].convertTo(b, CV_32F);
  if (a.size() != b.size()) return {0.f, 0.f};
  cv::Mat window;
  cv::createHanningWindow(window, a.size(), CV_32F);
  const cv::Point2d d = cv::phaseCorrelate(a, b, window);
  const float factor = static_cast<float>(1 << (level / 2));
  return {static_cast<float>(d.x) * factor, static_cast<float>(d.y) * factor};
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
  cv::buildOpticalFlowPyramid(shrinkToSide(grey, kMotionSide), pyramid, kWindow, kLevels);
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
    const double min_distance = std::max(1.0, 8.0 / shrinkOf(full_));  // 8 frame px
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
  if (from.size() < 8) {
    pyramid_ = std::move(pyramid);
    return kIdentity;
  }
  const cv::Point2f shrink(sx, sy);
  Fit fit = trackAndFit(pyramid_, pyramid, from, shrink, {0.f, 0.f});
  if (!fit.plausible(from.size())) {
    // Lucas-Kanade lost most points: a jump larger than its pyramid follows (a shaken camera
    // moves 100 px and more between two frames). Again from the global shift that phase
    // correlation finds on a coarse level; where too few points follow even from there, the
    // shift alone is the motion. Identity benchmark, shake (docs/identity.md, the camera motion
    // estimate): error 95th percentile 823 -> 9.9 px, worst frame 7869 -> 21.7 px.
    const cv::Point2f shift = coarseShift(pyramid_, pyramid);
    Fit again = trackAndFit(pyramid_, pyramid, from, shrink, shift);
    const cv::Point2f frame_shift(shift.x * sx, shift.y * sy);
    const cv::Point2f centre(full_.width / 2.f, full_.height / 2.f);
    const cv::Point2f moved = applyMotion(again.motion, centre) - centre;
    const bool agrees = cv::norm(moved - frame_shift) < kCoarseAgreement * sx;
    if (again.usable() && agrees) {
      fit = std::move(again);
    } else {
      fit = Fit{};
      fit.motion = cv::Matx23f(1, 0, frame_shift.x, 0, 1, frame_shift.y);
    }
  }
  // The points that moved with the camera are background: they go on into the next frame.
  points_ = std::move(fit.inliers);
  pyramid_ = std::move(pyramid);
  return fit.motion;
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
