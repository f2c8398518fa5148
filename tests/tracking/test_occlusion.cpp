// Occlusion on real frames: a wide opaque bar sweeps across vtest.avi and hides each walker for
// up to about two seconds. The tracks of the clean frames are the reference; a person the bar
// hid must come back under the id it had before (lost tracks, their motion model and
// re-identification), where without lost tracks it gets a new one.
#include <map>
#include <set>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <catch2/catch.hpp>

#include "jointflow/tracker.hpp"
#include "test_env.hpp"

using namespace jointflow;

namespace {

constexpr int kFrames = 80;  // 8 s of vtest.avi at its 10 frames/s
constexpr double kFps = 10.0;
constexpr int kBar = 140;  // px

int barLeft(int t) {
  return -kBar + static_cast<int>(t * (768.0 + kBar) / (kFrames - 1));
}

struct Seen {
  std::int64_t id;
  Box box;
};

std::vector<std::vector<Seen>> track(const TrackerSettings& s,
                                     const std::vector<SpatialResult>& results,
                                     const std::vector<cv::Mat>& frames) {
  Tracker tracker(s);
  std::vector<std::vector<Seen>> out;
  for (size_t t = 0; t < frames.size(); ++t) {
    out.emplace_back();
    for (const TrackedPose& tp : tracker.process(results[t], frames[t], PixelOrder::kBGR, t / kFps))
      out.back().push_back({tp.track_id, tp.pose.box});
  }
  return out;
}

// The id of the run's person on the reference box in frame t, or -1.
std::int64_t idAt(const std::vector<std::vector<Seen>>& run, int t, const Box& box) {
  float best = 0.3f;
  std::int64_t id = -1;
  for (const Seen& s : run[t])
    if (iou(s.box, box) > best) {
      best = iou(s.box, box);
      id = s.id;
    }
  return id;
}

struct Outcome {
  int hidden = 0;   ///< reference people the bar hid for >= 3 frames and that reappear
  int same_id = 0;  ///< of which the run gave the id they had before
};

Outcome score(const std::vector<std::vector<Seen>>& reference,
              const std::vector<std::vector<Seen>>& run) {
  // Each reference track's box per frame.
  std::map<std::int64_t, std::map<int, Box>> tracks;
  for (int t = 0; t < kFrames; ++t)
    for (const Seen& s : reference[t]) tracks[s.id][t] = s.box;
  Outcome o;
  for (const auto& [id, boxes] : tracks) {
    // The frames in which the bar covers the person's centre.
    int first = -1, last = -1;
    for (const auto& [t, b] : boxes) {
      const float cx = b.x + b.w / 2;
      if (cx >= barLeft(t) && cx <= barLeft(t) + kBar) {
        if (first < 0) first = t;
        last = t;
      }
    }
    if (first < 1 || last - first + 1 < 3) continue;
    const auto before = boxes.find(first - 1);
    if (before == boxes.end()) continue;
    const std::int64_t id_before = idAt(run, first - 1, before->second);
    if (id_before < 0) continue;
    // The first of the next five frames after the bar in which the run sees the person.
    std::int64_t id_after = -1;
    for (int t = last + 1; t <= last + 5 && t < kFrames && id_after < 0; ++t)
      if (const auto b = boxes.find(t); b != boxes.end()) id_after = idAt(run, t, b->second);
    if (id_after < 0) continue;
    ++o.hidden;
    o.same_id += id_after == id_before;
  }
  return o;
}

}  // namespace

TEST_CASE("a bar sweeping over real frames: the people it hid come back under their ids",
          "[tracking][occlusion][long]") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  TrackerSettings s;
  s.model_type = ModelType::kMoveNet;
  s.spatial.input_size = InputSize::parse("native");  // vtest's people are 40-100 px tall
  const auto spatial = createSpatialModel(s.model_type, s.spatial);
  cv::VideoCapture video(test::vtestPath());
  std::vector<cv::Mat> clean, hidden;
  std::vector<SpatialResult> clean_results, hidden_results;
  cv::Mat frame;
  for (int t = 0; t < kFrames && video.read(frame); ++t) {
    clean.push_back(frame.clone());
    cv::Mat h = frame.clone();
    cv::rectangle(h, cv::Rect(barLeft(t), 0, kBar, h.rows), cv::Scalar(40, 40, 40), cv::FILLED);
    hidden.push_back(h);
    clean_results.push_back(spatial->estimate(clean.back()));
    hidden_results.push_back(spatial->estimate(hidden.back()));
  }
  REQUIRE(static_cast<int>(clean.size()) == kFrames);
  const auto reference = track(s, clean_results, clean);

  const Outcome defaults = score(reference, track(s, hidden_results, hidden));
  TrackerSettings no_reid = s;
  no_reid.reid = AppearanceModel::kOff;
  const Outcome geometry = score(reference, track(no_reid, hidden_results, hidden));
  TrackerSettings no_lost = s;
  no_lost.lost_time = no_lost.tentative_lost_time = 0.f;
  const Outcome forgetful = score(reference, track(no_lost, hidden_results, hidden));
  WARN("people hidden by the bar for >= 3 frames and seen again: "
       << defaults.hidden << "; back under their id: defaults " << defaults.same_id
       << ", without re-identification " << geometry.same_id << ", without lost tracks "
       << forgetful.same_id);
  // At least 4 people to judge by. Two of the bar's people stand one behind the other at the sign
  // (frames 28-36, boxes at IoU 0.8); which of the two the run reports right after the bar moved
  // with the association (5 people counted before stop 46's changes, 4 since: the one behind is
  // not reported within 5 frames after it).
  REQUIRE(defaults.hidden >= 4);
  CHECK(defaults.same_id * 10 >= defaults.hidden * 8);  // at least 80 % come back
  CHECK(forgetful.same_id < defaults.same_id);          // what the lost tracks are for
}
