// The named choices among the settings (spatial model type, similarity, matcher, appearance model,
// tiles, dnn backend and target) as enums, each with one table of its values, their names and
// descriptions.
//
// The core compares enums only. Names appear at the edges (element properties, command lines,
// files, messages) and are converted there, in one place each way: parseEnum<E>() and
// toString(E). The GStreamer plugin registers its GEnum types from these same tables, so a value
// added here appears as a property value, a command-line choice and a documented option.
#pragma once

#include <array>
#include <cstddef>
#include <iterator>
#include <string>
#include <string_view>

#include "jointflow/error.hpp"

namespace jointflow {

/// Decoder of the spatial model (SpatialModel).
enum class ModelType { kAuto, kMoveNet, kPoseNet, kOpenPose, kYolo };
/// Person similarity of the association (paper Sec. 4.2 and its baselines, Sec. 6.1).
enum class SimilarityType { kTff, kOks, kIou, kPckh, kFlow, kAuto };
/// Bipartite matching of tracks to poses (paper Eq. 1).
enum class Matcher { kGreedy, kOptimal };
/// What re-identifies a lost track when its person comes back (besides where it is predicted).
enum class AppearanceModel { kOff, kFeatures, kFeaturesColour };
/// Whether the spatial network also runs on tiles of the frame (TileOptions). Off and on are 0 and
/// 1, as FALSE and TRUE were when `tiles` was a boolean property: an application that sets it with
/// g_object_set(..., "tiles", FALSE, ...) still gets the whole frame only.
enum class TileMode { kOff = 0, kOn = 1, kAuto = 2 };
/// Inference engine: OpenCV's dnn module (kDefault, kOpenCV, kCuda) or OpenVINO's runtime.
enum class DnnBackend { kDefault, kOpenCV, kCuda, kOpenVino };
/// Inference target device of OpenCV's dnn module.
enum class DnnTarget { kCpu, kOpenCL, kOpenCLFp16, kCuda, kCudaFp16 };

template <typename E>
struct EnumEntry {
  E value;
  const char* nick;         ///< the name users write ("tff", "greedy", ...)
  const char* description;  ///< one line, for help texts and gst-inspect
};

/// EnumInfo<E>::kWhat names the setting in messages; ::kEntries lists every value in order.
template <typename E>
struct EnumInfo;

template <>
struct EnumInfo<ModelType> {
  static constexpr const char* kWhat = "spatial model type";
  static constexpr std::array<EnumEntry<ModelType>, 5> kEntries{{
      {ModelType::kAuto, "auto", "Chosen from the ONNX file's output names"},
      {ModelType::kMoveNet, "movenet", "MoveNet MultiPose"},
      {ModelType::kPoseNet, "posenet", "PoseNet MobileNetV1"},
      {ModelType::kOpenPose, "openpose", "Belief maps + Part Affinity Fields (OpenPose)"},
      {ModelType::kYolo, "yolo",
       "YOLO11n-pose, opt-in: not shipped (AGPL-3.0 weights; make models-yolo installs it); no "
       "TFF"},
  }};
};

template <>
struct EnumInfo<SimilarityType> {
  static constexpr const char* kWhat = "similarity";
  static constexpr std::array<EnumEntry<SimilarityType>, 6> kEntries{{
      {SimilarityType::kTff, "tff", "Temporal Flow Fields (the paper's method; needs tff-model)"},
      {SimilarityType::kOks, "oks", "Object keypoint similarity to the track's last pose"},
      {SimilarityType::kIou, "iou", "Box intersection over union"},
      {SimilarityType::kPckh, "pckh", "PCKh of the track's last pose"},
      {SimilarityType::kFlow, "flow", "Keypoints moved by dense optical flow (OpenCV DIS)"},
      {SimilarityType::kAuto, "auto",
       "oks between frames closer than auto-tff-gap, tff between frames further apart (a slow "
       "engine, dropped frames); oks alone where the spatial model has no TFF network"},
  }};
};

template <>
struct EnumInfo<Matcher> {
  static constexpr const char* kWhat = "matcher";
  static constexpr std::array<EnumEntry<Matcher>, 2> kEntries{{
      {Matcher::kGreedy, "greedy", "Greedy, highest potential first (the paper)"},
      {Matcher::kOptimal, "optimal", "Optimal bipartite matching (Hungarian)"},
  }};
};

template <>
struct EnumInfo<AppearanceModel> {
  static constexpr const char* kWhat = "appearance model";
  static constexpr std::array<EnumEntry<AppearanceModel>, 3> kEntries{{
      {AppearanceModel::kOff, "off", "Position and pose only"},
      {AppearanceModel::kFeatures, "features",
       "The spatial network's features at the person's keypoints"},
      {AppearanceModel::kFeaturesColour, "features-colour",
       "The network's features and an HSV colour histogram of the person's box"},
  }};
};

template <>
struct EnumInfo<TileMode> {
  static constexpr const char* kWhat = "tiles";
  static constexpr std::array<EnumEntry<TileMode>, 3> kEntries{{
      {TileMode::kAuto, "auto",
       "Tiles with MoveNet at one scale (the default model); none with other models or several "
       "scales"},
      {TileMode::kOn, "true", "Tiles (an error where the model or scales do not allow them)"},
      {TileMode::kOff, "false", "The whole frame only"},
  }};
};

template <>
struct EnumInfo<DnnBackend> {
  static constexpr const char* kWhat = "dnn backend";
  static constexpr std::array<EnumEntry<DnnBackend>, 4> kEntries{{
      {DnnBackend::kDefault, "default", "OpenCV's default"},
      {DnnBackend::kOpenCV, "opencv", "OpenCV's own"},
      {DnnBackend::kCuda, "cuda", "CUDA (OpenCV built with CUDA)"},
      {DnnBackend::kOpenVino, "openvino", "OpenVINO's own runtime (PyPI wheel openvino)"},
  }};
};

template <>
struct EnumInfo<DnnTarget> {
  static constexpr const char* kWhat = "dnn target";
  static constexpr std::array<EnumEntry<DnnTarget>, 5> kEntries{{
      {DnnTarget::kCpu, "cpu", "CPU"},
      {DnnTarget::kOpenCL, "opencl", "OpenCL"},
      {DnnTarget::kOpenCLFp16, "opencl_fp16", "OpenCL, half precision"},
      {DnnTarget::kCuda, "cuda", "CUDA"},
      {DnnTarget::kCudaFp16, "cuda_fp16", "CUDA, half precision"},
  }};
};

/// "a, b or c": the nicks of `entries` (anything with a .nick), for messages.
template <typename Entries>
std::string joinNicks(const Entries& entries) {
  std::string text;
  size_t i = 0;
  for (const auto& e : entries) {
    text += std::string(i == 0 ? "" : (i + 1 == std::size(entries) ? " or " : ", ")) + e.nick;
    ++i;
  }
  return text;
}

/// "a, b or c": the names of E, for messages.
template <typename E>
std::string enumNames() {
  return joinNicks(EnumInfo<E>::kEntries);
}

/// The message of a name that is none of an enumeration's (`what` as in EnumInfo::kWhat,
/// `names` as enumNames() writes them).
inline Error unknownEnumError(std::string_view what, std::string_view nick,
                              const std::string& names) {
  return Error("unknown " + std::string(what) + " '" + std::string(nick) + "', expected " + names);
}

/// The name of a value ("?" for a value outside the enum, which only a cast can make).
template <typename E>
const char* toString(E value) {
  for (const auto& e : EnumInfo<E>::kEntries)
    if (e.value == value) return e.nick;
  return "?";
}

/// The value of a name; throws jointflow::Error naming the setting and the names it accepts.
template <typename E>
E parseEnum(std::string_view nick) {
  for (const auto& e : EnumInfo<E>::kEntries)
    if (nick == e.nick) return e.value;
  throw unknownEnumError(EnumInfo<E>::kWhat, nick, enumNames<E>());
}

}  // namespace jointflow
