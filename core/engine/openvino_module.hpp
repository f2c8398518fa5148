// Internal: the one entry point of the OpenVINO engine module, looked up with dlsym.
#pragma once

#include <string>

#include "jointflow/spatial_model.hpp"
#include "network.hpp"

namespace jointflow::detail {

/// Opens `path` on OpenVINO. Returns a new Network; throws jointflow::Error (the module links the
/// core, so the exception type is shared).
using OpenVinoOpenFn = Network* (*)(const std::string& path, const EngineOptions& dnn);
constexpr const char* kOpenVinoOpenSymbol = "jointflow_openvino_open";

}  // namespace jointflow::detail
