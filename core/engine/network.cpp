// openNetwork: picks the engine from EngineOptions::backend.
#include "network.hpp"

#include <algorithm>
#include <sstream>

#include "jointflow/error.hpp"

namespace jointflow::detail {

void checkOutputs(const std::string& path, const std::string& what,
                  const std::vector<std::string>& required_outputs,
                  const std::vector<std::string>& outs) {
  std::vector<std::string> missing;
  for (const auto& r : required_outputs) {
    if (std::find(outs.begin(), outs.end(), r) == outs.end()) missing.push_back(r);
  }
  if (missing.empty()) return;
  std::ostringstream msg;
  msg << "model file " << path << " is not a " << what << " model: expected outputs";
  for (const auto& r : required_outputs) msg << " " << r;
  msg << "; it has";
  for (const auto& o : outs) msg << " " << o;
  msg << " (missing";
  for (const auto& m : missing) msg << " " << m;
  msg << ")";
  throw Error(msg.str());
}

namespace {

std::unique_ptr<Network> openOn(const std::string& path, const EngineOptions& dnn) {
  if (dnn.backend == DnnBackend::kOpenVino) return openOpenVinoNetwork(path, dnn);
  return openDnnNetwork(path, dnn);
}

}  // namespace

std::unique_ptr<Network> openNetwork(const std::string& path, const std::string& what,
                                     const std::vector<std::string>& required_outputs,
                                     const EngineOptions& dnn) {
  std::unique_ptr<Network> net = openOn(path, dnn);
  checkOutputs(path, what, required_outputs, net->outputNames());
  return net;
}

std::vector<std::string> modelOutputNames(const std::string& path, const EngineOptions& dnn) {
  return openOn(path, dnn)->outputNames();
}

}  // namespace jointflow::detail
