// spatial-bench: per-frame forward and decode time of each spatial model at 256 px (letterboxed)
// and at native size on vtest.avi. Decoding (copying the heads, decoding, mapping to the frame)
// must stay under 5 % of the forward pass. Prints a Markdown table and writes it to a file.
//
//   spatial-bench [--video vtest.avi] [--frames 20] [--out docs/bench-spatial.md]
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <thread>

#include <CLI/CLI.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/videoio.hpp>

#include "jointflow/error.hpp"
#include "jointflow/spatial_model.hpp"

namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// The 1-minute load average (Linux), to tell timings taken on a busy machine; "?" elsewhere.
std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string first;
  return in >> first ? first : "?";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Forward and decode time of the spatial models"};
  std::string video = JOINTFLOW_VTEST_AVI, out = "docs/bench-spatial.md";
  int frames = 20;
  app.add_option("--video", video, "video file (default: opencv-doc's vtest.avi)");
  app.add_option("--frames", frames, "timed frames per configuration")->check(CLI::Range(1, 10000));
  app.add_option("--out", out, "Markdown file to write (empty: none)");
  CLI11_PARSE(app, argc, argv);

  try {
    cv::VideoCapture cap(video);
    if (!cap.isOpened()) throw jointflow::Error("cannot open the video " + video);
    std::vector<cv::Mat> images;
    for (int i = 0; i < frames + 2; ++i) {
      cv::Mat f;
      if (!cap.read(f)) break;
      images.push_back(f);
    }
    if (images.size() < 3)
      throw jointflow::Error("the video " + video + " has fewer than 3 frames");

    std::ostringstream table;
    table << "| model | input | network input | load (ms, this / a 2nd instance) | forward "
             "(ms/frame) | "
             "decode (ms/frame) | decode / forward | people/frame |\n"
          << "|---|---|---|---|---|---|---|---|\n";
    for (const std::string type : {"movenet", "posenet"}) {
      for (const std::string size : {"256x256", "native"}) {
        jointflow::SpatialOptions o;
        o.input_size = jointflow::InputSize::parse(size);
        auto t0 = std::chrono::steady_clock::now();
        auto model =
            jointflow::createSpatialModel(jointflow::parseEnum<jointflow::ModelType>(type), o);
        const double load_first = msSince(t0);
        t0 = std::chrono::steady_clock::now();
        auto again =
            jointflow::createSpatialModel(jointflow::parseEnum<jointflow::ModelType>(type), o);
        const double load_again = msSince(t0);
        again.reset();
        const auto first = model->estimate(images[0]);  // warm-up: allocations, first-run setup
        model->estimate(images[1]);
        double forward = 0, decode = 0, people = 0;
        const size_t n = images.size() - 2;
        for (size_t i = 2; i < images.size(); ++i) {
          const auto r = model->estimate(images[i]);
          const auto t = model->lastTimings();
          forward += t.forward_ms;
          decode += t.decode_ms;
          people += static_cast<double>(r.poses.size());
        }
        const cv::Size grid(first.beliefs.size[3], first.beliefs.size[2]);
        // Network input from the output grid: MoveNet input = 4 * grid, PoseNet = 16 (grid - 1)
        // + 1.
        auto side = [&](int cells) { return type == "movenet" ? 4 * cells : 16 * (cells - 1) + 1; };
        std::ostringstream input;
        input << side(grid.width) << "x" << side(grid.height);
        table << std::fixed << std::setprecision(1) << "| " << type << " | " << size << " | "
              << input.str() << " | " << load_first << " / " << load_again << " | " << forward / n
              << " | " << std::setprecision(2) << decode / n << " | " << std::setprecision(1)
              << 100.0 * decode / forward << " % | " << people / n << " |\n";
      }
    }
    std::ostringstream doc;
    doc << "# Spatial models: forward and decode time\n\n"
        << "Written by `build/bench/spatial-bench` (bench/spatial_bench.cpp): " << images.size() - 2
        << " frames of " << video.substr(video.find_last_of('/') + 1) << " (" << images[0].cols
        << "x" << images[0].rows << ") after 2 warm-up frames, OpenCV " << CV_VERSION
        << " dnn on the CPU, " << cv::getNumThreads() << " threads, "
        << std::thread::hardware_concurrency() << " cores, load average before the run "
        << loadAverage() << ". `256x256` letterboxes the frame; "
        << "`native` pads it to the model's size multiple. Decode = copying the output heads, "
        << "the sigmoid (PoseNet), decoding and mapping the poses to the frame. Load = creating "
        << "a SpatialModel, including one small probe forward pass (the first row also pays "
        << "OpenCV's one-time set-up), then a second instance of it (file bytes shared).\n\n"
        << table.str();
    std::cout << doc.str();
    if (!out.empty()) {
      std::ofstream file(out);
      if (!(file << doc.str())) throw jointflow::Error("cannot write " + out);
    }
  } catch (const std::exception& e) {
    std::cerr << "spatial-bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
