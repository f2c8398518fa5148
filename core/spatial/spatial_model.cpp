#include "jointflow/spatial_model.hpp"

#include <algorithm>
#include <regex>

#include "../engine/network.hpp"
#include "jointflow/error.hpp"
#include "jointflow/model_files.hpp"
#include "spatial_models.hpp"

namespace jointflow {

InputSize InputSize::parse(const std::string& text) {
  InputSize s;
  std::smatch m;
  if (text == "native") {
    s.mode = Mode::kNative;
  } else if (std::regex_match(text, m, std::regex(R"(([0-9]{1,5})x([0-9]{1,5}))"))) {
    s.mode = Mode::kFixed;
    s.fixed = {std::stoi(m[1]), std::stoi(m[2])};
  } else if (std::regex_match(text, m, std::regex(R"(max:([0-9]{1,5}))"))) {
    s.mode = Mode::kMaxSide;
    s.max_side = std::stoi(m[1]);
  } else {
    throw Error("input size \"" + text + "\" is not one of: native, WxH (e.g. 256x256), max:N");
  }
  return s;
}

std::string InputSize::toString() const {
  switch (mode) {
    case Mode::kFixed:
      return std::to_string(fixed.width) + "x" + std::to_string(fixed.height);
    case Mode::kNative:
      return "native";
    case Mode::kMaxSide:
      break;
  }
  return "max:" + std::to_string(max_side);
}

namespace {

std::string shippedModel(ModelType type) {
  if (type == ModelType::kYolo) return detail::yoloOptInModelOrThrow();
  const char* file = type == ModelType::kMoveNet   ? "movenet_multipose.onnx"
                     : type == ModelType::kPoseNet ? "posenet_mobilenetv1.onnx"
                                                   : nullptr;
  if (!file)
    throw Error(std::string("no ") + toString(type) +
                " model is shipped: set SpatialOptions::model_path to an ONNX file");
  const std::string path = findShippedModel(file);
  if (path.empty())
    throw Error(shippedModelMissing(file) +
                ": set JOINTFLOW_MODELS_DIR to the folder of the shipped models "
                "(share/jointflow/models of an install, models/ of the source tree), or "
                "SpatialOptions::model_path (spatial-model) to an ONNX file");
  return path;
}

}  // namespace

std::unique_ptr<SpatialModel> createSpatialModel(ModelType type, const SpatialOptions& options) {
  SpatialOptions o = options;
  ModelType t = type;
  if (t == ModelType::kAuto) {
    if (o.model_path.empty()) {
      t = ModelType::kMoveNet;
    } else {
      const auto outs = detail::modelOutputNames(o.model_path, o.dnn);
      t = detail::modelTypeOfOutputs(outs);
      if (t == ModelType::kAuto) {
        std::string list;
        for (const auto& n : outs) list += " " + n;
        throw Error("model file " + o.model_path +
                    " is not a known pose model: expected the outputs of MoveNet (center, "
                    "heatmaps, regression, offsets, box_scale, box_offset, features), PoseNet "
                    "(heatmaps, offsets, displacement_fwd, displacement_bwd, features), an "
                    "OpenPose-style model (beliefs, pafs) or a YOLO pose export (output0); it has" +
                    list);
      }
    }
  }
  if (o.model_path.empty()) o.model_path = shippedModel(t);
  try {
    switch (t) {
      case ModelType::kMoveNet:
        return detail::createMoveNet(o);
      case ModelType::kPoseNet:
        return detail::createPoseNet(o);
      case ModelType::kYolo:
        return detail::createYoloPose(o);
      case ModelType::kOpenPose:
      case ModelType::kAuto:
        break;
    }
    return detail::createOpenPose(o);
  } catch (const Error& e) {
    throw detail::withModelTypeHint(e, t, o);
  }
}

}  // namespace jointflow
