// The shipped TFF network through the whole Tracker on real frames (vtest.avi, people walking)
// seen by a moving camera: the frames are shifted by a known camera path, so where each person
// is in every frame is known from the unshifted frames. With camera compensation off, "tff" must
// keep far more of the ids than "oks" (camera motion is what the TFF is for, paper Sec. 1).
// It does not hold every id (measured: 10 switches of 60 links against oks's 23 of 26). With camera
// compensation on (the default), the network sees the previous maps moved by the estimated camera
// motion: under a shake of ~100 px a frame it must then hold the ids it loses on raw maps. And the
// behaviour under jointflowtrack's inference-interval = N, which pairs frames N apart: every Nth
// frame, tff against oks.
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "jointflow/tracker.hpp"
#include "test_env.hpp"

using namespace jointflow;

namespace {

constexpr int kFirstFrame = 200;

std::vector<cv::Mat> vtestFrames(int count) {
  cv::VideoCapture video(test::vtestPath());
  std::vector<cv::Mat> frames;
  cv::Mat frame;
  video.set(cv::CAP_PROP_POS_FRAMES, kFirstFrame);
  while (static_cast<int>(frames.size()) < count && video.read(frame))
    frames.push_back(frame.clone());
  return frames;
}

cv::Mat shifted(const cv::Mat& frame, cv::Point2f by) {
  const cv::Mat m = (cv::Mat_<double>(2, 3) << 1, 0, by.x, 0, 1, by.y);
  cv::Mat out;
  cv::warpAffine(frame, out, m, frame.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return out;
}

cv::Point2f centreOf(const Pose& pose) {
  const Box b = pose.keypointBox(0.3f);
  return {b.x + b.w / 2, b.y + b.h / 2};
}

// Reference identities: the oks tracker on the unshifted frames, where people move a few pixels
// a frame (it holds them there, checked below). Per frame: reference id -> keypoint-box centre.
using Reference = std::vector<std::map<std::int64_t, cv::Point2f>>;

Reference referenceTracks(const std::vector<cv::Mat>& frames) {
  TrackerSettings s;
  s.similarity = SimilarityType::kOks;
  Tracker tracker(s);
  Reference ref;
  for (const cv::Mat& f : frames) {
    std::map<std::int64_t, cv::Point2f> people;
    for (const TrackedPose& t : tracker.process(f)) people[t.track_id] = centreOf(t.pose);
    ref.push_back(people);
  }
  return ref;
}

struct IdCount {
  int switches = 0;  ///< a reference person with another id than in its previous frame
  int matched = 0;   ///< reference people found, over all frames but the first
};

// Runs a tracker over frames shifted by `path`, maps each output back by the shift and matches it
// to the nearest reference person (within 15 px), and counts id switches per reference person.
IdCount idSwitches(const TrackerSettings& settings, const std::vector<cv::Mat>& frames,
                   const Reference& ref, const std::vector<cv::Point2f>& path,
                   const std::vector<int>& frame_index) {
  Tracker tracker(settings);
  std::map<std::int64_t, std::int64_t> last_id;  // reference id -> tracker id
  IdCount count;
  for (size_t k = 0; k < frame_index.size(); ++k) {
    const int f = frame_index[k];
    std::map<std::int64_t, std::int64_t> now;
    // Stream time of the frame (30 frames/s): every Nth frame is N frames' time apart, as with
    // inference-interval N.
    const double time = f / 30.0;
    for (const TrackedPose& t :
         tracker.process(shifted(frames[f], path[f]), PixelOrder::kBGR, time)) {
      const cv::Point2f c = centreOf(t.pose) - path[f];
      std::int64_t best = -1;
      double best_d = 15.0;
      for (const auto& [id, rc] : ref[f]) {
        const double d = cv::norm(rc - c);
        if (d < best_d) best_d = d, best = id;
      }
      if (best >= 0) now[best] = t.track_id;
    }
    for (const auto& [rid, tid] : now) {
      auto it = last_id.find(rid);
      if (it == last_id.end()) continue;
      ++count.matched;
      if (it->second != tid) ++count.switches;
    }
    for (const auto& [rid, tid] : now) last_id[rid] = tid;
  }
  return count;
}

const std::string kModel = test::modelsDir() + "/tff_movenet.onnx";

// The shipped TFF and oks, otherwise the same (default) settings.
std::pair<TrackerSettings, TrackerSettings> tffAndOks(bool camera_compensation) {
  TrackerSettings tff;
  tff.similarity = SimilarityType::kTff;
  tff.tff_model = kModel;
  tff.camera_compensation = camera_compensation;
  TrackerSettings oks = tff;
  oks.similarity = SimilarityType::kOks;
  return {tff, oks};
}

// 16 real frames, their reference identities, and every frame's index (all of them tracked);
// loaded once for the test cases that use them (realFrames()).
struct RealFrames {
  std::vector<cv::Mat> frames = vtestFrames(16);
  Reference ref = referenceTracks(frames);
  std::vector<int> all;
  RealFrames() {
    REQUIRE(frames.size() == 16);
    for (size_t i = 0; i < frames.size(); ++i) all.push_back(static_cast<int>(i));
  }
};

const RealFrames& realFrames() {
  static const RealFrames real;
  return real;
}

}  // namespace

TEST_CASE("shipped TFF keeps most ids of real people under a camera pan where oks loses them",
          "[training][long]") {
  JF_REQUIRE_PATH_OR_SKIP(kModel);
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  const auto& [frames, ref, all] = realFrames();

  // A jerky pan to the right and back, 0-45 px a frame (at 768x576), as a hand-held camera
  // follows someone: no constant velocity that a motion model could learn.
  const float steps[] = {0, 30, 45, 15, 40, 0, 35, 45, -30, -45, -15, -40, 0, -35, -45, 20};
  std::vector<cv::Point2f> path;
  float x = 0.f;
  for (float s : steps) path.emplace_back(x += s, 0.f);

  const auto [defaults_tff, defaults_oks] = tffAndOks(false);
  const IdCount still = idSwitches(defaults_oks, frames, ref, std::vector<cv::Point2f>(16), all);
  // The two similarities alone, re-identification off: appearance rescues the tracks a
  // similarity drops (step 5 takes tentative tracks too), which with the defaults hides the
  // difference (measured 7 switches of 61 links for tff, 7 of 57 for oks).
  TrackerSettings tff = defaults_tff, oks = defaults_oks;
  tff.reid = oks.reid = AppearanceModel::kOff;
  const IdCount with_tff = idSwitches(tff, frames, ref, path, all);
  const IdCount with_oks = idSwitches(oks, frames, ref, path, all);
  const IdCount compensated = idSwitches(tffAndOks(true).first, frames, ref, path, all);
  INFO("no camera motion, oks: " << still.switches << " switches of " << still.matched);
  INFO("pan, tff: " << with_tff.switches << " switches of " << with_tff.matched);
  INFO("pan, oks: " << with_oks.switches << " switches of " << with_oks.matched);
  INFO("pan, tff with camera compensation: " << compensated.switches << " switches of "
                                             << compensated.matched);
  CHECK(still.switches == 0);  // the reference itself: unshifted frames, oks holds everyone
  REQUIRE(with_tff.matched >= 40);
  REQUIRE(with_oks.matched >= 15);
  CHECK(with_oks.switches >= 15);  // measured 21 of 24 links (42 of 63 when reid skipped
                                   // tentative tracks; oks then lost people for good)
  CHECK(with_tff.switches <= 12);  // measured 10 of 60 (12 with the 2000-step network)
  // tff's share of links that switch, at most half of oks's: measured 0.17 against 0.88.
  CHECK(with_tff.switches * with_oks.matched * 2 <= with_oks.switches * with_tff.matched);
  // The product's default: the same network on camera-compensated maps.
  REQUIRE(compensated.matched >= 40);
  CHECK(compensated.switches <= 2);
}

TEST_CASE(
    "shipped TFF holds the ids of real people under a ~100 px camera shake on "
    "camera-compensated maps",
    "[training]") {
  JF_REQUIRE_PATH_OR_SKIP(kModel);
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  const auto& [frames, ref, all] = realFrames();

  // A shaken camera: every frame 80 px from the rest position in a direction that turns by 100
  // to 170 degrees from the frame before, so the steps are 120-160 px, far beyond the motions the
  // network was trained on.
  std::vector<cv::Point2f> path;
  double angle = 0.0;
  for (int f = 0; f < 16; ++f) {
    angle += CV_PI * (100 + 70 * ((f * 7) % 10) / 9.0) / 180.0;
    path.emplace_back(static_cast<float>(80 * std::cos(angle)),
                      static_cast<float>(80 * std::sin(angle)));
  }

  const IdCount compensated = idSwitches(tffAndOks(true).first, frames, ref, path, all);
  const IdCount raw = idSwitches(tffAndOks(false).first, frames, ref, path, all);
  INFO("shake, tff on compensated maps: " << compensated.switches << " switches of "
                                          << compensated.matched);
  INFO("shake, tff on raw maps (camera_compensation off): " << raw.switches << " switches of "
                                                            << raw.matched);
  REQUIRE(compensated.matched >= 40);
  REQUIRE(raw.matched >= 40);
  CHECK(raw.switches >= 20);  // the shake is beyond what the network follows on its own
  CHECK(compensated.switches <= 2);
}

TEST_CASE("shipped TFF keeps the ids at least as well as oks when frames are 1-4 apart",
          "[training][long]") {
  JF_REQUIRE_PATH_OR_SKIP(kModel);
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  // jointflowtrack with inference-interval=N gives the Tracker every Nth frame, so the TFF pairs
  // frames N apart; the network was trained on pairs 1-4 frames apart.
  const auto frames = vtestFrames(25);
  REQUIRE(frames.size() == 25);
  const Reference ref = referenceTracks(frames);
  const std::vector<cv::Point2f> still(frames.size());
  const auto [tff, oks] = tffAndOks(true);
  for (int n = 1; n <= 4; ++n) {
    std::vector<int> every;
    for (int f = 0; f < static_cast<int>(frames.size()); f += n) every.push_back(f);
    const IdCount t = idSwitches(tff, frames, ref, still, every);
    const IdCount o = idSwitches(oks, frames, ref, still, every);
    INFO("frames " << n << " apart: tff " << t.switches << " switches of " << t.matched << ", oks "
                   << o.switches << " of " << o.matched);
    CHECK(t.matched >= 20);
    CHECK(t.switches <= o.switches);
    // Measured 0 for N = 1-4 (5 December, both networks); oks the same since step 5 re-identifies
    // tentative tracks (0, 4, 11, 12 before).
    CHECK(t.switches <= 4);
  }
}
