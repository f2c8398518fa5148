// Re-entry on real frames: in vtest.avi a man in a black coat walks out of the view on the right
// at frame 145 and comes back there at frame 218, 7 s later (bench/identity.cpp lists who comes
// and goes when, counted by eye). His track ended after lost_time (3 s); with re-entry
// (reentry_time, on by default) he gets his id back, without it a new one.
#include <map>
#include <set>

#include <opencv2/videoio.hpp>

#include <catch2/catch.hpp>

#include "../core/tracking/motion_model.hpp"
#include "jointflow/tracker.hpp"
#include "test_env.hpp"

using namespace jointflow;

namespace {

// Frames of vtest.avi (10 frames/s), every kStep-th inferred: the networks at 5 frames/s, as
// inference-interval=2 runs them (and half the test's time).
constexpr int kFirst = 120, kLast = 240, kStep = 2;

// Per inferred frame: the ids reported, with where each person is.
using Frames = std::vector<std::map<std::int64_t, cv::Point2f>>;

Frames track(const TrackerSettings& s, const std::vector<SpatialResult>& results,
             const std::vector<cv::Mat>& frames) {
  Tracker tracker(s);
  Frames out;
  for (size_t i = 0; i < frames.size(); ++i) {
    out.emplace_back();
    for (const TrackedPose& p :
         tracker.process(results[i], frames[i], PixelOrder::kBGR, (kFirst + kStep * i) / 10.0))
      out.back()[p.track_id] = poseCentre(p.pose);
  }
  return out;
}

}  // namespace

TEST_CASE("a man who walks out and comes back 7 s later gets his id back (real frames)",
          "[tracking][reentry][long]") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  TrackerSettings s;
  s.model_type = ModelType::kMoveNet;
  const auto spatial = createSpatialModel(s.model_type, s.spatial);
  cv::VideoCapture video(test::vtestPath());
  video.set(cv::CAP_PROP_POS_FRAMES, kFirst);
  std::vector<cv::Mat> frames;
  std::vector<SpatialResult> results;
  cv::Mat frame;
  for (int t = kFirst; t <= kLast && video.read(frame); ++t) {
    if ((t - kFirst) % kStep) continue;
    frames.push_back(frame.clone());
    results.push_back(spatial->estimate(frame));
  }
  REQUIRE(static_cast<int>(frames.size()) == (kLast - kFirst) / kStep + 1);
  // Who walked out on the right (seen at x > 720 up to frame 150, then not for 6 s) and who
  // arrived in the last 2.5 s (reported in frames 216-240, not in 200-214), with and without
  // re-entry.
  auto walkedOut = [](const Frames& f) {
    std::set<std::int64_t> out;
    for (int t = kFirst; t <= 150; t += kStep)
      for (const auto& [id, c] : f[(t - kFirst) / kStep])
        if (c.x > 720.f) out.insert(id);
    for (int t = 160; t <= 214; t += kStep)
      for (const auto& [id, c] : f[(t - kFirst) / kStep]) out.erase(id);
    return out;
  };
  auto seen = [](const Frames& f, int from, int to) {
    std::set<std::int64_t> ids;
    for (int t = from; t <= to; t += kStep)
      for (const auto& [id, c] : f[(t - kFirst) / kStep]) ids.insert(id);
    return ids;
  };
  auto minus = [](std::set<std::int64_t> a, const std::set<std::int64_t>& b) {
    for (std::int64_t id : b) a.erase(id);
    return a;
  };
  const Frames with = track(s, results, frames);
  const auto out_with = walkedOut(with);
  REQUIRE(out_with.size() == 1);  // the man in the black coat
  const std::int64_t man = *out_with.begin();
  const auto arrived = minus(seen(with, 216, kLast), seen(with, 200, 214));
  CHECK(arrived.count(man) == 1);
  // Nobody in the last 2.5 s under an id not seen before: everyone then had been in the view.
  CHECK(minus(seen(with, 216, kLast), seen(with, kFirst, 214)).empty());

  TrackerSettings off = s;
  off.reentry_time = 0.f;
  const Frames without = track(off, results, frames);
  const auto out_without = walkedOut(without);
  REQUIRE(out_without.size() == 1);
  CHECK(minus(seen(without, 216, kLast), seen(without, 200, 214)).count(*out_without.begin()) == 0);
  // His new id, and since the tiles (7 December 2026) one more: another track there also ends and
  // starts again, which re-entry mends as well (the empty set above).
  CHECK_FALSE(minus(seen(without, 216, kLast), seen(without, kFirst, 214)).empty());
}
