// Video variants with exact ground truth (see variants.hpp).
#include "variants.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <sstream>

#include <opencv2/imgproc.hpp>

#include "jointflow/error.hpp"
#include "text_format.hpp"

namespace jointflow::bench {

namespace pt = jointflow::posetrack;

std::vector<int> stridedTimeline(int n, int stride) {
  if (stride < 1) throw Error("stridedTimeline: stride " + std::to_string(stride) + " < 1");
  std::vector<int> out;
  for (int f = 0; f < n; f += stride) out.push_back(f);
  return out;
}

std::vector<int> reversedTimeline(int n) {
  std::vector<int> out;
  for (int f = n - 1; f >= 0; --f) out.push_back(f);
  return out;
}

std::vector<int> pingPongTimeline(int n, int length) {
  std::vector<int> out;
  if (n <= 0) return out;
  int f = 0, step = 1;
  for (int k = 0; k < length; ++k) {
    out.push_back(f);
    if (n == 1) continue;
    if (f + step < 0 || f + step >= n) step = -step;
    f += step;
  }
  return out;
}

std::vector<int> keptAfterDrops(int length, double drop, unsigned seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution dropped(drop);
  std::vector<int> kept;
  for (int k = 0; k < length; ++k) {
    const bool d = dropped(rng);  // drawn for every frame, so the pattern does not shift with k
    if (k == 0 || !d) kept.push_back(k);
  }
  return kept;
}

std::vector<int> keptBySlowEngine(int length, int stride, int jitter, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> extra(-jitter, jitter);
  std::vector<int> kept;
  for (int k = 0; k < length; k += std::max(1, stride + extra(rng))) kept.push_back(k);
  return kept;
}

cv::Matx23d scaleAbout(cv::Point2d centre, double scale) {
  return {scale, 0, centre.x * (1 - scale), 0, scale, centre.y * (1 - scale)};
}

std::vector<cv::Matx23d> shakePath(int frames, double radius, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * CV_PI);
  std::vector<cv::Matx23d> path;
  for (int f = 0; f < frames; ++f) {
    const double a = angle(rng);
    // Whole pixels: the output is then an exact copy of the source, shifted.
    path.push_back(
        {1, 0, std::round(radius * std::cos(a)), 0, 1, std::round(radius * std::sin(a))});
  }
  return path;
}

std::vector<cv::Matx23d> panPath(int frames, double amplitude, double speed) {
  std::vector<cv::Matx23d> path;
  double x = 0, direction = 1;
  for (int f = 0; f < frames; ++f) {
    path.push_back({1, 0, x, 0, 1, 0});
    if (std::fabs(x + direction * speed) > amplitude) direction = -direction;
    x += direction * speed;
  }
  return path;
}

std::vector<cv::Matx23d> zoomPath(int frames, cv::Point2d centre, double final_scale) {
  std::vector<cv::Matx23d> path;
  for (int f = 0; f < frames; ++f) {
    const double t = frames > 1 ? static_cast<double>(f) / (frames - 1) : 0.0;
    path.push_back(scaleAbout(centre, std::pow(final_scale, t)));
  }
  return path;
}

namespace {

cv::Point2d apply(const cv::Matx23d& m, cv::Point2d p) {
  return {m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2), m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2)};
}

/// The smaller singular value's stand-in for the warps used here (no shear): the smaller axis
/// scale.
double minScale(const cv::Matx23d& m) {
  return std::min(std::hypot(m(0, 0), m(1, 0)), std::hypot(m(0, 1), m(1, 1)));
}

}  // namespace

double meanStep(const std::vector<cv::Matx23d>& path, cv::Point2d point) {
  if (path.size() < 2) return 0.0;
  double sum = 0.0;
  for (size_t f = 1; f < path.size(); ++f) {
    const cv::Point2d d = apply(path[f], point) - apply(path[f - 1], point);
    sum += std::hypot(d.x, d.y);
  }
  return sum / static_cast<double>(path.size() - 1);
}

cv::Mat renderFrame(const cv::Mat& source, const FrameRecipe& recipe, cv::Size size) {
  if (source.empty()) throw Error("renderFrame: empty source frame");
  cv::Mat src = source;
  const double scale = minScale(recipe.warp);
  if (scale < 1.0) {
    // A Gaussian is symmetric: it blurs, it does not move anything.
    const double sigma = (1.0 / scale - 1.0) / 2.0;
    cv::GaussianBlur(source, src, cv::Size(), sigma, sigma, cv::BORDER_REPLICATE);
  }
  cv::Mat out;
  cv::warpAffine(src, out, cv::Mat(recipe.warp), size, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                 cv::Scalar::all(kBorderGrey));
  if (recipe.hasOccluder()) {
    const int b = std::clamp(recipe.occluder_begin, 0, size.width);
    const int e = std::clamp(recipe.occluder_end, 0, size.width);
    if (e > b) out(cv::Rect(b, 0, e - b, size.height)).setTo(cv::Scalar::all(kOccluderGrey));
  }
  return out;
}

bool pointVisible(cv::Point2d p, const FrameRecipe& recipe, cv::Size size) {
  // Pixel k covers [k - 0.5, k + 0.5).
  if (p.x < -0.5 || p.y < -0.5 || p.x >= size.width - 0.5 || p.y >= size.height - 0.5) return false;
  if (recipe.hasOccluder() && p.x >= recipe.occluder_begin - 0.5 && p.x < recipe.occluder_end - 0.5)
    return false;
  return true;
}

pt::Frame transformGroundTruth(const pt::Frame& source, const FrameRecipe& recipe, cv::Size size) {
  pt::Frame out = source;
  out.people.clear();
  for (const pt::Person& person : source.people) {
    pt::Person moved = person;
    bool any = false;
    for (auto& joint : moved.joints) {
      if (!joint) continue;
      const cv::Point2d q = apply(recipe.warp, {joint->x, joint->y});
      if (!pointVisible(q, recipe, size)) {
        joint.reset();
        continue;
      }
      joint->x = q.x;
      joint->y = q.y;
      any = true;
    }
    if (!any) continue;
    if (moved.head_box) {
      pt::HeadBox& b = *moved.head_box;
      double x1 = 1e300, y1 = 1e300, x2 = -1e300, y2 = -1e300;
      for (const cv::Point2d c : {cv::Point2d(b.x1, b.y1), cv::Point2d(b.x2, b.y1),
                                  cv::Point2d(b.x1, b.y2), cv::Point2d(b.x2, b.y2)}) {
        const cv::Point2d q = apply(recipe.warp, c);
        x1 = std::min(x1, q.x), y1 = std::min(y1, q.y);
        x2 = std::max(x2, q.x), y2 = std::max(y2, q.y);
      }
      b = {x1, y1, x2, y2};
    }
    out.people.push_back(std::move(moved));
  }
  for (pt::Polygon& poly : out.ignore_regions) {
    for (size_t i = 0; i < poly.x.size(); ++i) {
      const cv::Point2d q = apply(recipe.warp, {poly.x[i], poly.y[i]});
      poly.x[i] = q.x;
      poly.y[i] = q.y;
    }
  }
  return out;
}

std::vector<HiddenEpisode> hiddenEpisodes(const std::vector<pt::Frame>& source_gt,
                                          const Variant& variant) {
  // Per person: -1 not in the source frame, 0 hidden, 1 visible; per output frame.
  std::map<std::int64_t, std::vector<int>> state;
  const int n = static_cast<int>(variant.frames.size());
  for (int k = 0; k < n; ++k) {
    const FrameRecipe& r = variant.frames[k];
    const pt::Frame& src = source_gt.at(static_cast<size_t>(r.source));
    const pt::Frame out = transformGroundTruth(src, r, variant.size);
    for (const pt::Person& p : src.people) {
      if (!p.track_id) continue;
      auto& s = state.try_emplace(*p.track_id, std::vector<int>(n, -1)).first->second;
      s[k] = 0;
    }
    for (const pt::Person& p : out.people) {
      if (p.track_id) state[*p.track_id][k] = 1;
    }
  }
  std::vector<HiddenEpisode> episodes;
  for (const auto& [id, s] : state) {
    int k = 0;
    while (k < n) {
      if (s[k] != 0) {
        ++k;
        continue;
      }
      int e = k;
      while (e + 1 < n && s[e + 1] == 0) ++e;
      if (k > 0 && s[k - 1] == 1 && e + 1 < n && s[e + 1] == 1) episodes.push_back({id, k, e});
      k = e + 1;
    }
  }
  std::sort(episodes.begin(), episodes.end(),
            [](const HiddenEpisode& a, const HiddenEpisode& b) { return a.first < b.first; });
  return episodes;
}

namespace {

Variant fromTimeline(const std::string& name, const std::string& description, cv::Size size,
                     const std::vector<int>& timeline) {
  Variant v{name, description, size, {}};
  for (int f : timeline) v.frames.push_back(FrameRecipe{f});
  return v;
}

Variant withPath(const std::string& name, const std::string& description, cv::Size size,
                 const std::vector<int>& timeline, const std::vector<cv::Matx23d>& path) {
  Variant v = fromTimeline(name, description, size, timeline);
  for (size_t k = 0; k < v.frames.size(); ++k) v.frames[k].warp = path[k];
  return v;
}

}  // namespace

std::vector<Variant> bonnVariants(int n, cv::Size size, const VariantOptions& o) {
  std::vector<Variant> out;
  for (int s = 1; s <= o.still_strides_max; ++s) {
    out.push_back(fromTimeline("still-s" + std::to_string(s),
                               s == 1 ? std::string("the sequence as it is")
                                      : "one frame in " + std::to_string(s) + " of the sequence",
                               size, stridedTimeline(n, s)));
  }
  out.push_back(
      fromTimeline("reversed", "the sequence played backwards", size, reversedTimeline(n)));
  {
    const std::vector<int> timeline = pingPongTimeline(n, o.dropped_frames);
    const std::vector<int> positions = keptAfterDrops(o.dropped_frames, o.drop_probability, o.seed);
    std::vector<int> kept;
    for (int k : positions) kept.push_back(timeline[static_cast<size_t>(k)]);
    out.push_back(fromTimeline(
        "dropped",
        "forward-backward play of " + std::to_string(o.dropped_frames) +
            " frames, each frame after the first dropped with probability " +
            fixed(o.drop_probability, 2) +
            " (seeded), as a leaky queue does: " + std::to_string(kept.size()) + " frames kept",
        size, kept));
    for (size_t k = 0; k < positions.size(); ++k) out.back().frames[k].time = positions[k] / o.fps;
  }
  const std::vector<int> slow_play = pingPongTimeline(n, o.slow_frames);
  // The positions in the play of the frames an engine keeping up with one in s takes.
  auto slowPositions = [&](int s) {
    return keptBySlowEngine(o.slow_frames, s, o.slow_jitter, o.seed + static_cast<unsigned>(s));
  };
  auto sourcesAt = [&](const std::vector<int>& positions) {
    std::vector<int> kept;
    for (int k : positions) kept.push_back(slow_play[static_cast<size_t>(k)]);
    return kept;
  };
  for (int s : o.slow_strides) {
    const std::vector<int> positions = slowPositions(s);
    const std::vector<int> kept = sourcesAt(positions);
    out.push_back(
        fromTimeline("slow-s" + std::to_string(s),
                     "forward-backward play of " + std::to_string(o.slow_frames) +
                         " frames, one in " + std::to_string(s) + " kept (each gap " +
                         std::to_string(s) + " +- " + std::to_string(o.slow_jitter) +
                         ", seeded): a live camera whose engine keeps up with about 1 frame in " +
                         std::to_string(s) + " (" + std::to_string(kept.size()) + " frames)",
                     size, kept));
    for (size_t k = 0; k < kept.size(); ++k) out.back().frames[k].time = positions[k] / o.fps;
  }
  // The same frames as slow-sN, each 1 / fps after the one before: people moving about N times
  // faster than the Bonn ones (a sprinter, sport) before a camera whose engine keeps up with every
  // frame. The joints move as far between frames as in slow-sN, but little stream time passes.
  for (int s : o.fast_strides) {
    const std::vector<int> kept = sourcesAt(slowPositions(s));
    out.push_back(fromTimeline(
        "fast-x" + std::to_string(s),
        "the frames of slow-s" + std::to_string(s) + ", each 1 / " + fixed(o.fps, 0) +
            " s after the one before: people moving about " + std::to_string(s) +
            " times faster, every frame inferred (" + std::to_string(kept.size()) + " frames)",
        size, kept));
  }
  const std::vector<int> moving = pingPongTimeline(n, o.moving_frames);
  const cv::Point2d centre((size.width - 1) / 2.0, (size.height - 1) / 2.0);
  {
    const auto path = shakePath(o.moving_frames, o.shake_radius, o.seed);
    out.push_back(withPath("shake",
                           "forward-backward play of " + std::to_string(o.moving_frames) +
                               " frames, each shifted by " + fixed(o.shake_radius, 0) +
                               " px (whole pixels) in a random direction (seeded): mean step " +
                               fixed(meanStep(path, centre), 1) + " px per frame; black border",
                           size, moving, path));
  }
  out.push_back(withPath("pan",
                         "forward-backward play of " + std::to_string(o.moving_frames) +
                             " frames panned horizontally back and forth, +-" +
                             fixed(o.pan_amplitude, 0) + " px at " + fixed(o.pan_speed, 0) +
                             " px per frame; black border",
                         size, moving, panPath(o.moving_frames, o.pan_amplitude, o.pan_speed)));
  out.push_back(withPath("zoom",
                         "forward-backward play of " + std::to_string(o.moving_frames) +
                             " frames zoomed in about the centre from 1x to " +
                             fixed(o.zoom_final, 1) + "x, the same factor each frame",
                         size, moving, zoomPath(o.moving_frames, centre, o.zoom_final)));
  {
    // The bar crosses left to right, waits outside, and crosses back: each person is hidden
    // twice, from either side.
    const int crossing =
        static_cast<int>(std::ceil((size.width + o.occluder_width) / o.occluder_speed));
    const int lead = o.occluder_lead;
    const int length = lead + crossing + lead + crossing + lead;
    Variant v = fromTimeline(
        "occluder",
        "forward-backward play of " + std::to_string(length) + " frames; an opaque grey bar " +
            std::to_string(o.occluder_width) + " px wide, full height, crosses from left to " +
            "right and back at " + fixed(o.occluder_speed, 1) + " px per frame (" +
            std::to_string(lead) + " frames outside before, between and after); joints under it " +
            "are removed from the ground truth",
        size, pingPongTimeline(n, length));
    for (int k = 0; k < length; ++k) {
      // Frames since the bar set off, on the way there (0 .. crossing) or back.
      const int there = std::clamp(k - lead, 0, crossing);
      const int back = std::clamp(k - lead - crossing - lead, 0, crossing);
      const double travelled = o.occluder_speed * (there - back);
      const int begin = static_cast<int>(std::lround(-o.occluder_width + travelled));
      v.frames[static_cast<size_t>(k)].occluder_begin = begin;
      v.frames[static_cast<size_t>(k)].occluder_end = begin + o.occluder_width;
    }
    out.push_back(std::move(v));
  }
  {
    Variant v = fromTimeline("small",
                             "the sequence shrunk to " + fixed(o.small_scale, 2) +
                                 "x about the centre of a black canvas of the frame's size",
                             size, stridedTimeline(n, 1));
    for (FrameRecipe& r : v.frames) r.warp = scaleAbout(centre, o.small_scale);
    out.push_back(std::move(v));
  }
  for (Variant& v : out) {
    for (size_t k = 0; k < v.frames.size(); ++k) {
      if (std::isnan(v.frames[k].time)) v.frames[k].time = static_cast<double>(k) / o.fps;
    }
  }
  return out;
}

pt::Sequence variantGroundTruth(const pt::Sequence& source, const Variant& variant) {
  pt::Sequence out = source;
  out.frames.clear();
  for (const FrameRecipe& r : variant.frames) {
    if (r.source < 0 || r.source >= static_cast<int>(source.frames.size()))
      throw Error("variant " + variant.name + ": source frame " + std::to_string(r.source) +
                  " of a " + std::to_string(source.frames.size()) + "-frame sequence");
    out.frames.push_back(transformGroundTruth(source.frames[r.source], r, variant.size));
    // One id per position, not per source frame: a forward-backward play shows a source frame
    // twice, and PoseTrack files (--predictions) put annotations on images by id.
    const std::int64_t position = static_cast<std::int64_t>(out.frames.size()) - 1;
    out.frames.back().image_id = source.frames.front().image_id + position;
    out.frames.back().frame_id = source.frames.front().frame_id + position;
  }
  return out;
}

}  // namespace jointflow::bench
