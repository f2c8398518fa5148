// Which spatial model type an ONNX file is, from its output names: for type "auto", and to say
// which type a file is when it was loaded as another.
#include <algorithm>

#include "../engine/network.hpp"
#include "spatial_models.hpp"

namespace jointflow::detail {
namespace {

bool hasAll(const std::vector<std::string>& outs, std::initializer_list<const char*> names) {
  return std::all_of(names.begin(), names.end(), [&](const char* n) {
    return std::find(outs.begin(), outs.end(), n) != outs.end();
  });
}

}  // namespace

ModelType modelTypeOfOutputs(const std::vector<std::string>& outs) {
  if (hasAll(outs, {"center", "regression"})) return ModelType::kMoveNet;
  if (hasAll(outs, {"displacement_fwd", "displacement_bwd"})) return ModelType::kPoseNet;
  if (hasAll(outs, {"beliefs", "pafs"})) return ModelType::kOpenPose;
  // Ultralytics names the one output of every export so; the model checks that it is a pose one.
  if (hasAll(outs, {"output0"})) return ModelType::kYolo;
  return ModelType::kAuto;
}

Error withModelTypeHint(const Error& e, ModelType chosen, const SpatialOptions& o,
                        const EngineOptions& engine) {
  ModelType found = ModelType::kAuto;
  try {
    found = modelTypeOfOutputs(modelOutputNames(o.model_path, engine));
  } catch (const std::exception&) {
    return e;  // unreadable here too: the error says why
  }
  if (found == ModelType::kAuto || found == chosen) return e;
  return Error(std::string(e.what()) + ". Its outputs are those of a " + toString(found) +
               " model, not of a " + toString(chosen) + " model: choose model-type " +
               toString(found) + " (or auto) for this file, or the " + toString(chosen) +
               " file for model-type " + toString(chosen));
}

}  // namespace jointflow::detail
