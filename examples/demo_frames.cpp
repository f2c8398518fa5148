// demo_frames: runs MoveNet on 10 frames of a video, spread over its length, and writes each
// frame with the estimated skeletons drawn on it as OUTDIR/frame_NNNN.png (`make demo` until the
// GStreamer pipeline exists).
//
//   demo_frames VIDEO OUTDIR [--frames N] [--input-size native|WxH|max:N]
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "jointflow/error.hpp"
#include "jointflow/spatial_model.hpp"

namespace {

void drawPose(cv::Mat& img, const jointflow::Pose& pose, const cv::Scalar& colour) {
  auto pt = [&](int j) { return cv::Point2f(pose.keypoints[j].x, pose.keypoints[j].y); };
  for (const auto& [a, b] : jointflow::kCocoSkeleton) {
    if (pose.keypoints[a].score > 0.f && pose.keypoints[b].score > 0.f) {
      cv::line(img, pt(a), pt(b), colour, 2, cv::LINE_AA);
    }
  }
  for (int j = 0; j < jointflow::kNumJoints; ++j) {
    if (pose.keypoints[j].score > 0.f) cv::circle(img, pt(j), 3, colour, cv::FILLED, cv::LINE_AA);
  }
  std::ostringstream label;
  label << std::fixed << std::setprecision(2) << pose.score;
  cv::putText(img, label.str(), {static_cast<int>(pose.box.x), static_cast<int>(pose.box.y) - 3},
              cv::FONT_HERSHEY_SIMPLEX, 0.4, colour, 1, cv::LINE_AA);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Draws MoveNet's poses on frames of a video"};
  std::string video, outdir, input_size = "native";
  int frames = 10;
  app.add_option("video", video, "video file")->required();
  app.add_option("outdir", outdir, "folder for the annotated PNG files")->required();
  app.add_option("--frames", frames, "number of frames")->check(CLI::Range(1, 1000));
  app.add_option("--input-size", input_size, "native (default: small people), WxH or max:N");
  CLI11_PARSE(app, argc, argv);

  try {
    cv::VideoCapture cap(video);
    if (!cap.isOpened()) throw jointflow::Error("cannot open the video " + video);
    const int total = static_cast<int>(cap.get(cv::CAP_PROP_FRAME_COUNT));
    jointflow::SpatialOptions options;
    options.input_size = jointflow::InputSize::parse(input_size);
    auto model = jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, options);
    std::filesystem::create_directories(outdir);
    const std::vector<cv::Scalar> colours = {{0, 255, 0},   {255, 128, 0}, {0, 128, 255},
                                             {255, 0, 255}, {0, 255, 255}, {255, 255, 0},
                                             {128, 0, 255}, {0, 0, 255}};
    for (int i = 0; i < frames; ++i) {
      const int index = total > frames ? i * (total / frames) : i;
      cap.set(cv::CAP_PROP_POS_FRAMES, index);
      cv::Mat frame;
      if (!cap.read(frame)) break;
      const auto result = model->estimate(frame);
      for (size_t p = 0; p < result.poses.size(); ++p)
        drawPose(frame, result.poses[p], colours[p % colours.size()]);
      std::ostringstream name;
      name << outdir << "/frame_" << std::setw(4) << std::setfill('0') << index << ".png";
      if (!cv::imwrite(name.str(), frame)) throw jointflow::Error("cannot write " + name.str());
      std::cout << name.str() << ": " << result.poses.size() << " people\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "demo_frames: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
