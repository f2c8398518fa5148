// What jointflow-bench measures with (bench/jointflow_bench.cpp has why each is measured so):
// pipelines of jointflowtrack fed from threads, a live source, the end-to-end rounds of each
// engine at one input size, and the engines on the bare ONNX file. The cases
// (jointflow_bench_cases.hpp) call these; the child processes of the memory and end-to-end
// figures call them through main's --child options.
#pragma once

#include <sys/types.h>

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

namespace jointflow::bench {

/// The 1-minute load average as /proc/loadavg writes it.
std::string loadAverage();

/// `v` with `digits` decimals.
std::string fmt(double v, int digits = 1);

/// Every `stride`th of the first `count` frames of `video` (count <= 0: all); at least 4.
std::vector<cv::Mat> readFrames(const std::string& video, int count, int stride = 1);

/// `--child K`: K pipelines fed from K threads; time per frame and memory.
nlohmann::json runPipelines(const std::vector<cv::Mat>& frames, int streams,
                            const std::string& input_size, int warmup, const std::string& props);

/// `--child-live POLICY`: a live source faster than inference; latency at the sink.
nlohmann::json runLive(const std::string& policy, const std::string& input_size, double seconds);

/// This program (`self`) with `args` in a child process; its last line of output, as JSON.
nlohmann::json runChild(const std::string& self, const std::string& args);

/// `--child-e2e SIZE`: the element against the bare network, every engine, in rounds.
nlohmann::json runEndToEnd(const std::vector<cv::Mat>& frames,
                           const std::vector<std::string>& backends, const std::string& size,
                           int block, int rounds, const std::string& tff_path);

/// bench/ort_time.py in a process of its own, asked for one timed run at a time.
class OrtServer {
 public:
  OrtServer(const std::string& python, const std::string& script, const std::string& model);
  ~OrtServer();
  OrtServer(const OrtServer&) = delete;
  OrtServer& operator=(const OrtServer&) = delete;
  const std::string& version() const { return version_; }
  double runMs(cv::Size size, int threads);

 private:
  nlohmann::json reply(const std::string& request);
  pid_t pid_ = -1;
  FILE* in_ = nullptr;
  FILE* out_ = nullptr;
  std::string version_;
};

struct EngineTimes {
  double dnn = 0, ov = -1, ov32 = -1, ort = -1;
  std::vector<std::pair<std::string, double>> by_type;   ///< cv::dnn: type, ms; largest first
  std::vector<std::pair<std::string, double>> by_layer;  ///< "name (type)", ms; largest first
};

/// cv::dnn, OpenVINO and onnxruntime (where `ort` is given) on the same file and input.
EngineTimes timeEngines(const std::string& path, cv::Size size, int runs, int threads, bool have_ov,
                        OrtServer* ort);

}  // namespace jointflow::bench
