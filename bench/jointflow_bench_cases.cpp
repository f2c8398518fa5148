// jointflow-bench's cases (jointflow_bench_cases.hpp): what runs, in which process, in which
// order. The tables they end up in are written by jointflow_bench_document.cpp.
#include "jointflow_bench_cases.hpp"

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <memory>

#include <opencv2/core/utility.hpp>
#include <opencv2/videoio.hpp>

#include "jointflow/spatial_model.hpp"

namespace jointflow::bench {
namespace {

// 1: the element end to end, a child per input size (its memory and threads of its own).
void runEndToEndCase(const BudgetSettings& s, BudgetFigures& out) {
  const std::string backends = s.haveOpenVino() ? "default,openvino" : "default";
  for (const std::string& size : s.sizes) {
    std::cerr << "end to end at " << size << " ..." << std::endl;
    out.e2e[size] = runChild(s.self, s.base + " --child-e2e " + size + " --child-backends " +
                                         backends + " --block " + std::to_string(s.block) +
                                         " --rounds " + std::to_string(s.rounds));
  }
}

// 3: the engines on the same file, at every thread count and size; onnxruntime where --python
// gives a Python that has it.
void runEnginesCase(const BudgetSettings& s, BudgetFigures& out) {
  std::cerr << "engines on the same file ..." << std::endl;
  std::unique_ptr<OrtServer> ort;
  if (!s.python.empty()) ort = std::make_unique<OrtServer>(s.python, s.ort_script, s.movenet);
  if (ort) out.ort_version = ort->version();
  for (const int n_threads : {s.threads, 1})
    for (const cv::Size size : {cv::Size(256, 256), s.max640, s.native})
      out.engines.push_back(
          {size, n_threads,
           timeEngines(s.movenet, size, n_threads == s.threads ? s.runs : std::max(2, s.runs / 2),
                       n_threads, s.haveOpenVino(), ort.get())});
  ort.reset();
  cv::setNumThreads(s.threads);
}

// 4: streams at the default input size, a child per row (its memory from its own start).
void runStreamsCase(const BudgetSettings& s, BudgetFigures& out) {
  std::cerr << "streams ..." << std::endl;
  auto streams = [&](int k, const std::string& props) {
    return runChild(s.self, s.base + " --stream-frames " + std::to_string(s.stream_frames) +
                                " --child " + std::to_string(k) +
                                " --child-size max:640 --child-props '" + props + "'");
  };
  out.streams.push_back({"cv::dnn", streams(1, "backend=default"), ""});
  out.streams.push_back({"cv::dnn", streams(4, "backend=default"), ""});
  if (s.haveOpenVino()) {
    out.streams.push_back({"OpenVINO", streams(1, "backend=openvino"), ""});
    out.shared_streams = streams(4, "backend=openvino model-instance-id=bench");
    out.streams.push_back({"OpenVINO", out.shared_streams, " (one shared model)"});
    out.separate_streams = streams(2, "backend=openvino");
    out.streams.push_back({"OpenVINO", out.separate_streams, " (a model each)"});
    out.streams.push_back({"OpenVINO", streams(4, "backend=openvino"), " (a model each)"});
  }
}

// 5: person counts of the two engines (tests/engine checks every 6th frame of a few).
void runPersonCountsCase(const BudgetSettings& s, BudgetFigures& out) {
  std::cerr << "person counts ..." << std::endl;
  jointflow::SpatialOptions o;  // max:640
  auto dnn = jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, o);
  jointflow::EngineOptions openvino;
  openvino.backend = jointflow::DnnBackend::kOpenVino;
  auto ov = jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, o, openvino);
  cv::VideoCapture capture(s.video);
  PersonCounts c;
  cv::Mat f;
  for (int i = 0; capture.read(f); ++i) {
    ++c.total;
    if (i % s.agreement_stride) continue;
    const int a = static_cast<int>(dnn->estimate(f).poses.size());
    const int b = static_cast<int>(ov->estimate(f).poses.size());
    c.frames++;
    c.people += a;
    c.within += std::abs(a - b) <= 1;
    c.equal += a == b;
  }
  out.counts = c;
}

// 6: a live source faster than inference, a child per policy.
void runLiveCase(const BudgetSettings& s, BudgetFigures& out) {
  std::cerr << "live source ..." << std::endl;
  for (const std::string policy : {"skip", "leaky", "none"})
    out.live.emplace_back(
        policy,
        runChild(s.self, "--child-live " + policy + " --child-size native --live-seconds " +
                             fmt(s.live_seconds, 1) + " --threads " + std::to_string(s.threads)));
}

}  // namespace

std::vector<BudgetCase> budgetCases(const BudgetSettings& settings) {
  std::vector<BudgetCase> cases = {
      {"end-to-end",
       "the element against the bare network and the TFF network, each engine and input size",
       runEndToEndCase},
      {"engines", "cv::dnn, OpenVINO and onnxruntime on the same ONNX file", runEnginesCase},
      {"streams", "frames/s and memory of 1 and 4 streams", runStreamsCase}};
  if (settings.haveOpenVino())
    cases.push_back({"person-counts", "the person counts of cv::dnn and OpenVINO on vtest.avi",
                     runPersonCountsCase});
  cases.push_back({"live", "a live source faster than inference, per live policy", runLiveCase});
  return cases;
}

}  // namespace jointflow::bench
