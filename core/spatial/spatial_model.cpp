#include "jointflow/spatial_model.hpp"

#include <algorithm>
#include <cmath>
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

// Tiles run at one scale (tiling.hpp): several would multiply the runs per tile.
bool singleScale(const SpatialOptions& o) {
  return o.scales.size() == 1 && o.scales.front() == 1.f;
}

}  // namespace

void validateSpatialOptions(const SpatialOptions& o) {
  if (o.scales.empty()) throw Error("spatial options: the list of inference scales is empty");
  for (float s : o.scales) {
    if (!(s > 0.f) || !std::isfinite(s) || s > kMaxScale) {
      throw Error("spatial options: inference scale " + std::to_string(s) + " is not in (0, " +
                  std::to_string(kMaxScale) + "]");
    }
  }
  if (o.max_persons < 1 || o.max_persons > kMaxPersonsLimit) {
    throw Error("spatial options: max_persons must be in [1, " + std::to_string(kMaxPersonsLimit) +
                "], got " + std::to_string(o.max_persons));
  }
  auto unit = [](float v, const char* name) {
    if (!(v >= 0.f && v <= 1.f)) {
      throw Error(std::string("spatial options: ") + name + " must be in [0, 1], got " +
                  std::to_string(v));
    }
  };
  unit(o.person_threshold, "person_threshold");
  unit(o.keypoint_threshold, "keypoint_threshold");
  unit(o.nms_threshold, "nms_threshold");
  unit(o.part_threshold, "part_threshold");
  if (!(o.nms_radius >= 0.f)) throw Error("spatial options: nms_radius must be >= 0");
  const TileOptions& t = o.tiles;
  if (t.mode == TileMode::kOff) return;  // auto may become on: its values are checked too
  if (t.size < kMinTileSize || t.size > kMaxTileSize)
    throw Error("spatial options: tile-size (tiles.size) " + std::to_string(t.size) +
                " is out of range: " + std::to_string(kMinTileSize) + " to " +
                std::to_string(kMaxTileSize) + " frame pixels");
  if (!(t.overlap >= 0.f && t.overlap <= kMaxTileOverlap))
    throw Error("spatial options: tile-overlap (tiles.overlap) " + std::to_string(t.overlap) +
                " is out of range: 0 to " + std::to_string(kMaxTileOverlap) + " of a tile's side");
  if (!(t.scale >= kMinTileScale && t.scale <= kMaxTileScale))
    throw Error("spatial options: tile-scale (tiles.scale) " + std::to_string(t.scale) +
                " is out of range: " + std::to_string(kMinTileScale) + " to " +
                std::to_string(kMaxTileScale));
  if (t.mode == TileMode::kOn && !singleScale(o))
    throw Error(
        "spatial options: tiles and multi-scale inference (scales) do not go together: "
        "set scales to 1 or tiles to false");
}

std::unique_ptr<SpatialModel> createSpatialModel(ModelType type, const SpatialOptions& options,
                                                 const EngineOptions& engine) {
  validateSpatialOptions(options);
  SpatialOptions o = options;
  ModelType t = type;
  if (t == ModelType::kAuto) {
    if (o.model_path.empty()) {
      t = ModelType::kMoveNet;
    } else {
      const auto outs = detail::modelOutputNames(o.model_path, engine);
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
  if (o.tiles.mode == TileMode::kAuto)
    o.tiles.mode = t == ModelType::kMoveNet && singleScale(o) ? TileMode::kOn : TileMode::kOff;
  try {
    switch (t) {
      case ModelType::kMoveNet:
        return detail::createMoveNet(o, engine);
      case ModelType::kPoseNet:
        return detail::createPoseNet(o, engine);
      case ModelType::kYolo:
        return detail::createYoloPose(o, engine);
      case ModelType::kOpenPose:
      case ModelType::kAuto:
        break;
    }
    return detail::createOpenPose(o, engine);
  } catch (const Error& e) {
    throw detail::withModelTypeHint(e, t, o, engine);
  }
}

}  // namespace jointflow
