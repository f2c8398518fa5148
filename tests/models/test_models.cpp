// The shipped pose models (models/*.onnx) load in the system OpenCV 4.6 dnn and produce the output
// names and shapes documented in models/README.md, at two input sizes from one cv::dnn::Net.
// Checksums are checked by the separate meson test `models-sha256` (sha256sum -c SHA256SUMS).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "test_env.hpp"

namespace {

struct OutputSpec {
  std::string name;
  int channels;
};

// MoveNet: stride 4, H and W multiples of 32. PoseNet: stride 16, H and W = 16k + 1.
const std::vector<OutputSpec> kMoveNetOutputs = {
    {"center", 1},    {"heatmaps", 17},  {"regression", 34}, {"offsets", 34},
    {"box_scale", 2}, {"box_offset", 2}, {"features", 24}};
const std::vector<OutputSpec> kPoseNetOutputs = {{"heatmaps", 17},
                                                 {"offsets", 34},
                                                 {"displacement_fwd", 32},
                                                 {"displacement_bwd", 32},
                                                 {"features", 384}};

std::string modelPath(const std::string& file) {
  return (std::filesystem::path(jointflow::test::modelsDir()) / file).string();
}

// vtest.avi frame 200 (768x576), or a deterministic gradient image when the sample is absent.
cv::Mat testFrame() {
  cv::VideoCapture cap(jointflow::test::vtestPath());
  cv::Mat frame;
  if (cap.isOpened()) {
    cap.set(cv::CAP_PROP_POS_FRAMES, 200);
    cap.read(frame);
  }
  if (frame.empty()) {
    frame.create(576, 768, CV_8UC3);
    for (int y = 0; y < frame.rows; ++y)
      for (int x = 0; x < frame.cols; ++x)
        frame.at<cv::Vec3b>(y, x) = cv::Vec3b(x % 256, y % 256, (x + y) % 256);
  }
  return frame;
}

// RGB float NCHW blob of size h x w: the frame scaled to fit (aspect kept), top-left aligned,
// zero padded; then value * scale + shift.
cv::Mat makeBlob(const cv::Mat& bgr, int h, int w, double scale, double shift) {
  const double s = std::min(double(h) / bgr.rows, double(w) / bgr.cols);
  cv::Mat resized;
  cv::resize(bgr, resized, cv::Size(int(std::lround(bgr.cols * s)), int(std::lround(bgr.rows * s))),
             0, 0, cv::INTER_AREA);
  cv::Mat canvas(h, w, CV_8UC3, cv::Scalar::all(0));
  resized.copyTo(canvas(cv::Rect(0, 0, std::min(w, resized.cols), std::min(h, resized.rows))));
  cv::Mat blob = cv::dnn::blobFromImage(canvas, 1.0, cv::Size(), cv::Scalar(), /*swapRB=*/true);
  if (scale != 1.0 || shift != 0.0) blob = blob * scale + shift;
  return blob;
}

std::vector<cv::Mat> forwardTimed(cv::dnn::Net& net, const cv::Mat& blob,
                                  const std::vector<std::string>& names, const std::string& label) {
  std::vector<cv::Mat> outs;
  net.setInput(blob);
  net.forward(outs, names);  // first run at a new size allocates
  const auto t0 = std::chrono::steady_clock::now();
  net.setInput(blob);
  net.forward(outs, names);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "[models] " << label << " forward " << ms << " ms (" << cv::getNumThreads()
            << " threads)\n";
  return outs;
}

void checkShapes(const std::vector<cv::Mat>& outs, const std::vector<OutputSpec>& spec, int gh,
                 int gw) {
  REQUIRE(outs.size() == spec.size());
  for (size_t i = 0; i < spec.size(); ++i) {
    INFO("output " << spec[i].name);
    const cv::Mat& m = outs[i];
    REQUIRE(m.dims == 4);
    CHECK(m.type() == CV_32F);
    CHECK(m.size[0] == 1);
    CHECK(m.size[1] == spec[i].channels);
    CHECK(m.size[2] == gh);
    CHECK(m.size[3] == gw);
    CHECK(cv::checkRange(m));  // no NaN / Inf
  }
}

std::vector<std::string> names(const std::vector<OutputSpec>& spec) {
  std::vector<std::string> n;
  for (const auto& s : spec) n.push_back(s.name);
  return n;
}

// Number of 5x5 local maxima above `thr` in a [1,1,h,w] map.
int countPeaks(const cv::Mat& map4d, float thr) {
  cv::Mat m(map4d.size[2], map4d.size[3], CV_32F, const_cast<float*>(map4d.ptr<float>()));
  cv::Mat dil;
  cv::dilate(m, dil, cv::Mat::ones(5, 5, CV_8U));
  int n = 0;
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x)
      if (m.at<float>(y, x) > thr && m.at<float>(y, x) >= dil.at<float>(y, x)) ++n;
  return n;
}

}  // namespace

TEST_CASE("MoveNet MultiPose ONNX loads and gives the documented outputs", "[models]") {
  const std::string path = modelPath("movenet_multipose.onnx");
  REQUIRE(std::filesystem::exists(path));
  cv::dnn::Net net = cv::dnn::readNetFromONNX(path);
  REQUIRE(!net.empty());
  const auto outNames = names(kMoveNetOutputs);
  const cv::Mat frame = testFrame();

  // RGB 0..255, normalised inside the graph; stride 4.
  for (const auto& hw : std::vector<std::pair<int, int>>{{256, 256}, {576, 768}}) {
    const auto [h, w] = hw;
    DYNAMIC_SECTION("input " << h << "x" << w) {
      const cv::Mat blob = makeBlob(frame, h, w, 1.0, 0.0);
      const auto outs = forwardTimed(net, blob, outNames,
                                     "movenet " + std::to_string(h) + "x" + std::to_string(w));
      checkShapes(outs, kMoveNetOutputs, h / 4, w / 4);
      double lo, hi;
      for (int i : {0, 1}) {  // center and heatmaps are sigmoid outputs
        cv::minMaxLoc(outs[i].reshape(1, 1), &lo, &hi);
        CHECK(lo >= 0.0);
        CHECK(hi <= 1.0);
      }
      if (h == 576) {
        // vtest frame 200 shows 7 people; at native size MoveNet finds them with high scores.
        CHECK(countPeaks(outs[0], 0.4f) >= 5);
      }
    }
  }
}

TEST_CASE("PoseNet MobileNetV1 ONNX loads and gives the documented outputs", "[models]") {
  const std::string path = modelPath("posenet_mobilenetv1.onnx");
  REQUIRE(std::filesystem::exists(path));
  cv::dnn::Net net = cv::dnn::readNetFromONNX(path);
  REQUIRE(!net.empty());
  const auto outNames = names(kPoseNetOutputs);
  const cv::Mat frame = testFrame();

  // RGB scaled to [-1, 1] outside the graph; stride 16, sizes 16k + 1.
  for (const auto& hw : std::vector<std::pair<int, int>>{{257, 257}, {577, 769}}) {
    const auto [h, w] = hw;
    DYNAMIC_SECTION("input " << h << "x" << w) {
      const cv::Mat blob = makeBlob(frame, h, w, 1.0 / 127.5, -1.0);
      const auto outs = forwardTimed(net, blob, outNames,
                                     "posenet " + std::to_string(h) + "x" + std::to_string(w));
      checkShapes(outs, kPoseNetOutputs, (h - 1) / 16 + 1, (w - 1) / 16 + 1);
      double lo, hi;
      cv::minMaxLoc(outs[4].reshape(1, 1), &lo, &hi);  // features come out of a ReLU6
      CHECK(lo >= 0.0);
      CHECK(hi <= 6.0);
    }
  }
}
