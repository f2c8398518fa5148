// The engine layer's settings: which inference engine runs the networks (spatial and TFF), on
// which device, with how many threads. A layer of its own below the spatial and temporal models,
// so that the engine (core/engine) reads these and nothing of the models' settings.
#pragma once

#include <string>

#include "jointflow/setting_enums.hpp"

namespace jointflow {

/// Which inference engine runs the networks, and how (docs/benchmarks.md helps to choose).
///
/// backend: "default" | "opencv" | "cuda" run on OpenCV's dnn module (cv::dnn, the default);
/// "openvino" runs on OpenVINO's own C++ runtime (the PyPI wheel `openvino`, which `make build`
/// installs into the build folder): about 3x faster on a CPU, asynchronous, and shareable between
/// streams. Choosing one this build or machine lacks is an error at load time that says how to get
/// it, never a silent fall-back.
struct EngineOptions {
  DnnBackend backend = DnnBackend::kDefault;
  /// cv::dnn target: "cpu" | "opencl" | "opencl_fp16" | "cuda" | "cuda_fp16". OpenVINO takes
  /// "cpu" here and its device from `device`.
  DnnTarget target = DnnTarget::kCpu;
  /// Inference threads; 0 = the engine's default. cv::dnn's thread pool is process-wide (the last
  /// model made sets it); OpenVINO's is per compiled model (so per model instance).
  int num_threads = 0;
  /// OpenVINO only. Device name as OpenVINO spells it: "CPU", "GPU", "GPU.1", "AUTO", ...
  std::string device = "CPU";
  /// OpenVINO only. Execution streams of the compiled model (requests that run at the same time);
  /// 0 = OpenVINO's choice for latency (1 on a CPU).
  int num_streams = 0;
  /// OpenVINO only. Precision the network computes in: "" = OpenVINO's default for the device
  /// (bf16 on CPUs with AVX-512 BF16 or AMX, else f32), or "f32", "bf16", "f16". bf16 is about
  /// 1.8x faster where the CPU has it, at a small cost in agreement with cv::dnn
  /// (models/README.md, "OpenVINO parity").
  std::string precision;
  /// OpenVINO only. Networks of the same file with the same id share one compiled model in the
  /// process (as DL Streamer's model-instance-id): one copy of the weights for every stream; each
  /// keeps its own infer request. Empty = a model of its own. The settings of one id must agree.
  std::string model_instance_id;
};

}  // namespace jointflow
