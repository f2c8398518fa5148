// The Tracker facade end to end: MoveNet on real frames of vtest.avi, then association; the TFF
// runner wired in with a tiny contract model for MoveNet's 24 feature channels.
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <catch2/catch.hpp>

#include "jointflow/error.hpp"
#include "jointflow/tracker.hpp"
#include "test_env.hpp"

using namespace jointflow;

namespace {

std::vector<cv::Mat> vtestFrames(int count) {
  cv::VideoCapture video(test::vtestPath());
  std::vector<cv::Mat> frames;
  cv::Mat frame;
  video.set(cv::CAP_PROP_POS_FRAMES, 200);
  while (static_cast<int>(frames.size()) < count && video.read(frame))
    frames.push_back(frame.clone());
  return frames;
}

TrackerSettings movenetSettings(const std::string& similarity) {
  TrackerSettings s;
  s.model_type = ModelType::kMoveNet;
  s.spatial.input_size = InputSize::parse("native");  // people in vtest.avi are 40-100 px tall
  s.similarity = parseEnum<SimilarityType>(similarity);
  return s;
}

std::string dataFile(const std::string& name) {
  return test::sourceRoot() + "/tests/data/" + name;
}

}  // namespace

TEST_CASE("Tracker refuses a missing or unfitting TFF model", "[tracking][tracker]") {
  TrackerSettings s = movenetSettings("tff");
  s.tff_model = "/nonexistent/tff_movenet.onnx";
  CHECK_THROWS_WITH(Tracker(s), Catch::Contains("needs a TFF model") &&
                                    Catch::Contains("/nonexistent/tff_movenet.onnx"));
  s.tff_model = dataFile("tff_wiring_c3.onnx");
  CHECK_THROWS_WITH(Tracker(s), Catch::Contains("takes 40") && Catch::Contains("needs 82"));
  // auto takes a named TFF file as tff does: a missing one is an error that names the similarity.
  s = movenetSettings("auto");
  s.tff_model = "/nonexistent/tff_movenet.onnx";
  CHECK_THROWS_WITH(Tracker(s), Catch::Contains("similarity \"auto\" needs a TFF model"));
  s = movenetSettings("auto");
  s.auto_tff_gap = std::nanf("");
  CHECK_THROWS_WITH(Tracker(s), Catch::Contains("auto-tff-gap: nan is out of range (0 to 3600)"));
  s.auto_tff_gap = -0.1f;
  CHECK_THROWS_WITH(Tracker(s), Catch::Contains("auto-tff-gap: -0.1 is out of range"));
  s = movenetSettings("oks");
  s.lost_time = -1.f;
  CHECK_THROWS_WITH(Tracker(s), Catch::Contains("lost-time: -1 is out of range (0 to 3600)"));
}

TEST_CASE("Tracker tracks the people of real frames, ids without gaps", "[tracking][tracker]") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  const auto frames = vtestFrames(6);
  REQUIRE(frames.size() == 6);
  for (const std::string similarity : {"oks", "flow", "tff"}) {
    INFO(similarity);
    TrackerSettings s = movenetSettings(similarity);
    if (similarity == "tff") s.tff_model = dataFile("tff_wiring_c24.onnx");
    Tracker tracker(s);
    CHECK(toString(tracker.settings().similarity) == similarity);
    std::set<std::int64_t> first, seen;
    for (size_t t = 0; t < frames.size(); ++t) {
      const auto out = tracker.process(frames[t]);
      CHECK(out.size() >= 3);
      std::set<std::int64_t> here;
      for (const TrackedPose& p : out) {
        CHECK(here.insert(p.track_id).second);  // unique within the frame
        seen.insert(p.track_id);
        if (t == 0) first.insert(p.track_id);
        CHECK(p.age <= static_cast<int>(t));
      }
      if (t == frames.size() - 1 && similarity != "tff") {
        // Walkers at 1-2 px per frame keep their ids over six frames. (The "tff" run uses a
        // wiring model whose output is no flow field: it checks the plumbing, not the ids.)
        int kept = 0;
        for (std::int64_t id : here) kept += first.count(id);
        CHECK(kept >= 3);
      }
    }
    // Output ids count up from 1 without gaps.
    CHECK(*seen.begin() == 1);
    CHECK(*seen.rbegin() == static_cast<std::int64_t>(seen.size()));
    tracker.reset();
    for (const TrackedPose& p : tracker.process(frames[0]))
      CHECK(p.track_id > static_cast<std::int64_t>(seen.size()));
  }
}

TEST_CASE("Tracker with similarity auto: oks between close frames, the shipped TFF between far",
          "[tracking][tracker]") {
  // Real frames, the shipped network: auto's output is oks's exactly where the frames are closer
  // than auto_tff_gap (10 frames/s here), and tff's exactly where they are further apart (a slow
  // engine taking 1 frame in 5).
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  JF_REQUIRE_PATH_OR_SKIP(test::modelsDir() + "/tff_movenet.onnx");
  const auto frames = vtestFrames(5);
  REQUIRE(frames.size() == 5);
  const TrackerSettings oks = movenetSettings("oks");
  const auto spatial = createSpatialModel(oks.model_type, oks.spatial);
  std::vector<SpatialResult> results;
  for (const cv::Mat& frame : frames) results.push_back(spatial->estimate(frame));
  for (const auto& [gap, like] : {std::pair{0.1, "oks"}, std::pair{0.5, "tff"}}) {
    INFO("frames " << gap << " s apart: as " << like);
    Tracker a(movenetSettings("auto")), b(movenetSettings(like));
    size_t people = 0;
    for (size_t t = 0; t < frames.size(); ++t) {
      const double time = static_cast<double>(t) * gap;
      const auto x = a.process(results[t], frames[t], PixelOrder::kBGR, time);
      const auto y = b.process(results[t], frames[t], PixelOrder::kBGR, time);
      REQUIRE(x.size() == y.size());
      people += x.size();
      for (size_t k = 0; k < x.size(); ++k) {
        CHECK(x[k].track_id == y[k].track_id);
        CHECK(x[k].detection == y[k].detection);
        CHECK(x[k].pose.keypoints[9].x == y[k].pose.keypoints[9].x);
      }
    }
    CHECK(people >= 15);
  }
  Tracker with_tff(movenetSettings("auto"));
  CHECK(with_tff.hasTff());
  // PoseNet has no TFF network: auto is oks there, and starts where tff would refuse.
  TrackerSettings posenet = oks;
  posenet.model_type = ModelType::kPoseNet;
  posenet.spatial.input_size = InputSize::parse("max:640");
  posenet.similarity = SimilarityType::kAuto;
  Tracker a(posenet);
  CHECK_FALSE(a.hasTff());
  posenet.similarity = SimilarityType::kOks;
  Tracker b(posenet);
  for (size_t t = 0; t < 2; ++t) {
    const auto x = a.process(frames[t], PixelOrder::kBGR, t * 0.5);
    const auto y = b.process(frames[t], PixelOrder::kBGR, t * 0.5);
    REQUIRE(x.size() == y.size());
    for (size_t k = 0; k < x.size(); ++k) CHECK(x[k].track_id == y[k].track_id);
  }
}

TEST_CASE(
    "Tracker with similarity auto and a shipped TFF that does not fit: oks, where tff refuses",
    "[tracking][tracker]") {
  // A models folder whose tff_movenet.onnx takes 3 feature channels, not MoveNet's 24 (a custom
  // export): the default similarity must not refuse to start over a network nobody asked for.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("jf-auto-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // Only the TFF network is looked up in the models folder; the spatial model is named below.
  fs::copy_file(dataFile("tff_wiring_c3.onnx"), dir / "tff_movenet.onnx",
                fs::copy_options::overwrite_existing);
  const std::string movenet = test::modelsDir() + "/movenet_multipose.onnx";  // before setenv
  const char* before = std::getenv("JOINTFLOW_MODELS_DIR");
  const std::string saved = before ? before : "";
  ::setenv("JOINTFLOW_MODELS_DIR", dir.c_str(), 1);
  TrackerSettings s = movenetSettings("auto");
  s.spatial.model_path = movenet;
  bool has_tff = true;
  CHECK_NOTHROW(has_tff = Tracker(s).hasTff());
  CHECK_FALSE(has_tff);
  s.similarity = SimilarityType::kTff;
  CHECK_THROWS_WITH(Tracker(s), Catch::Contains("takes 40") && Catch::Contains("needs 82"));
  if (before)
    ::setenv("JOINTFLOW_MODELS_DIR", saved.c_str(), 1);
  else
    ::unsetenv("JOINTFLOW_MODELS_DIR");
  fs::remove_all(dir);
}

TEST_CASE("Tracker refuses images it cannot use", "[tracking][tracker]") {
  Tracker tracker(movenetSettings("oks"));
  CHECK_THROWS_WITH(tracker.process(cv::Mat()), Catch::Contains("empty"));
  CHECK_THROWS_WITH(tracker.process(cv::Mat(64, 64, CV_8UC1, cv::Scalar(0))),
                    Catch::Contains("3-channel"));
}

TEST_CASE("Tracker on a precomputed spatial result follows the same path as on the frame",
          "[tracking][tracker]") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  const auto frames = vtestFrames(4);
  REQUIRE(frames.size() == 4);
  const TrackerSettings s = movenetSettings("flow");
  Tracker whole(s), split(s);
  const auto spatial = createSpatialModel(s.model_type, s.spatial);
  for (const cv::Mat& frame : frames) {
    const auto a = whole.process(frame);
    const auto b = split.process(spatial->estimate(frame), frame);
    REQUIRE(a.size() == b.size());
    for (size_t k = 0; k < a.size(); ++k) {
      CHECK(a[k].track_id == b[k].track_id);
      CHECK(a[k].detection == b[k].detection);
      CHECK(a[k].pose.keypoints[0].x == b[k].pose.keypoints[0].x);
    }
  }
  cv::Mat half;
  cv::resize(frames[0], half, {}, 0.5, 0.5);
  CHECK_THROWS_WITH(split.process(spatial->estimate(frames[0]), half),
                    Catch::Contains("768x576 frame") && Catch::Contains("384x288"));
}
