// jointflow-bench: the performance budgets of issues 7 and 13, all measured in one run on one
// machine, for each engine (cv::dnn, and OpenVINO where the build has it).
//
//   1. jointflowtrack end to end against the bare spatial network at the same input size
//      (overhead, target <= 1.05), at 256x256, max:640 and native, with where the time goes
//      (pre-processing, forward, decoding, camera motion, association, GStreamer); OpenVINO's
//      speed-up over cv::dnn end to end; what the held frame (async-inference) gains, with the
//      frames coming raw from another thread and decoded in the element's own thread;
//   2. the TFF network against the spatial network (target <= 0.25);
//   3. cv::dnn, OpenVINO and onnxruntime on the same ONNX file and input shape, with cv::dnn's
//      time per layer type (Net::getPerfProfile) to show where it goes;
//   4. frames/s and memory of 1 and 4 streams; OpenVINO's streams sharing one compiled model
//      (model-instance-id) against streams with a model each;
//   5. the person counts of the two engines on the frames of vtest.avi;
//   6. a live source faster than inference.
// The machine may be shared and loaded: every comparison takes turns between what it compares,
// block by block or run by run, in one process, and reports the median of the per-round ratios,
// so that both sides see the same load. Each pipeline set-up whose memory is reported runs in a
// child process of its own (this program, --child ...). Prints Markdown and writes it to --out.
//
//   jointflow-bench [--block 6] [--rounds 4] [--runs 20] [--threads N] [--python venv/bin/python]
//                   [--ort-script bench/ort_time.py] [--out docs/benchmarks.md]
//
// The measurements are in jointflow_bench_measures.cpp, the cases that run them in
// jointflow_bench_cases.cpp, the document in jointflow_bench_document.cpp; here: the options,
// the child processes' entry points, and the order of the run.
#include <gst/gst.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include <CLI/CLI.hpp>
#include <opencv2/core/utility.hpp>

#include "jointflow/error.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow_bench_cases.hpp"
#include "jointflow_bench_document.hpp"

using namespace jointflow::bench;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  gst_init(&argc, &argv);
  CLI::App app{"JointFlow performance budgets (issues 7 and 13)"};
  BudgetSettings s;
  s.video = JOINTFLOW_VTEST_AVI;
  s.ort_script = "bench/ort_time.py";
  std::string out = "docs/benchmarks.md", child_size;
  std::string models = jointflow::defaultModelsDir();
  s.threads = static_cast<int>(std::thread::hardware_concurrency());
  int child_streams = 0;
  app.add_option("--video", s.video, "video file (default: opencv-doc's vtest.avi)");
  app.add_option("--block", s.block, "frames per block of the end-to-end rounds")
      ->check(CLI::Range(3, 1000));
  app.add_option("--rounds", s.rounds, "rounds of the end-to-end measurements (plus one warm-up)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--runs", s.runs, "runs per engine on the bare ONNX file (half at 1 thread)")
      ->check(CLI::Range(2, 100000));
  app.add_option("--stream-frames", s.stream_frames, "frames per stream (3 of them warm-up)")
      ->check(CLI::Range(6, 100000));
  app.add_option("--threads", s.threads, "threads of the engines")->check(CLI::Range(1, 256));
  app.add_option("--python", s.python, "python with onnxruntime (empty: no onnxruntime column)");
  app.add_option("--ort-script", s.ort_script, "bench/ort_time.py");
  app.add_option("--out", out, "Markdown file to write (empty: none)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);  // bench/run.sh gives a default
  app.add_option("--agreement-stride", s.agreement_stride,
                 "person counts of the two engines on every Nth frame of the video")
      ->check(CLI::Range(1, 1000));
  app.add_option("--live-seconds", s.live_seconds, "seconds of each live-source run")
      ->check(CLI::Range(2.0, 3600.0));
  app.add_option("--child", child_streams, "internal: run N pipelines, print JSON");
  app.add_option("--child-size", child_size, "internal: input-size of the child's pipelines");
  std::string child_props, child_live, child_e2e, child_backends = "default";
  app.add_option("--child-props", child_props, "internal: more jointflowtrack properties");
  app.add_option("--child-live", child_live, "internal: run the live test with this policy");
  app.add_option("--child-e2e", child_e2e, "internal: the end-to-end rounds at this input size");
  app.add_option("--child-backends", child_backends, "internal: engines of --child-e2e");
  CLI11_PARSE(app, argc, argv);
  cv::setNumThreads(s.threads);
  s.movenet = models + "/movenet_multipose.onnx";
  s.tff_path = models + "/tff_movenet.onnx";
  s.tff_used = std::filesystem::exists(s.tff_path) ? s.tff_path : "";

  try {
    // The child processes: one measurement each, its figures printed as JSON.
    if (!child_live.empty()) {
      std::cout << runLive(child_live, child_size, s.live_seconds).dump() << std::endl;
      return 0;
    }
    if (!child_e2e.empty()) {
      std::vector<std::string> backends;
      std::stringstream list(child_backends);
      for (std::string b; std::getline(list, b, ',');) backends.push_back(b);
      const auto frames = readFrames(s.video, s.block * (s.rounds + 1) + 1);
      std::cout << runEndToEnd(frames, backends, child_e2e, s.block, s.rounds, s.tff_used).dump()
                << std::endl;
      return 0;
    }
    if (child_streams > 0) {
      const auto frames = readFrames(s.video, s.stream_frames);
      std::cout
          << runPipelines(frames, child_streams, child_size, kStreamWarmup, child_props).dump()
          << std::endl;
      return 0;
    }

    const auto run_start = Clock::now();
    s.self = std::filesystem::read_symlink("/proc/self/exe").string();
    s.base = "--video '" + s.video + "' --threads " + std::to_string(s.threads);
    const std::string load_before = loadAverage();
    s.native = readFrames(s.video, 4).front().size();
    s.max640 = cv::Size(
        640, static_cast<int>(std::lround(640.0 * s.native.height / s.native.width / 32.0)) * 32);
    // The engines of this build: cv::dnn always, OpenVINO where it was built with it.
    s.engines = {{"default", "cv::dnn"}};
    try {
      jointflow::EngineOptions openvino;
      openvino.backend = jointflow::DnnBackend::kOpenVino;
      s.openvino_name =
          jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, {}, openvino)->engine();
      s.engines.emplace_back("openvino", "OpenVINO");
    } catch (const std::exception& e) {
      s.openvino_missing = e.what();
    }

    BudgetFigures figures;
    for (const BudgetCase& c : budgetCases(s)) {
      c.run(s, figures);
      figures.loads.push_back(loadAverage());
    }

    const std::string doc = budgetMarkdown(
        s, figures, std::chrono::duration<double>(Clock::now() - run_start).count() / 60.0,
        load_before);
    std::cout << doc;
    if (!out.empty()) {
      std::ofstream file(out);
      if (!file) throw jointflow::Error("cannot write " + out);
      file << doc;
      std::cout << "\nwritten to " << out << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "jointflow-bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
