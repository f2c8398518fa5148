// Model files that are broken in ways tests/spatial and tests/tracking do not cover: empty files,
// folders, bytes corrupted in the middle (a bad download or disk), and one network's file given
// for the other. Each is refused with a jointflow::Error naming the file, or, where the damage
// leaves a loadable network, gives finite poses (or an Error) and never a crash.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <opencv2/videoio.hpp>

#include "jointflow/error.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow/tff_model.hpp"
#include "jointflow/tracker.hpp"
#include "test_env.hpp"

using namespace jointflow;
namespace fs = std::filesystem;

namespace {

std::string shipped(const std::string& file) {
  return test::modelsDir() + "/" + file;
}
std::string testData(const std::string& file) {
  return test::sourceRoot() + "/tests/data/" + file;
}

std::vector<char> readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string writeTemp(const std::string& name, const std::vector<char>& bytes) {
  const std::string path = (fs::temp_directory_path() / ("jointflow-hardening-" + name)).string();
  std::ofstream(path, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

SpatialOptions optionsFor(const std::string& path) {
  SpatialOptions o;
  o.model_path = path;
  o.input_size = InputSize::parse("256x256");
  return o;
}

}  // namespace

TEST_CASE("an empty file or a folder as the model is refused, naming it", "[hardening][models]") {
  const std::string empty = writeTemp("empty.onnx", {});
  for (const std::string type : {"movenet", "posenet", "auto"}) {
    INFO(type);
    CHECK_THROWS_WITH(createSpatialModel(parseEnum<ModelType>(type), optionsFor(empty)),
                      Catch::Contains(empty));
    CHECK_THROWS_WITH(createSpatialModel(parseEnum<ModelType>(type),
                                         optionsFor(fs::temp_directory_path().string())),
                      Catch::Contains("is not a regular file"));
  }
  CHECK_THROWS_WITH(TemporalFlowModel(empty, 24), Catch::Contains(empty));
  fs::remove(empty);
}

TEST_CASE("a model corrupted in the middle: refused, or finite poses", "[hardening][models]") {
  const std::string source = shipped("movenet_multipose.onnx");
  JF_REQUIRE_PATH_OR_SKIP(source);
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  cv::VideoCapture video(test::vtestPath());
  cv::Mat frame;
  REQUIRE(video.read(frame));
  const std::vector<char> good = readAll(source);
  REQUIRE(good.size() > 100000);
  // 4 KiB of 0xFF at a quarter, half and three quarters of the file: protobuf structure or
  // weights (NaN-producing float patterns) damaged, the length unchanged.
  for (const double where : {0.25, 0.5, 0.75}) {
    INFO("corrupted at " << where);
    std::vector<char> bad = good;
    const auto at = static_cast<std::size_t>(where * static_cast<double>(bad.size()));
    std::fill(bad.begin() + at, bad.begin() + at + 4096, static_cast<char>(0xFF));
    const std::string path = writeTemp("corrupt.onnx", bad);
    std::unique_ptr<SpatialModel> model;
    try {
      model = createSpatialModel(ModelType::kMoveNet, optionsFor(path));
    } catch (const Error& e) {
      CHECK_THAT(e.what(), Catch::Contains(path));
      continue;
    }
    try {
      for (const Pose& p : model->estimate(frame).poses) {
        CHECK(std::isfinite(p.score));
        for (const Keypoint& k : p.keypoints) {
          CHECK(std::isfinite(k.x));
          CHECK(std::isfinite(k.y));
          CHECK(std::isfinite(k.score));
        }
      }
    } catch (const Error&) {
      // A clear refusal at run time is fine too.
    }
    fs::remove(path);
  }
}

TEST_CASE("one network's file given for another is refused with what was expected",
          "[hardening][models]") {
  const std::string movenet = shipped("movenet_multipose.onnx");
  JF_REQUIRE_PATH_OR_SKIP(movenet);
  SECTION("a TFF network as the spatial model") {
    const std::string tff = testData("tff_tiny_c3.onnx");
    for (const std::string type : {"movenet", "posenet", "openpose", "yolo", "auto"}) {
      INFO(type);
      CHECK_THROWS_WITH(createSpatialModel(parseEnum<ModelType>(type), optionsFor(tff)),
                        Catch::Contains(tff));
    }
  }
  SECTION("a spatial network as the TFF model") {
    CHECK_THROWS_WITH(TemporalFlowModel(movenet, 24), Catch::Contains(movenet));
    TrackerSettings s;
    s.model_type = ModelType::kMoveNet;
    s.similarity = SimilarityType::kTff;
    s.tff_model = shipped("posenet_mobilenetv1.onnx");
    CHECK_THROWS_WITH(Tracker(s), Catch::Contains(s.tff_model));
  }
}
