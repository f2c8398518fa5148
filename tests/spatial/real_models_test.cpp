// The shipped MoveNet and PoseNet models on real images (vtest.avi from opencv-doc; the Bonn
// PoseTrack sequence from ../shared/data, skipped where absent).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <opencv2/dnn.hpp>

#include "../test_env.hpp"
#include "../vtest_frame.hpp"
#include "bonn_eval.hpp"
#include "held_maps.hpp"
#include "jointflow/error.hpp"
#include "jointflow/letterbox.hpp"
#include "jointflow/model_bytes.hpp"
#include "jointflow/spatial_model.hpp"

using namespace jointflow;

namespace {

using test::vtestFrame;

std::string model(const std::string& file) {
  return test::modelsDir() + "/" + file;
}

int confident(const Poses& poses, float score) {
  return static_cast<int>(std::count_if(poses.begin(), poses.end(), [&](const Pose& p) {
    return p.score >= score && p.countVisible(0.3f) >= 8;
  }));
}

}  // namespace

TEST_CASE("MoveNet at native size finds the people of vtest.avi frame 200") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  SpatialOptions o;
  o.input_size = InputSize::parse("native");
  auto m = createSpatialModel(ModelType::kMoveNet, o);
  const cv::Mat frame = vtestFrame(200);
  const SpatialResult r = m->estimate(frame);
  WARN("MoveNet native, vtest frame 200: " << r.poses.size() << " poses, "
                                           << confident(r.poses, 0.3f)
                                           << " with score >= 0.3 and >= 8 joints");
  // Frame 200 shows 7 people; measured: 7 found, all 7 with score >= 0.3 and >= 8 joints.
  CHECK(r.poses.size() >= 7);
  CHECK(confident(r.poses, 0.3f) >= 6);
  for (const auto& p : r.poses) {
    CHECK(p.box.x + p.box.w > 0);
    CHECK(p.box.x < frame.cols);
  }
  // Maps: one stride-4 grid, beliefs in [0, 1], transform = the letterbox's.
  REQUIRE(r.beliefs.size[1] == kNumJoints);
  REQUIRE(r.features.size[1] == m->featureChannels());
  CHECK(m->featureChannels() == 24);
  CHECK(r.beliefs.size[2] == r.features.size[2]);
  CHECK(r.beliefs.size[3] == r.features.size[3]);
  CHECK(r.beliefs.size[2] == 576 / 4);
  double lo, hi;
  cv::minMaxIdx(r.beliefs, &lo, &hi);
  CHECK(lo >= 0.0);
  CHECK(hi <= 1.0);
  CHECK(r.grid_to_frame.scale_x == Approx(4.f));
  CHECK(r.frame_size == frame.size());
}

TEST_CASE("cv::dnn: a frame's maps stay as they were while the caller holds them") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  SpatialOptions o;
  o.input_size = InputSize::parse("256x256");
  auto m = createSpatialModel(ModelType::kMoveNet, o);
  test::checkHeldMapsKept(*m, {vtestFrame(10), vtestFrame(60), vtestFrame(110), vtestFrame(160)});
}

TEST_CASE("Poses follow the frame: a shifted frame gives the same poses, shifted") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  // The frame placed at (64, 32) in a larger canvas: a shift by whole network strides (32), so
  // the network sees the same content, except near the frame's border (zero padding of the
  // convolutions there, black canvas here): people at least 100 px inside the frame must come
  // back within a quarter pixel. An error in the padding or grid mapping would show here.
  const cv::Mat frame = vtestFrame(200);
  cv::Mat canvas(frame.rows + 64, frame.cols + 96, CV_8UC3, cv::Scalar::all(0));
  frame.copyTo(canvas(cv::Rect(64, 32, frame.cols, frame.rows)));
  SpatialOptions o;
  o.input_size = InputSize::parse("native");
  o.tiles.mode = TileMode::kOff;  // one run of each: the tiles of the canvas lie elsewhere
  auto m = createSpatialModel(ModelType::kMoveNet, o);
  const Poses a = m->estimate(frame).poses;
  const Poses b = m->estimate(canvas).poses;
  REQUIRE(a.size() >= 6);
  int inside = 0, matched = 0;
  for (const auto& p : a) {
    const Box k = p.keypointBox(0.f);
    if (k.x < 100 || k.y < 100 || k.x + k.w > frame.cols - 100 || k.y + k.h > frame.rows - 100)
      continue;
    ++inside;
    for (const auto& q : b) {
      const float dx = q.keypoints[kLeftHip].x - 64.f - p.keypoints[kLeftHip].x;
      const float dy = q.keypoints[kLeftHip].y - 32.f - p.keypoints[kLeftHip].y;
      if (dx * dx + dy * dy > 4.f) continue;
      ++matched;
      for (int j = 0; j < kNumJoints; ++j) {
        if (p.keypoints[j].score < 0.3f) continue;
        CHECK(q.keypoints[j].x - 64.f == Approx(p.keypoints[j].x).margin(0.25));
        CHECK(q.keypoints[j].y - 32.f == Approx(p.keypoints[j].y).margin(0.25));
      }
    }
  }
  CHECK(inside >= 3);
  CHECK(matched == inside);
}

TEST_CASE("PoseNet finds people in vtest.avi, beliefs and features on its stride-16 grid") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  SpatialOptions o;
  o.input_size = InputSize::parse("native");
  o.part_threshold = 0.3f;
  auto m = createSpatialModel(ModelType::kPoseNet, o);
  const SpatialResult r = m->estimate(vtestFrame(200));
  WARN("PoseNet native, vtest frame 200: " << r.poses.size() << " poses");
  CHECK(r.poses.size() >= 4);
  CHECK(m->featureChannels() == 384);
  REQUIRE(r.beliefs.size[2] == (577 - 1) / 16 + 1);
  REQUIRE(r.beliefs.size[3] == (769 - 1) / 16 + 1);
  CHECK(r.features.size[2] == r.beliefs.size[2]);
  double lo, hi;
  cv::minMaxIdx(r.beliefs, &lo, &hi);
  CHECK(lo >= 0.0);
  CHECK(hi <= 1.0);
  CHECK(r.grid_to_frame.scale_x == Approx(16.f));
}

TEST_CASE("Multi-scale MoveNet: maps on the grid of scale 1, people still found") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  SpatialOptions o;
  o.input_size = InputSize::parse("native");
  o.scales = {0.75f, 1.f, 1.25f};
  auto m = createSpatialModel(ModelType::kMoveNet, o);
  const SpatialResult r = m->estimate(vtestFrame(200));
  WARN("MoveNet native x {0.75, 1, 1.25}, vtest frame 200: "
       << confident(r.poses, 0.2f) << " poses with score >= 0.2, >= 8 joints");
  CHECK(r.beliefs.size[2] == 576 / 4);
  CHECK(r.beliefs.size[3] == 768 / 4);
  CHECK(confident(r.poses, 0.2f) >= 6);
}

TEST_CASE("MoveNet at the default settings finds the people of the Bonn sequence", "[data]") {
  const std::string root = test::dataDir() + "/bonn-posetrack";
  const std::string gt = root + "/annotations/test/060470979_bonn_test.json";
  JF_REQUIRE_PATH_OR_SKIP(gt);
  auto m = createSpatialModel(ModelType::kMoveNet, SpatialOptions{});
  const test::FoundCount c = test::countFound(*m, root, gt);
  WARN("MoveNet " << m->options().input_size.toString() << " on Bonn: " << c.found << " of "
                  << c.total << " GT people found (" << 100.0 * c.rate() << " %), " << c.predictions
                  << " predictions");
  CHECK(c.total == 164);
  // Measured at the default max:640: 161 of 164 (98.2 %), 164 predictions.
  CHECK(c.rate() >= 0.95);
  CHECK(c.predictions <= 180);
}

TEST_CASE("Bad models are refused at load, naming the file and what was expected") {
  SpatialOptions o;
  SECTION("missing file") {
    o.model_path = "/nonexistent/movenet.onnx";
    REQUIRE_THROWS_WITH(
        createSpatialModel(ModelType::kMoveNet, o),
        Catch::Contains("/nonexistent/movenet.onnx") && Catch::Contains("does not exist"));
  }
  SECTION("truncated file") {
    const std::string src = model("movenet_multipose.onnx");
    JF_REQUIRE_PATH_OR_SKIP(src);
    const auto bytes = sharedModelBytes(src);
    const std::string path =
        (std::filesystem::temp_directory_path() / "jointflow_truncated.onnx").string();
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes->data()), 100000);
    o.model_path = path;
    REQUIRE_THROWS_WITH(
        createSpatialModel(ModelType::kMoveNet, o),
        Catch::Contains(path) && Catch::Contains("not an ONNX model that OpenCV can load"));
  }
  SECTION("PoseNet given as MoveNet, and the reverse") {
    o.model_path = model("posenet_mobilenetv1.onnx");
    JF_REQUIRE_PATH_OR_SKIP(o.model_path);
    REQUIRE_THROWS_WITH(createSpatialModel(ModelType::kMoveNet, o),
                        Catch::Contains(o.model_path) &&
                            Catch::Contains("is not a MoveNet MultiPose model") &&
                            Catch::Contains("expected outputs center heatmaps regression"));
    o.model_path = model("movenet_multipose.onnx");
    REQUIRE_THROWS_WITH(createSpatialModel(ModelType::kPoseNet, o),
                        Catch::Contains(o.model_path) && Catch::Contains("displacement_fwd"));
    CHECK(createSpatialModel(ModelType::kAuto, o)->type() == ModelType::kMoveNet);
  }
  SECTION("unknown type, or a backend this OpenCV lacks") {
    REQUIRE_THROWS_WITH(parseEnum<ModelType>("hrnet"),
                        Catch::Contains("unknown spatial model type 'hrnet'") &&
                            Catch::Contains("auto, movenet, posenet, openpose or yolo"));
    EngineOptions cuda_engine;
    cuda_engine.backend = DnnBackend::kCuda;
    cuda_engine.target = DnnTarget::kCuda;
    const auto cuda = cv::dnn::getAvailableTargets(cv::dnn::DNN_BACKEND_CUDA);
    if (cuda.empty()) {
      REQUIRE_THROWS_WITH(
          createSpatialModel(ModelType::kMoveNet, o, cuda_engine),
          Catch::Contains("\"cuda\"") && Catch::Contains("not available in this OpenCV"));
    }
    REQUIRE_THROWS_WITH(parseEnum<DnnBackend>("tpu"), Catch::Contains("unknown dnn backend 'tpu'"));
  }
  SECTION("nonsense options") {
    o.scales = {};
    REQUIRE_THROWS_WITH(createSpatialModel(ModelType::kMoveNet, o),
                        Catch::Contains("scales is empty"));
    o.scales = {1.f};
    o.max_persons = 0;
    REQUIRE_THROWS_WITH(createSpatialModel(ModelType::kMoveNet, o),
                        Catch::Contains("max_persons must be in [1, 1000], got 0"));
    // The ranges are the settings schema's (kMaxPersonsLimit, kMaxScale): a direct caller meets
    // the same limits as a property or an option.
    o.max_persons = kMaxPersonsLimit + 1;
    REQUIRE_THROWS_WITH(createSpatialModel(ModelType::kMoveNet, o), Catch::Contains("got 1001"));
    o.max_persons = 10;
    o.scales = {kMaxScale * 1.5f};
    REQUIRE_THROWS_WITH(
        createSpatialModel(ModelType::kMoveNet, o),
        Catch::Contains("inference scale 6.0") && Catch::Contains("is not in (0, 4"));
  }
}

TEST_CASE("Bad images give clear errors") {
  JF_REQUIRE_PATH_OR_SKIP(model("movenet_multipose.onnx"));
  for (const std::string type : {"movenet", "posenet"}) {
    INFO(type);
    auto m = createSpatialModel(parseEnum<ModelType>(type), SpatialOptions{});
    REQUIRE_THROWS_WITH(m->estimate(cv::Mat()), Catch::Contains("image is empty"));
    REQUIRE_THROWS_WITH(m->estimate(cv::Mat(1, 1, CV_8UC3, cv::Scalar::all(0))),
                        Catch::Contains("1x1 pixels is too small"));
    REQUIRE_THROWS_WITH(
        m->estimate(cv::Mat(64, 64, CV_8UC1, cv::Scalar(0))),
        Catch::Contains("expected an 8-bit 3-channel image") && Catch::Contains("got 1 channel"));
    REQUIRE_THROWS_WITH(m->estimate(cv::Mat(64, 64, CV_8UC4, cv::Scalar::all(0))),
                        Catch::Contains("got 4 channel"));
    REQUIRE_THROWS_WITH(m->estimate(cv::Mat(64, 64, CV_32FC3, cv::Scalar::all(0))),
                        Catch::Contains("depth 5"));
    // A tiny but valid image: no people, no crash.
    CHECK(m->estimate(cv::Mat(16, 16, CV_8UC3, cv::Scalar::all(90))).poses.size() <= 1);
  }
}

TEST_CASE("Model bytes are read once per process and shared") {
  const std::string path = model("posenet_mobilenetv1.onnx");
  JF_REQUIRE_PATH_OR_SKIP(path);
  CHECK(sharedModelBytes(path).get() == sharedModelBytes(path).get());
  SpatialOptions o;
  o.model_path = path;
  auto a = createSpatialModel(ModelType::kPoseNet, o);
  auto b = createSpatialModel(ModelType::kPoseNet, o);  // a second instance: its own Net
  const cv::Mat frame(129, 129, CV_8UC3, cv::Scalar::all(128));
  CHECK(a->estimate(frame).poses.size() == b->estimate(frame).poses.size());
}
