// The OpenPose-style spatial model end to end: a tiny ONNX model (written by the test) outputs
// belief maps and PAFs rendered from known poses; the model must return those poses in frame
// pixels, through the letterbox and grid transform.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "jointflow/error.hpp"
#include "jointflow/spatial_model.hpp"
#include "onnx_writer.hpp"
#include "render_maps.hpp"

using namespace jointflow;

namespace {

std::string writeTemp(const std::string& name, const std::string& bytes) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

Poses knownPoses() {
  Poses truth(2);
  const float shape[kNumJoints][2] = {
      {0, 0},       {-0.7f, -0.5f}, {0.7f, -0.5f}, {-1.4f, 0.1f},  {1.4f, 0.1f}, {-2.2f, 2.6f},
      {2.2f, 2.6f}, {-3.1f, 5.2f},  {3.1f, 5.2f},  {-3.3f, 7.9f},  {3.3f, 7.9f}, {-1.3f, 8.3f},
      {1.3f, 8.3f}, {-1.5f, 11.8f}, {1.5f, 11.8f}, {-1.6f, 15.2f}, {1.6f, 15.2f}};
  const cv::Point2f origin[2] = {{6.4f, 3.3f}, {17.2f, 4.1f}};
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < kNumJoints; ++j) {
      truth[i].keypoints[j] = {origin[i].x + shape[j][0], origin[i].y + shape[j][1], 1.f};
    }
  }
  return truth;
}

}  // namespace

TEST_CASE("OpenPose model: decoded poses equal the poses its maps were rendered from") {
  const cv::Size grid(24, 21);
  const Poses truth = knownPoses();
  const cv::Mat beliefs = test::renderBeliefs(truth, grid, 1.f);
  const cv::Mat pafs = test::renderPafs(truth, kCocoSkeleton, grid, 1.f);
  const std::string path =
      writeTemp("jointflow_tiny_openpose.onnx",
                test::constantMapsOnnx({{"beliefs", beliefs}, {"pafs", pafs}}));
  SpatialOptions o;
  o.model_path = path;
  o.input_size = InputSize::parse("native");
  auto model = createSpatialModel(ModelType::kAuto, o);
  REQUIRE(model->type() == ModelType::kOpenPose);
  CHECK(model->featureChannels() == 2 * static_cast<int>(kCocoSkeleton.size()));

  // A frame of 8x the grid: input = frame (a multiple of 8), stride 8. The first channel must
  // be 255 for the tiny model's output to be exactly its maps (its contract, not OpenPose's).
  for (const int zoom : {1, 2}) {
    INFO("frame = " << zoom << " x input");
    const cv::Mat frame(grid.height * 8 * zoom, grid.width * 8 * zoom, CV_8UC3,
                        cv::Scalar(0, 0, 255));
    o.input_size = zoom == 1 ? InputSize::parse("native") : InputSize::parse("192x168");
    model = createSpatialModel(ModelType::kOpenPose, o);
    const SpatialResult r = model->estimate(frame, PixelOrder::kBGR);
    REQUIRE(r.beliefs.size[1] == kNumJoints);
    REQUIRE(r.beliefs.size[2] == grid.height);
    REQUIRE(r.beliefs.size[3] == grid.width);
    REQUIRE(r.poses.size() == 2);
    Poses got = r.poses;
    std::sort(got.begin(), got.end(),
              [](const Pose& a, const Pose& b) { return a.keypoints[0].x < b.keypoints[0].x; });
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < kNumJoints; ++j) {
        INFO("person " << i << " joint " << j);
        // input pixel = 8 * cell; frame = (input + 0.5) * zoom - 0.5
        const float ex = (8.f * truth[i].keypoints[j].x + 0.5f) * zoom - 0.5f;
        const float ey = (8.f * truth[i].keypoints[j].y + 0.5f) * zoom - 0.5f;
        CHECK(got[i].keypoints[j].x == Approx(ex).margin(0.01 * zoom));
        CHECK(got[i].keypoints[j].y == Approx(ey).margin(0.01 * zoom));
        CHECK(got[i].keypoints[j].score > 0.5f);
      }
    }
  }
}

TEST_CASE("OpenPose model: a model without beliefs and PAFs is refused, naming the file") {
  const cv::Mat maps(std::vector<int>{1, 17, 4, 4}, CV_32F, cv::Scalar(0));
  const std::string path =
      writeTemp("jointflow_not_openpose.onnx", test::constantMapsOnnx({{"heatmaps", maps}}));
  SpatialOptions o;
  o.model_path = path;
  REQUIRE_THROWS_WITH(createSpatialModel(ModelType::kOpenPose, o),
                      Catch::Contains(path) && Catch::Contains("expected outputs beliefs pafs"));
  REQUIRE_THROWS_WITH(createSpatialModel(ModelType::kAuto, o),
                      Catch::Contains(path) && Catch::Contains("not a known pose model"));
}
