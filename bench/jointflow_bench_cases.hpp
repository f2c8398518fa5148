// jointflow-bench's cases (bench/jointflow_bench.cpp has what each measures and why): each a
// name, a line saying what it measures, and a function that runs it and adds its figures to
// BudgetFigures; jointflow_bench_document.hpp writes those as docs/benchmarks.md. Split from the
// program's main so that the benchmark reads like the tests: a list of named cases, a runner, a
// writer.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "jointflow_bench_measures.hpp"

namespace jointflow::bench {

/// Frames of each stream that do not count (--child K).
constexpr int kStreamWarmup = 3;

/// jointflow-bench's command line and what this build has; every case and the writer read it.
struct BudgetSettings {
  std::string video, python, ort_script;
  // 10 rounds: with 4, the overhead of the same build moved by 0.05-0.1 from run to run (the
  // per-round ratios of a shared 2-core machine), as much as what it is to show.
  int block = 6, rounds = 10, runs = 20, stream_frames = 10, agreement_stride = 2, threads = 1;
  double live_seconds = 8;
  std::string self;  ///< this program, which the cases run again as their child processes
  std::string base;  ///< the options every child gets (the video, the threads)
  std::string movenet, tff_path;
  std::string tff_used;  ///< tff_path, or empty where the trained TFF network is absent
  cv::Size native;       ///< the video's frame size
  cv::Size max640;       ///< the network input of input-size=max:640 on it
  std::vector<std::pair<std::string, std::string>> engines;  ///< backend, name in the tables
  std::string openvino_name;     ///< OpenVINO's engine, as SpatialModel::engine() names it
  std::string openvino_missing;  ///< why this build has no OpenVINO; empty where it has
  bool haveOpenVino() const { return openvino_missing.empty(); }
  std::vector<std::string> sizes = {"256x256", "max:640", "native"};  ///< the element's input-size
};

/// One row of the engines on the same file.
struct EngineRow {
  cv::Size size;
  int threads = 1;
  EngineTimes times;
};

/// One row of the streams: a child's figures (runPipelines) and what the row adds to the count.
struct StreamRow {
  std::string engine;
  nlohmann::json figures;
  std::string note;
};

/// The person counts of cv::dnn and OpenVINO on the same frames.
struct PersonCounts {
  int frames = 0;  ///< compared
  int within = 0;  ///< counts within 1 of each other
  int equal = 0;
  int people = 0;  ///< on cv::dnn, summed over the frames compared
  int total = 0;   ///< frames of the video
};

/// Every figure of a run; a case fills its part.
struct BudgetFigures {
  std::map<std::string, nlohmann::json> e2e;  ///< per input size: runEndToEnd's figures
  std::vector<EngineRow> engines;
  std::optional<std::string> ort_version;  ///< onnxruntime's; none: not measured (no --python)
  std::vector<StreamRow> streams;
  nlohmann::json shared_streams,
      separate_streams;  ///< OpenVINO: 4 on one model, 2 with a model each
  std::optional<PersonCounts> counts;
  std::vector<std::pair<std::string, nlohmann::json>> live;  ///< per policy: runLive's figures
  std::vector<std::string> loads;                            ///< the load average after each case
};

struct BudgetCase {
  std::string name;
  std::string measures;  ///< one line, for a reader of the list
  std::function<void(const BudgetSettings&, BudgetFigures&)> run;
};

/// The cases in the order they run (the person counts only where the build has OpenVINO).
std::vector<BudgetCase> budgetCases(const BudgetSettings& settings);

}  // namespace jointflow::bench
