// The OpenVINO engine against cv::dnn on real frames (vtest.avi), and its errors. The tolerances
// are the ones models/README.md documents ("OpenVINO parity"); each check prints what it measured.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "../../core/engine/network.hpp"
#include "../spatial/held_maps.hpp"
#include "../test_env.hpp"
#include "jointflow/error.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow/tff_model.hpp"
#include "jointflow/tracker.hpp"

using namespace jointflow;

namespace {

std::string model(const std::string& file) {
  return test::modelsDir() + "/" + file;
}

EngineOptions openvino(const std::string& instance = "") {
  EngineOptions d;
  d.backend = DnnBackend::kOpenVino;
  d.model_instance_id = instance;
  return d;
}

std::vector<cv::Mat> vtestFrames(const std::vector<int>& indices) {
  cv::VideoCapture cap(test::vtestPath());
  REQUIRE(cap.isOpened());
  std::vector<cv::Mat> frames;
  cv::Mat f;
  for (int i = 0; cap.read(f) && frames.size() < indices.size(); ++i)
    if (std::find(indices.begin(), indices.end(), i) != indices.end()) frames.push_back(f.clone());
  REQUIRE(frames.size() == indices.size());
  return frames;
}

// A BGR frame resized to a network input size.
cv::Mat resizedTo(const cv::Mat& frame, cv::Size input) {
  cv::Mat resized;
  cv::resize(frame, resized, input);
  return resized;
}

// MoveNet's input blob of a frame at a network input size (RGB 0..255, as cv::dnn gets it).
cv::Mat blobOf(const cv::Mat& frame, cv::Size input) {
  return cv::dnn::blobFromImage(resizedTo(frame, input), 1.0, cv::Size(), cv::Scalar(), true, false,
                                CV_32F);
}

// Largest |a - b| over the tensor, relative to the largest |a| (the head's range).
struct Diff {
  double max_abs = 0, range = 0;
  double relative() const { return range > 0 ? max_abs / range : max_abs; }
};
Diff diff(const cv::Mat& a, const cv::Mat& b) {
  REQUIRE(a.total() == b.total());
  Diff d;
  d.max_abs = cv::norm(a.reshape(1, 1), b.reshape(1, 1), cv::NORM_INF);
  d.range = cv::norm(a.reshape(1, 1), cv::NORM_INF);
  return d;
}

float keypointDistance(const Pose& a, const Pose& b) {
  float worst = 0;
  for (int j = 0; j < kNumJoints; ++j) {
    if (a.keypoints[j].score < 0.3f || b.keypoints[j].score < 0.3f) continue;
    worst = std::max(worst, std::hypot(a.keypoints[j].x - b.keypoints[j].x,
                                       a.keypoints[j].y - b.keypoints[j].y));
  }
  return worst;
}

}  // namespace

// Tolerances of models/README.md ("OpenVINO parity"), per precision: f32 computes what cv::dnn
// computes up to rounding; bf16 (OpenVINO's default on CPUs with AVX-512 BF16 or AMX) keeps 8
// bits of mantissa, so the heads move by a few percent of their range.
struct Tolerance {
  const char* precision;
  double head_relative;  ///< max |dnn - openvino| / max |dnn|, any head or feature map
  double belief_abs;     ///< max |dnn - openvino| of the belief maps (values in [0, 1])
  float keypoint_px;     ///< keypoints of a person scoring >= 0.3 (both >= 0.3), frame pixels
  float person_score;    ///< person score
};
const Tolerance kTolerances[] = {{"f32", 1e-3, 1e-3, 0.1f, 1e-3f}, {"", 0.25, 0.2, 8.f, 0.04f}};

TEST_CASE("OpenVINO gives MoveNet's heads and features as cv::dnn does, on real frames") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  auto dnn = detail::openDnnNetwork(model("movenet_multipose.onnx"), {});
  const std::vector<std::string> names = dnn->outputNames();
  const std::vector<cv::Mat> frames = vtestFrames({0, 200});
  for (const Tolerance& tol : kTolerances) {
    EngineOptions o = openvino();
    o.precision = tol.precision;
    auto ov = detail::openOpenVinoNetwork(model("movenet_multipose.onnx"), o);
    CHECK(ov->asynchronous());
    CHECK(ov->inputChannels() == 3);
    std::vector<std::string> ov_names = ov->outputNames(), dnn_names = names;
    std::sort(ov_names.begin(), ov_names.end());
    std::sort(dnn_names.begin(), dnn_names.end());
    CHECK(ov_names == dnn_names);
    for (const cv::Size input : {cv::Size(256, 256), cv::Size(640, 480)}) {
      std::map<std::string, double> worst;
      double image_vs_blob = 0;
      for (const cv::Mat& frame : frames) {
        const cv::Mat blob = blobOf(frame, input);
        const auto a = dnn->run(blob, names);
        const auto b = ov->run(blob, names);
        // The 8-bit BGR image itself, converted in OpenVINO's graph (how NetSpatialModel runs
        // it): the same network input, so the same outputs as from the blob, to rounding.
        ov->setImage(resizedTo(frame, input), {true, 1.0, 0.0});
        ov->start();
        const auto c = ov->wait(names);
        for (size_t i = 0; i < names.size(); ++i) {
          REQUIRE(a[i].size == b[i].size);
          REQUIRE(c[i].size == b[i].size);
          worst[names[i]] = std::max(worst[names[i]], diff(a[i], b[i]).relative());
          worst[names[i]] = std::max(worst[names[i]], diff(a[i], c[i]).relative());
          image_vs_blob = std::max(image_vs_blob, diff(b[i], c[i]).relative());
        }
      }
      std::ostringstream line;
      for (const auto& [name, d] : worst) {
        line << " " << name << " " << d;
        CHECK(d < tol.head_relative);
      }
      WARN(ov->engineName() << " at " << input << ", max |dnn - openvino| / range:" << line.str()
                            << "; 8-bit image against float blob: " << image_vs_blob);
      CHECK(image_vs_blob < tol.head_relative);
    }
  }
}

TEST_CASE("OpenVINO decodes the same people as cv::dnn on vtest frames") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  SpatialOptions o;  // max:640, one run a frame: the engines' agreement, not the tiles' merge
  o.tiles.mode = TileMode::kOff;
  auto dnn = createSpatialModel(ModelType::kMoveNet, o);
  const std::vector<cv::Mat> frames = vtestFrames({100, 200, 300});
  for (const Tolerance& tol : kTolerances) {
    EngineOptions engine = openvino();
    engine.precision = tol.precision;
    auto ov = createSpatialModel(ModelType::kMoveNet, o, engine);
    CHECK(ov->asynchronous());
    CHECK(ov->engine().rfind("OpenVINO 2026", 0) == 0);
    CHECK(ov->featureChannels() == dnn->featureChannels());
    double features = 0, beliefs = 0;
    float px = 0, score = 0;
    int people = 0;
    for (const cv::Mat& frame : frames) {
      const SpatialResult a = dnn->estimate(frame);
      const SpatialResult b = ov->estimate(frame);
      features = std::max(features, diff(a.features, b.features).relative());
      beliefs = std::max(beliefs, diff(a.beliefs, b.beliefs).max_abs);
      // Every confident person of cv::dnn is one of OpenVINO's: the nearest by keypoints.
      for (const Pose& p : a.poses) {
        if (p.score < 0.3f) continue;
        const Pose* best = nullptr;
        for (const Pose& q : b.poses)
          if (!best || keypointDistance(p, q) < keypointDistance(p, *best)) best = &q;
        REQUIRE(best);
        people++;
        px = std::max(px, keypointDistance(p, *best));
        score = std::max(score, std::abs(p.score - best->score));
      }
    }
    WARN(ov->engine() << ", max:640, 3 frames, " << people << " people scoring >= 0.3: features "
                      << features << " of range, beliefs " << beliefs << ", keypoints " << px
                      << " px, person score " << score);
    CHECK(people >= 10);
    CHECK(features < tol.head_relative);
    CHECK(beliefs < tol.belief_abs);
    CHECK(px < tol.keypoint_px);
    CHECK(score < tol.person_score);
  }
}

TEST_CASE("The person counts of cv::dnn and OpenVINO agree within 1 on 95 % of vtest frames") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  SpatialOptions o;  // max:640, one run a frame, as above
  o.tiles.mode = TileMode::kOff;
  auto dnn = createSpatialModel(ModelType::kMoveNet, o);
  // OpenVINO's default precision: the looser agreement
  auto ov = createSpatialModel(ModelType::kMoveNet, o, openvino());
  cv::VideoCapture cap(test::vtestPath());
  REQUIRE(cap.isOpened());
  // Every 6th frame of the 795 (make bench runs them all): 133 frames.
  int frames = 0, agree = 0, exact = 0;
  cv::Mat f;
  for (int i = 0; cap.read(f); ++i) {
    if (i % 6) continue;
    const int a = static_cast<int>(dnn->estimate(f).poses.size());
    const int b = static_cast<int>(ov->estimate(f).poses.size());
    frames++;
    agree += std::abs(a - b) <= 1;
    exact += a == b;
  }
  WARN("person counts: within 1 on " << agree << " of " << frames << " frames, equal on " << exact);
  REQUIRE(frames > 120);
  CHECK(agree >= 0.95 * frames);
}

TEST_CASE("OpenVINO: a frame's maps stay as they were while the caller holds them") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  SpatialOptions o;
  o.input_size = InputSize::parse("256x256");
  auto m = createSpatialModel(ModelType::kMoveNet, o, openvino());
  test::checkHeldMapsKept(*m, vtestFrames({10, 60, 110, 160}));
}

// The element holds one frame: frame N starts before frame N-1's outputs are read, queued behind
// its run (Network::maxRuns). Each frame must come back in order and as it does alone, at a size
// whose maps are transposed from channels-last (256x256) and at one whose maps the runs write in
// place into buffers that earlier frames' results still hold (640x480).
TEST_CASE("OpenVINO: a frame queued behind another comes back in order, as it does alone") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  const std::vector<cv::Mat> frames = vtestFrames({30, 90, 150, 210});
  const std::string size = GENERATE("256x256", "640x480");
  INFO("input size " << size);
  SpatialOptions o;
  o.input_size = InputSize::parse(size);
  o.tiles.mode = TileMode::kOff;  // one run a frame: only those are queued
  auto alone = createSpatialModel(ModelType::kMoveNet, o, openvino());
  std::vector<SpatialResult> expected;
  for (const cv::Mat& f : frames) {
    SpatialResult r = alone->estimate(f);
    r.beliefs = r.beliefs.clone();  // the engine reuses its buffers once nobody holds them
    expected.push_back(std::move(r));
  }
  auto queued = createSpatialModel(ModelType::kMoveNet, o, openvino());
  std::vector<SpatialResult> got;
  for (const cv::Mat& f : frames) {
    queued->submit(f);
    if (queued->pending() == 2) got.push_back(queued->collect());
  }
  got.push_back(queued->collect());
  REQUIRE(got.size() == frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    INFO("frame " << i);
    CHECK(cv::norm(got[i].beliefs, expected[i].beliefs, cv::NORM_INF) == 0.0);
    REQUIRE(got[i].poses.size() == expected[i].poses.size());
    for (size_t p = 0; p < got[i].poses.size(); ++p)
      CHECK(keypointDistance(got[i].poses[p], expected[i].poses[p]) == 0.f);
  }
  // The frames differ, so a result given to the wrong frame would have failed above.
  CHECK(cv::norm(expected[0].beliefs, expected[1].beliefs, cv::NORM_INF) > 0.1);

  SECTION("a third run while two are in flight is refused, naming the file") {
    auto net = detail::openOpenVinoNetwork(model("movenet_multipose.onnx"), openvino());
    REQUIRE(net->maxRuns() == 2);
    const cv::Mat blob = blobOf(frames[0], {256, 256});
    net->setInput(blob);
    net->start();
    net->setInput(blob);
    net->start();
    CHECK_THROWS_WITH(net->setInput(blob), Catch::Contains("movenet_multipose.onnx") &&
                                               Catch::Contains("2 runs are in flight"));
    const std::vector<std::string> names = {"heatmaps"};
    const cv::Mat first = net->wait(names).front().clone();
    const cv::Mat second = net->wait(names).front();
    CHECK(cv::norm(first, second, cv::NORM_INF) == 0.0);  // the same input twice
    CHECK_THROWS_WITH(net->wait(names), Catch::Contains("wait() without start()"));
  }
}

TEST_CASE("OpenVINO runs the TFF network as cv::dnn does") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  SpatialOptions o;
  auto spatial = createSpatialModel(ModelType::kMoveNet, o);
  std::vector<SpatialResult> maps;
  for (const cv::Mat& frame : vtestFrames({10, 11, 12})) maps.push_back(spatial->estimate(frame));
  TemporalFlowModel dnn(model("tff_movenet.onnx"), spatial->featureChannels());
  for (const Tolerance& tol : kTolerances) {
    EngineOptions d = openvino();
    d.precision = tol.precision;
    TemporalFlowModel ov(model("tff_movenet.onnx"), spatial->featureChannels(), d);
    dnn.reset();
    int fields = 0;
    double worst = 0;
    for (const SpatialResult& r : maps) {
      const cv::Mat a = dnn.predict(r.features, r.beliefs);
      const cv::Mat b = ov.predict(r.features, r.beliefs);
      REQUIRE(a.empty() == b.empty());
      if (a.empty()) continue;
      fields++;
      worst = std::max(worst, diff(a, b).relative());
    }
    WARN("TFF on OpenVINO (precision " << (*tol.precision ? tol.precision : "default")
                                       << "), max:640: max |dnn - openvino| / range " << worst);
    CHECK(fields == 2);
    CHECK(worst < tol.head_relative);
  }
}

// The engine takes 4-D outputs channels-last and transposes them itself, in tiles of 64 cells
// (openvino_network.cpp): grids whose cell count is not a multiple of the tile, and one whose
// planes lie a multiple of 4 KiB apart (vtest.avi's native 144x192), come out as cv::dnn's.
TEST_CASE("OpenVINO hands over the TFF on any grid as cv::dnn does") {
  const int channels = 24;  // MoveNet's features
  TemporalFlowModel dnn(model("tff_movenet.onnx"), channels);
  EngineOptions d = openvino();
  d.precision = "f32";
  TemporalFlowModel ov(model("tff_movenet.onnx"), channels, d);
  cv::RNG rng(12);
  for (const cv::Size grid : {cv::Size(38, 22), cv::Size(192, 144), cv::Size(10, 6)}) {
    CAPTURE(grid);
    dnn.reset();
    ov.reset();
    for (int frame = 0; frame < 2; ++frame) {
      const int fs[] = {1, channels, grid.height, grid.width};
      const int bs[] = {1, kNumJoints, grid.height, grid.width};
      cv::Mat features(4, fs, CV_32F), beliefs(4, bs, CV_32F);
      rng.fill(features, cv::RNG::UNIFORM, 0.f, 2.f);
      rng.fill(beliefs, cv::RNG::UNIFORM, 0.f, 1.f);
      const cv::Mat a = dnn.predict(features, beliefs);
      const cv::Mat b = ov.predict(features, beliefs);
      REQUIRE(a.empty() == b.empty());
      if (a.empty()) continue;
      REQUIRE(b.size[1] == 2 * kNumJoints);
      REQUIRE(b.size[2] == grid.height);
      REQUIRE(b.size[3] == grid.width);
      const Diff e = diff(a, b);
      CHECK(e.range > 0.01);  // a field, not zeros
      CHECK(e.relative() < 1e-3);
    }
  }
}

TEST_CASE("Networks with one model-instance-id share one compiled model", "[streams]") {
  const std::string path = model("movenet_multipose.onnx");
  auto a = detail::openOpenVinoNetwork(path, openvino("shared-test"));
  auto b = detail::openOpenVinoNetwork(path, openvino("shared-test"));
  auto c = detail::openOpenVinoNetwork(path, openvino("other"));
  auto d = detail::openOpenVinoNetwork(path, openvino());
  CHECK(a->sharedModel() == b->sharedModel());
  CHECK(a->sharedModel() != c->sharedModel());
  CHECK(a->sharedModel() != d->sharedModel());
  SECTION("an instance asking for other settings is refused, naming the id") {
    EngineOptions other = openvino("shared-test");
    other.num_threads = 1;
    CHECK_THROWS_WITH(
        detail::openOpenVinoNetwork(path, other),
        Catch::Contains("model-instance-id \"shared-test\"") && Catch::Contains("1 threads"));
  }
}

// At 256x256 the maps come channels-last and are transposed on the stream's thread; at 640x480
// OpenVINO's threads write them in place into buffers of the stream's pool (giveOutputs).
TEST_CASE("Streams sharing one compiled model track as one stream alone does", "[streams]") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  const std::vector<cv::Mat> frames = vtestFrames({20, 21, 22, 23, 24, 25});
  const std::string size = GENERATE("256x256", "640x480");
  INFO("input size " << size);
  TrackerSettings s;
  s.model_type = ModelType::kMoveNet;
  s.similarity = SimilarityType::kTff;
  s.spatial.input_size = InputSize::parse(size);
  s.engine = openvino("streams-test");
  auto run = [&](std::vector<std::vector<TrackedPose>>& out) {
    Tracker t(s);
    // Pipelined as the element runs it: frame N starts before frame N-1 is associated.
    for (const cv::Mat& f : frames) {
      t.submit(f);
      if (t.pending() == 2) out.push_back(t.collect());
    }
    while (t.pending() > 0) out.push_back(t.collect());
  };
  std::vector<std::vector<TrackedPose>> alone;
  run(alone);
  REQUIRE(alone.size() == frames.size());
  REQUIRE(!alone.back().empty());
  constexpr int kStreams = 4;
  std::vector<std::vector<std::vector<TrackedPose>>> streams(kStreams);
  std::vector<std::thread> threads;
  for (int i = 0; i < kStreams; ++i) threads.emplace_back([&, i] { run(streams[i]); });
  for (auto& t : threads) t.join();
  for (const auto& st : streams) {
    REQUIRE(st.size() == alone.size());
    for (size_t k = 0; k < st.size(); ++k) {
      REQUIRE(st[k].size() == alone[k].size());
      for (size_t p = 0; p < st[k].size(); ++p) {
        CHECK(st[k][p].track_id == alone[k][p].track_id);
        CHECK(st[k][p].pose.keypoints[0].x == Approx(alone[k][p].pose.keypoints[0].x).margin(1e-3));
      }
    }
  }
}

TEST_CASE("OpenVINO's errors name the file, the device and the id") {
  SECTION("a file OpenVINO cannot read") {
    const std::string bad =
        (std::filesystem::temp_directory_path() / "jointflow_truncated.onnx").string();
    {
      std::ifstream in(model("movenet_multipose.onnx"), std::ios::binary);
      std::vector<char> bytes(4096);
      in.read(bytes.data(), bytes.size());
      std::ofstream(bad, std::ios::binary).write(bytes.data(), bytes.size());
    }
    CHECK_THROWS_WITH(detail::openOpenVinoNetwork(bad, openvino()),
                      Catch::Contains(bad) && Catch::Contains("OpenVINO"));
    SpatialOptions o;
    o.model_path = bad;
    CHECK_THROWS_WITH(createSpatialModel(ModelType::kMoveNet, o, openvino()), Catch::Contains(bad));
    std::filesystem::remove(bad);
  }
  SECTION("a missing file") {
    CHECK_THROWS_WITH(detail::openOpenVinoNetwork("/nonexistent/m.onnx", openvino()),
                      Catch::Contains("/nonexistent/m.onnx"));
  }
  SECTION("an unknown device lists the devices there are") {
    EngineOptions d = openvino();
    d.device = "TPU";
    CHECK_THROWS_WITH(detail::openOpenVinoNetwork(model("movenet_multipose.onnx"), d),
                      Catch::Contains("\"TPU\"") && Catch::Contains("CPU"));
  }
  SECTION("a cv::dnn target") {
    EngineOptions d = openvino();
    d.target = DnnTarget::kOpenCL;
    CHECK_THROWS_WITH(detail::openOpenVinoNetwork(model("movenet_multipose.onnx"), d),
                      Catch::Contains("device"));
  }
  SECTION("a model of the wrong kind: the outputs it lacks") {
    SpatialOptions o;
    o.model_path = model("tff_movenet.onnx");
    CHECK_THROWS_WITH(createSpatialModel(ModelType::kMoveNet, o, openvino()),
                      Catch::Contains("tff_movenet.onnx") && Catch::Contains("missing"));
  }
}
