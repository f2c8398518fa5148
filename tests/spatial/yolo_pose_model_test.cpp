// The YOLO pose spatial model (model-type yolo) end to end on a tiny ONNX file written by the test,
// whose output is a known {1, 56, N} tensor: poses through the letterbox to frame pixels, on each
// engine of the build; the errors for a missing opt-in file and for a file of another type; and
// what the Tracker makes of a spatial model without maps.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "../test_env.hpp"
#include "jointflow/error.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow/tracker.hpp"
#include "onnx_writer.hpp"
#include "yolo_pose_output.hpp"

using namespace jointflow;
namespace fs = std::filesystem;
using test::YoloAnchor;

namespace {

std::string writeTemp(const std::string& name, const std::string& bytes) {
  const auto path = fs::temp_directory_path() / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

// 65 people of 24x48 px on a 512x384 input, 13 x 5, none overlapping.
std::vector<YoloAnchor> people() {
  std::vector<YoloAnchor> p;
  for (int i = 0; i < 65; ++i)
    p.push_back(test::yoloPerson(30.f + 36.f * (i % 13), 40.f + 70.f * (i / 13), 24.f, 48.f,
                                 0.3f + 0.01f * i));
  return p;
}

std::string tinyYolo() {
  static const std::string path =
      writeTemp("jointflow_tiny_yolo_pose.onnx",
                test::constantSequenceOnnx("output0", test::yoloOutput(people(), 1008)));
  return path;
}

// The tiny model's output is its tensor for a frame whose red channel is 255 (its contract).
cv::Mat redFrame(cv::Size size) {
  return cv::Mat(size, CV_8UC3, cv::Scalar(0, 0, 255));
}

std::vector<DnnBackend> backends() {
#ifdef JOINTFLOW_TEST_OPENVINO
  return {DnnBackend::kDefault, DnnBackend::kOpenVino};
#else
  return {DnnBackend::kDefault};
#endif
}

/// JOINTFLOW_MODELS_DIR set for the scope of the object.
class ModelsDir {
 public:
  explicit ModelsDir(const std::string& dir) : old_(test::envOr("JOINTFLOW_MODELS_DIR", "")) {
    setenv("JOINTFLOW_MODELS_DIR", dir.c_str(), 1);
  }
  ~ModelsDir() {
    if (old_.empty())
      unsetenv("JOINTFLOW_MODELS_DIR");
    else
      setenv("JOINTFLOW_MODELS_DIR", old_.c_str(), 1);
  }

 private:
  std::string old_;
};

/// The message of what `make` throws; "" when it throws nothing or something else.
template <typename F>
std::string errorOf(F make) {
  try {
    make();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

void checkSays(const std::string& message, const std::vector<std::string>& parts) {
  for (const auto& part : parts) CHECK_THAT(message, Catch::Contains(part));
}

void checkFramePoses(const Poses& poses, const std::vector<YoloAnchor>& truth, float zoom) {
  // Ultralytics' input pixels (edges at integers) to frame pixels (centres at integers) for a
  // frame `zoom` times the input: frame = (input - 0.5 + 0.5) zoom - 0.5.
  auto frame = [&](float v) { return Approx(v * zoom - 0.5f).margin(1e-3); };
  REQUIRE(poses.size() == truth.size());
  for (size_t i = 0; i < truth.size(); ++i) {
    const YoloAnchor& want = truth[truth.size() - 1 - i];  // highest score first
    const Pose& got = poses[i];
    INFO("person at " << want.cx << ", " << want.cy);
    CHECK(got.score == want.score);
    CHECK(got.box.x == frame(want.cx - 0.5f * want.w));
    CHECK(got.box.y == frame(want.cy - 0.5f * want.h));
    CHECK(got.box.w == Approx(want.w * zoom));
    CHECK(got.box.h == Approx(want.h * zoom));
    for (int j = 0; j < kNumJoints; ++j) {
      INFO("joint " << j);
      CHECK(got.keypoints[j].x == frame(want.joints[j].x));
      CHECK(got.keypoints[j].y == frame(want.joints[j].y));
      // keypoint_threshold 0.12: joint j scores 0.9 - 0.05 j, so joint 16 (0.1) is dropped.
      CHECK(got.keypoints[j].score == (j < 16 ? want.joints[j].score : 0.f));
    }
  }
}

}  // namespace

TEST_CASE("YOLO pose model: the poses of its output in frame pixels, through the letterbox") {
  const std::vector<YoloAnchor> truth = people();
  // Each case makes the network's input 512x384 without padding (the tiny model's output is its
  // tensor only for an input whose red channel is 1 everywhere).
  struct Case {
    const char* input_size;
    std::vector<float> scales;
    int zoom;  // frame = zoom x input
  };
  const std::vector<Case> cases = {{"native", {1.f}, 1},
                                   {"max:512", {1.f}, 2},
                                   {"512x384", {1.f}, 2},
                                   // two scales' candidates pooled, then suppressed as one
                                   {"256x192", {2.f, 2.f}, 2}};
  for (const DnnBackend backend : backends()) {
    for (const Case& k : cases) {
      INFO(toString(backend) << ", input size " << k.input_size << " at " << k.scales.size()
                             << " scale(s), frame " << k.zoom << " x the input");
      SpatialOptions o;
      o.model_path = tinyYolo();
      o.input_size = InputSize::parse(k.input_size);
      o.scales = k.scales;
      o.max_persons = 100;
      o.keypoint_threshold = 0.12f;
      EngineOptions engine;
      engine.backend = backend;
      auto model = createSpatialModel(ModelType::kYolo, o, engine);
      CHECK(model->type() == ModelType::kYolo);
      CHECK(model->featureChannels() == 0);
      const cv::Mat frame = redFrame({512 * k.zoom, 384 * k.zoom});
      const SpatialResult r = model->estimate(frame);
      CHECK(r.frame_size == frame.size());
      CHECK(r.features.empty());
      CHECK(r.beliefs.empty());
      checkFramePoses(r.poses, truth, static_cast<float>(k.zoom));
      // Two frames pending (OpenVINO queues the second behind the first).
      model->submit(frame);
      model->submit(frame);
      CHECK(model->pending() == 2);
      checkFramePoses(model->collect().poses, truth, static_cast<float>(k.zoom));
      checkFramePoses(model->collect().poses, truth, static_cast<float>(k.zoom));
    }
  }
}

TEST_CASE("YOLO pose model: person threshold and cap") {
  SpatialOptions o;
  o.model_path = tinyYolo();
  o.input_size = InputSize::parse("native");
  o.person_threshold = 0.6f;  // people score 0.3 + 0.01 i: i >= 30 stay (35 of them)
  o.max_persons = 100;
  CHECK(createSpatialModel(ModelType::kYolo, o)->estimate(redFrame({512, 384})).poses.size() == 35);
  o.max_persons = 20;
  const Poses poses = createSpatialModel(ModelType::kYolo, o)->estimate(redFrame({512, 384})).poses;
  REQUIRE(poses.size() == 20);
  CHECK(poses.front().score == people().back().score);
}

TEST_CASE("YOLO pose model: tiles are refused, not ignored") {
  SpatialOptions o;
  o.model_path = tinyYolo();
  o.tiles.mode = TileMode::kOn;
  checkSays(errorOf([&] { createSpatialModel(ModelType::kYolo, o); }), {"tiles", "false"});
}

TEST_CASE("model-type auto takes a YOLO pose export for one") {
  SpatialOptions o;
  o.model_path = tinyYolo();
  CHECK(createSpatialModel(ModelType::kAuto, o)->type() == ModelType::kYolo);
}

TEST_CASE("model-type yolo without the opt-in file says how to install it and its licence") {
  const fs::path empty = fs::temp_directory_path() / "jointflow_no_opt_in_models";
  fs::create_directories(empty);
  const ModelsDir dir(empty.string());
  const std::vector<std::string> says = {"opt-in/yolo11n_pose.onnx", empty.string(),
                                         "make models-yolo", "AGPL-3.0"};
  checkSays(errorOf([] { createSpatialModel(ModelType::kYolo, {}); }), says);
  // The same through the settings, as --model-type yolo and model-type=yolo give them.
  TrackerSettings s;
  s.model_type = parseEnum<ModelType>("yolo");
  checkSays(errorOf([&] { Tracker t(s); }), says);
}

TEST_CASE("a model file of another type names both types") {
  const std::string movenet = test::modelsDir() + "/movenet_multipose.onnx";
  JF_REQUIRE_PATH_OR_SKIP(movenet);
  SpatialOptions o;
  SECTION("the MoveNet file as model-type yolo") {
    o.model_path = movenet;
    CHECK_THROWS_WITH(createSpatialModel(ModelType::kYolo, o),
                      Catch::Contains(movenet) && Catch::Contains("not a YOLO pose") &&
                          Catch::Contains("those of a movenet model, not of a yolo model"));
  }
  SECTION("a YOLO pose file as model-type movenet") {
    o.model_path = tinyYolo();
    CHECK_THROWS_WITH(createSpatialModel(ModelType::kMoveNet, o),
                      Catch::Contains(o.model_path) && Catch::Contains("not a MoveNet") &&
                          Catch::Contains("those of a yolo model, not of a movenet model"));
  }
  SECTION("an Ultralytics detection export (84 values per anchor) as model-type yolo") {
    const cv::Mat detection(std::vector<int>{1, 84, 84}, CV_32F, cv::Scalar(0));
    o.model_path = writeTemp("jointflow_tiny_yolo_detect.onnx",
                             test::constantSequenceOnnx("output0", detection));
    CHECK_THROWS_WITH(createSpatialModel(ModelType::kYolo, o),
                      Catch::Contains(o.model_path) && Catch::Contains("{1, 56, N}"));
  }
}

TEST_CASE("Tracker on the YOLO pose model: auto is oks, tff is refused") {
  TrackerSettings s;
  s.model_type = ModelType::kYolo;
  s.spatial.model_path = tinyYolo();
  s.spatial.input_size = InputSize::parse("native");
  s.similarity = SimilarityType::kAuto;
  Tracker auto_tracker(s);
  CHECK_FALSE(auto_tracker.hasTff());
  const cv::Mat frame = redFrame({512, 384});
  // All 65 people of the tiny model's output: max_persons (100) does not cut them.
  CHECK(auto_tracker.process(frame, PixelOrder::kBGR, 0.0).size() == 65);
  CHECK(auto_tracker.process(frame, PixelOrder::kBGR, 0.04).size() == 65);

  const std::vector<std::string> refusal = {"yolo spatial model has none", "oks"};
  s.similarity = SimilarityType::kTff;
  checkSays(errorOf([&] { Tracker t(s); }), refusal);
  s.similarity = SimilarityType::kAuto;  // a TFF file named in the settings must load
  s.tff_model = test::modelsDir() + "/tff_movenet.onnx";
  checkSays(errorOf([&] { Tracker t(s); }), refusal);
}
