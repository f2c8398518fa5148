// Video variants with exact ground truth for the identity benchmark (bench/identity.cpp): output
// frames made from the frames of a real sequence by an affine warp (camera shake, pan, zoom, small
// people) and an opaque occluder bar, with every ground-truth point moved by the same warp, and
// timelines that say which source frame each output frame shows (strides, forward-backward play,
// reversed play, dropped frames).
//
// Coordinates follow OpenCV's convention, integer coordinates at pixel centres, which is the
// convention of cv::warpAffine and of the poses the spatial model reports; so a point p of a
// source frame shows at warp * p in the output frame (tests/bench checks it to < 0.5 px).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/posetrack.hpp"

namespace jointflow::bench {

/// How one output frame is made.
struct FrameRecipe {
  int source = 0;                      ///< index of the source frame
  cv::Matx23d warp{1, 0, 0, 0, 1, 0};  ///< source pixels -> output pixels
  /// An opaque full-height bar over the output pixel columns [occluder_begin, occluder_end);
  /// none when occluder_end <= occluder_begin.
  int occluder_begin = 0;
  int occluder_end = 0;
  /// Stream time of the output frame, seconds (what the tracker is given as the timestamp).
  double time = std::numeric_limits<double>::quiet_NaN();

  bool hasOccluder() const { return occluder_end > occluder_begin; }
};

/// One case of the benchmark: its output frames, all of one size.
struct Variant {
  std::string name;
  std::string description;  ///< how it is made, for the document
  cv::Size size;
  std::vector<FrameRecipe> frames;
};

/// Grey level of the occluder bar and of the border where a warp leaves no source pixel.
constexpr int kOccluderGrey = 128;
constexpr int kBorderGrey = 0;

// ---- Timelines: the source frame of each output frame ------------------------------------------

/// 0, s, 2s, ... < n.
std::vector<int> stridedTimeline(int n, int stride);
/// n - 1, ..., 0.
std::vector<int> reversedTimeline(int n);
/// Forward-backward play of n frames for `length` output frames: 0 .. n-1, n-2 .. 0, 1 .. n-1, ...
/// (no frame repeated at the turns).
std::vector<int> pingPongTimeline(int n, int length);
/// The positions of `timeline` that a leaky queue lets through when each frame but the first is
/// dropped with probability `drop`, seeded; in order.
std::vector<int> keptAfterDrops(int length, double drop, unsigned seed);
/// The positions of a timeline of `length` frames that an engine keeping up with one frame in
/// `stride` takes from behind a leaky queue: 0, then each gap stride + a jitter drawn uniformly
/// from [-jitter, jitter] (seeded), as the engine's time per frame varies; in order.
std::vector<int> keptBySlowEngine(int length, int stride, int jitter, unsigned seed);

// ---- Camera paths: one warp per output frame -------------------------------------------------

/// Scaling by `scale` about `centre`, which stays in place.
cv::Matx23d scaleAbout(cv::Point2d centre, double scale);
/// A shaking camera: each frame translated by `radius` px in a random direction (seeded), rounded
/// to whole pixels; the mean step between two frames is about 4 / pi x radius.
std::vector<cv::Matx23d> shakePath(int frames, double radius, unsigned seed);
/// A horizontal pan back and forth: a triangle wave of the given amplitude (px) at `speed` px per
/// frame, starting at 0.
std::vector<cv::Matx23d> panPath(int frames, double amplitude, double speed);
/// A zoom from scale 1 to `final_scale` about `centre`, the same factor each frame.
std::vector<cv::Matx23d> zoomPath(int frames, cv::Point2d centre, double final_scale);
/// Mean distance between consecutive frames of the image point that starts at `point`.
double meanStep(const std::vector<cv::Matx23d>& path, cv::Point2d point);

// ---- Rendering ---------------------------------------------------------------------------------

/// The output frame: `source` warped (bilinear; a warp that shrinks is anti-aliased first with a
/// Gaussian of sigma (1 / scale - 1) / 2, as scikit-image's rescale does), border kBorderGrey,
/// then the occluder bar in kOccluderGrey.
cv::Mat renderFrame(const cv::Mat& source, const FrameRecipe& recipe, cv::Size size);

/// True when the output point lies on a pixel the frame shows: inside it and not under the bar.
bool pointVisible(cv::Point2d output_point, const FrameRecipe& recipe, cv::Size size);

/// The ground truth of an output frame: every joint and head box moved by the warp; joints that
/// leave the frame or fall under the bar are removed (not visible, so not counted against a
/// detector), and so are people left without any joint. Ignore regions move too.
posetrack::Frame transformGroundTruth(const posetrack::Frame& source, const FrameRecipe& recipe,
                                      cv::Size size);

/// A maximal run of output frames in which a ground-truth person of the source is completely
/// hidden (every joint removed by transformGroundTruth), with visible frames before and after.
struct HiddenEpisode {
  std::int64_t track_id = 0;
  int first = 0;  ///< first hidden output frame
  int last = 0;   ///< last hidden output frame
  int frames() const { return last - first + 1; }
};
std::vector<HiddenEpisode> hiddenEpisodes(const std::vector<posetrack::Frame>& source_gt,
                                          const Variant& variant);

// ---- The Bonn cases ----------------------------------------------------------------------------

/// Settings of the cases made from one real sequence (defaults: the benchmark's).
struct VariantOptions {
  int still_strides_max = 3;  ///< still sequence at strides 1 .. this
  int moving_frames = 81;     ///< shake, pan, zoom: forward-backward play of this many frames
  double shake_radius = 80;   ///< px (mean step ~ 100 px)
  double pan_amplitude = 240, pan_speed = 20;  ///< px, px per frame
  double zoom_final = 1.8;
  int occluder_width = 300;   ///< px
  double occluder_speed = 5;  ///< px per frame, left to right, then back
  int occluder_lead = 15;     ///< frames the bar is out of view before, between and after
  int dropped_frames = 121;   ///< forward-backward play before the drops
  double drop_probability = 0.5;
  double small_scale = 1.0 / 3;  ///< small people: the frame shrunk into a canvas of its size
  /// A slow engine on a live camera: forward-backward play of slow_frames frames, of which the
  /// tracker gets about one in s (s in slow_strides), as a leaky queue gives an engine that keeps
  /// up with 1 / s of the frame rate (at 30 frames/s: 5 down to 1.9 frames/s); each gap is s +
  /// a jitter of up to slow_jitter frames (keptBySlowEngine). Why the jitter and the long play:
  /// with exact gaps, the 41-frame Bonn sequence's period (80 frames) made the tracker see the
  /// same few pairs again and again (1 in 10: frames 0, 10, .., 40 and back, 4 pairs; 1 in 16:
  /// 0, 16, 32, 2 pairs), so one pair decided a case; the figures moved by up to 20 MOTA points
  /// with the stride's divisibility. Jittered over 1921 frames, each case sees 120-320 frames
  /// of many pairs, and a seed changes a similarity's MOTA by about 1-2 points.
  int slow_frames = 1921;
  int slow_jitter = 1;
  std::vector<int> slow_strides = {6, 8, 10, 12, 16};
  /// Fast motion at the camera's rate: the frames of slow-sN for N in fast_strides, 1 / fps apart.
  std::vector<int> fast_strides = {6, 8, 12};
  /// Frame rate of the source sequence (the Bonn data does not record it): output frame k is at
  /// k / fps seconds, a dropped frame's time passes too.
  double fps = 30;
  unsigned seed = 2018;
};

/// The cases from a sequence of `frames` source frames of `size`: still-s1.., reversed, dropped,
/// slow-s6.., fast-x6.., shake, pan, zoom, occluder, small. Each variant's description says how it
/// was made. Frame k is at k / fps seconds of stream time (strides stand for faster motion), except
/// in "dropped" and "slow-s..", where the time of the dropped frames passes as it does behind a
/// leaky queue.
std::vector<Variant> bonnVariants(int frames, cv::Size size, const VariantOptions& options = {});

/// A variant's ground truth: transformGroundTruth of its source frame for every output frame.
posetrack::Sequence variantGroundTruth(const posetrack::Sequence& source, const Variant& variant);

}  // namespace jointflow::bench
