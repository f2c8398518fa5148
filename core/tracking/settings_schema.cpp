// The rows of the tracker settings that users set by name (settings_schema.hpp).
#include "jointflow/settings_schema.hpp"

#include <cstdio>
#include <sstream>

#include "jointflow/error.hpp"

namespace jointflow {
namespace {

using S = TrackerSettings;
using Spec = SettingSpec<S>;

SettingInfo number(const char* name, const char* nick, const char* blurb, SettingKind kind,
                   double min, double max) {
  return {name, nick, blurb, kind, min, max, nullptr, false};
}

// A row without a range: its kind comes from the member it reaches.
SettingInfo plain(const char* name, const char* nick, const char* blurb) {
  return {name, nick, blurb, SettingKind::kString, 0, 0, nullptr, false};
}

std::string numbersToString(const std::vector<float>& numbers) {
  std::ostringstream out;
  for (size_t i = 0; i < numbers.size(); ++i) out << (i ? "," : "") << numbers[i];
  return out.str();
}

// A comma-separated list of numbers, each in [min, max] (or (min, max] with `open_min`), as the
// text row `name` takes them; "" is no number. Throws jointflow::Error naming the item at fault,
// with `what` (the range in words) and `example`.
std::vector<float> parseNumbers(const char* name, const std::string& text, float min, float max,
                                bool open_min, const std::string& what, const char* example) {
  std::vector<float> numbers;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    size_t used = 0;
    float v = 0.f;
    try {
      v = std::stof(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || item.find_first_not_of(" \t", used) != std::string::npos ||
        !(open_min ? v > min : v >= min) || !(v <= max))
      throw Error(std::string(name) + ": \"" + item + "\" in \"" + text + "\" is not " + what +
                  "; expected e.g. " + example);
    numbers.push_back(v);
  }
  return numbers;
}

// "0.5,1,1.5": each scale in (0, kMaxScale].
std::vector<float> parseScales(const std::string& text) {
  std::vector<float> scales = parseNumbers("scales", text, 0.f, kMaxScale, true,
                                           "a scale in (0, " + numbersToString({kMaxScale}) + "]",
                                           "\"1\" or \"0.5,1,1.5\"");
  if (scales.empty()) throw Error("scales: empty; expected a comma-separated list such as \"1\"");
  return scales;
}

// "" (none) or one threshold in [0, 1] per COCO joint.
std::vector<float> parseJointThresholds(const std::string& text) {
  std::vector<float> thresholds =
      parseNumbers("joint-thresholds", text, 0.f, 1.f, false, "a threshold in [0, 1]",
                   "\"\" or 17 values such as \"0.3,0.3,0.3,0.3,0.3,0.2,...\"");
  if (!thresholds.empty() && thresholds.size() != static_cast<size_t>(kNumJoints))
    throw Error("joint-thresholds: \"" + text + "\" has " + std::to_string(thresholds.size()) +
                " values, expected 17 (one per COCO joint) or none");
  return thresholds;
}

std::vector<Spec> makeSchema() {
  using K = SettingKind;
  using SO = SpatialOptions;
  using DO = EngineOptions;
  const auto text = [](SettingInfo info, std::function<std::string(const S&)> format,
                       std::function<void(S&, const std::string&)> parse) {
    info.kind = K::kString;
    return customSetting<S>(
        info, [format](const S& s) { return SettingValue{format(s)}; },
        [parse](S& s, const SettingValue& v) { parse(s, std::get<std::string>(v)); });
  };
  std::vector<Spec> rows;
  rows.push_back(memberSetting<S>(
      plain("spatial-model", "Spatial model",
            "ONNX file of the pose estimation network; empty = the shipped model of model-type "
            "(MoveNet MultiPose for auto) from the models folder: $JOINTFLOW_MODELS_DIR, else "
            "share/jointflow/models of the install, else the source tree's models/"),
      &S::spatial, &SO::model_path));
  rows.push_back(memberSetting<S>(plain("model-type", "Model type", "Decoder of the spatial model"),
                                  &S::model_type));
  rows.push_back(memberSetting<S>(plain("tff-model", "TFF model",
                                        "ONNX file of the Temporal Flow Field network "
                                        "(similarity=tff, auto); empty = the shipped "
                                        "one, from the models folder as for spatial-model"),
                                  &S::tff_model));
  rows.push_back(memberSetting<S>(
      plain("similarity", "Similarity", "How a new pose is compared with a track's last pose"),
      &S::similarity));
  rows.push_back(memberSetting<S>(plain("matcher", "Matcher", "How poses are assigned to tracks"),
                                  &S::matcher));
  rows.push_back(text(
      plain("input-size", "Input size",
            "Size the frame is brought to for the spatial network: \"native\", \"WxH\" "
            "(letterboxed) or \"max:N\" (longer side N pixels)"),
      [](const S& s) { return s.spatial.input_size.toString(); },
      [](S& s, const std::string& t) { s.spatial.input_size = InputSize::parse(t); }));
  static_assert(kMaxScale == 4.f, "the scales row's text gives the range");
  rows.push_back(text(
      plain("scales", "Scales",
            "Comma-separated scales of multi-scale inference, each in (0, 4] (the paper uses "
            "0.5,1,1.5,2; each scale costs one network run)"),
      [](const S& s) { return numbersToString(s.spatial.scales); },
      [](S& s, const std::string& t) { s.spatial.scales = parseScales(t); }));
  using TO = TileOptions;
  rows.push_back(memberSetting<S>(
      plain("tiles", "Tiles",
            "Also run the spatial network on overlapping tiles of the frame (tile-size, "
            "tile-overlap, tile-scale), for people too small in the whole frame (street scenes); "
            "each tile costs one network run; auto: with MoveNet at one scale"),
      &S::spatial, &SO::tiles, &TO::mode));
  rows.push_back(
      memberSetting<S>(number("tile-size", "Tile size", "Side of a tile in frame pixels (tiles)",
                              K::kInt, kMinTileSize, kMaxTileSize),
                       &S::spatial, &SO::tiles, &TO::size));
  rows.push_back(memberSetting<S>(
      number("tile-overlap", "Tile overlap",
             "Least share of a tile's side that neighbouring tiles have in common (tiles)",
             K::kFloat, 0, kMaxTileOverlap),
      &S::spatial, &SO::tiles, &TO::overlap));
  rows.push_back(memberSetting<S>(
      number("tile-scale", "Tile scale",
             "Network pixels per frame pixel in a tile: above 1 enlarges small people (tiles)",
             K::kFloat, kMinTileScale, kMaxTileScale),
      &S::spatial, &SO::tiles, &TO::scale));
  rows.push_back(memberSetting<S>(
      plain("tile-full-frame", "Tile full frame",
            "With tiles, also run the whole frame at input-size, for people larger than a tile; "
            "its maps feed the TFF network (without it, the tiles' maps stitched together)"),
      &S::spatial, &SO::tiles, &TO::full_frame));
  // One limit for the decoder and the track book.
  rows.push_back(customSetting<S>(
      number("max-persons", "Max persons", "Most persons tracked per frame", K::kInt, 1,
             kMaxPersonsLimit),
      [](const S& s) { return SettingValue{s.max_persons}; },
      [](S& s, const SettingValue& v) {
        s.max_persons = s.spatial.max_persons = std::get<int>(v);
      }));
  rows.push_back(
      memberSetting<S>(number("person-threshold", "Person threshold",
                              "Poses with a lower person score are dropped", K::kFloat, 0, 1),
                       &S::spatial, &SO::person_threshold));
  rows.push_back(memberSetting<S>(
      number("keypoint-threshold", "Keypoint threshold",
             "Keypoints with a lower score are reported with score 0", K::kFloat, 0, 1),
      &S::spatial, &SO::keypoint_threshold));
  rows.push_back(memberSetting<S>(
      number("nms-threshold", "NMS threshold",
             "Lowest belief-map peak kept by non-maximum suppression (OpenPose decoder, the "
             "paper's tau_NMS)",
             K::kFloat, 0, 1),
      &S::spatial, &SO::nms_threshold));
  rows.push_back(memberSetting<S>(
      number("tau-delta", "Tau delta",
             "Frame pixels: a joint that moved less than this between frames (after camera "
             "compensation) counts as still (the paper's tau_Delta, 2 there; 12 covers the "
             "camera estimate's error)",
             K::kFloat, 0, 1000),
      &S::tau_delta));
  rows.push_back(memberSetting<S>(
      number("line-samples", "Line samples",
             "Points sampled along each limb for the TFF line integral (the paper's Eq. 5), both "
             "ends included",
             K::kInt, 2, 1000),
      &S::line_samples));
  rows.push_back(memberSetting<S>(
      number("sigma-flow", "Sigma flow",
             "Frame pixels: width of the dense optical flow's joint energy (the paper's Eq. 9, 30 "
             "there): a joint this far from where the flow moved it scores exp(-1)",
             K::kFloat, 0.01, 10000),
      &S::sigma_flow));
  rows.push_back(memberSetting<S>(
      number("min-track-length", "Min track length",
             "Tracks are tentative until they were matched on this many inferred frames", K::kInt,
             1, 100000),
      &S::min_track_length));
  rows.push_back(memberSetting<S>(
      number("min-report-length", "Min report length",
             "A new track is reported (and gets its id) once matched on this many inferred "
             "frames; those born on a stream's first frame at once. 2: a detection seen on one "
             "frame only shows no id; 1 = from the first detection (the paper)",
             K::kInt, 1, 100000),
      &S::min_report_length));
  rows.push_back(memberSetting<S>(
      number("contested-time", "Contested time",
             "Seconds at most that a new track born where a lost confirmed track may still take "
             "its person back is not shown (until it is confirmed, or that track is matched or "
             "ends): a person half hidden behind a partner does not flash a new id; 0 = off",
             K::kFloat, 0, 3600),
      &S::contested_time));
  rows.push_back(memberSetting<S>(
      number("lost-time", "Lost time",
             "Seconds of stream time a confirmed track that is not matched is kept (predicted "
             "by its motion model) and can take its person back, e.g. after an occlusion",
             K::kFloat, 0, 3600),
      &S::lost_time));
  rows.push_back(memberSetting<S>(
      number("gap-time", "Gap time",
             "Frames at least this many seconds of stream time apart (a camera outage): confirmed "
             "tracks are matched on their appearance within their position gates, not on the "
             "OKS of their predictions; 0 = off",
             K::kFloat, 0, 3600),
      &S::gap_time));
  rows.push_back(memberSetting<S>(
      number("tentative-lost-time", "Tentative lost time",
             "Seconds a tentative track (shorter than min-track-length) that is not matched is "
             "kept; at least 1.5 frame intervals, so that it lives through one missed frame at "
             "any frame rate",
             K::kFloat, 0, 3600),
      &S::tentative_lost_time));
  rows.push_back(memberSetting<S>(
      number("fallback-frame-rate", "Fallback frame rate",
             "Frames per second assumed for a frame without a usable timestamp (none, or not "
             "after the previous frame's): it is taken 1 / this after the previous one",
             K::kFloat, 0.001, 10000),
      &S::frame_rate));
  rows.push_back(memberSetting<S>(
      plain("reid", "Re-identification",
            "What recognises a lost track's person when it comes back, besides where its "
            "motion model predicts it"),
      &S::reid));
  rows.push_back(memberSetting<S>(
      number("reid-min-similarity", "Re-id min similarity",
             "Lowest appearance similarity (cosine, 0 to 1) at which a lost track takes a pose "
             "within its position gate",
             K::kFloat, 0, 1),
      &S::reid_min_similarity));
  rows.push_back(memberSetting<S>(
      number("reentry-time", "Re-entry time",
             "Seconds a confirmed track that ended (its person left the view or stayed hidden "
             "longer than lost-time) is remembered by appearance and where it was last seen, so "
             "that the person coming back near there gets the old id; 0 = off",
             K::kFloat, 0, 3600),
      &S::reentry_time));
  rows.push_back(memberSetting<S>(
      number("reentry-min-similarity", "Re-entry min similarity",
             "Lowest appearance similarity (cosine, 0 to 1) at which a new person is taken for a "
             "departed one (reentry-time)",
             K::kFloat, 0, 1),
      &S::reentry_min_similarity));
  rows.push_back(memberSetting<S>(
      number(
          "swap-margin", "Swap margin",
          "Two tracks whose poses each look more like the other track by more than this (sum "
          "of both appearance similarities, 0 to 2) take each other's pose: people side by "
          "side or crossing whose ids the position swapped; likewise a track left unmatched "
          "and a matched one, for a pose still free, and a track left unmatched takes back a pose "
          "that looks like it from a track it does not look like; 0 = off",
          K::kFloat, 0, 2),
      &S::swap_margin));
  rows.push_back(memberSetting<S>(
      number("joint-threshold", "Joint threshold",
             "Keypoints scoring at least this take part in the similarity of two poses (the "
             "paper's detected joints)",
             K::kFloat, 0, 1),
      &S::joint_threshold));
  rows.push_back(text(
      plain("joint-thresholds", "Joint thresholds",
            "Per-joint thresholds in COCO order (17 comma-separated values in [0, 1]) that "
            "replace joint-threshold; empty = joint-threshold for every joint"),
      [](const S& s) { return numbersToString(s.joint_thresholds); },
      [](S& s, const std::string& t) { s.joint_thresholds = parseJointThresholds(t); }));
  rows.push_back(memberSetting<S>(
      number("min-potential", "Min potential",
             "No match below this potential per joint (tff, flow: Psi over the joints in both; "
             "oks, iou, pckh: the score); the pose starts a new track",
             K::kFloat, -1000, 1000),
      &S::min_potential));
  rows.push_back(memberSetting<S>(
      number("track-score", "Track score",
             "Poses with a lower person score start no track and are matched only in a second "
             "pass, to the tracks the first pass left (ByteTrack); 0 = every pose in the first",
             K::kFloat, 0, 1),
      &S::track_score));
  rows.push_back(memberSetting<S>(
      number("min-common-joints", "Min common joints",
             "oks and pckh: their mean over the joints detected in both poses is taken over at "
             "least this many joints, the missing ones counting 0, so that a pose sharing one or "
             "two joints with a track (a lower body detected apart) does not win on them",
             K::kInt, 1, 17),
      &S::min_common_joints));
  rows.push_back(memberSetting<S>(
      number(
          "tff-oks-weight", "TFF OKS weight",
          "similarity=tff, and auto where its TFF runs: weight of the OKS of the track's predicted "
          "pose with the new pose in the potential per joint (tff-flow-weight says the whole "
          "mix); with tff-flow-weight=0, 0 = the paper's TFF potential alone",
          K::kFloat, 0, 1),
      &S::tff_oks_weight));
  rows.push_back(memberSetting<S>(
      number(
          "tff-flow-weight", "TFF flow weight",
          "similarity=tff, and auto where its TFF runs, between frames auto-tff-gap or more apart: "
          "weight of the dense optical flow's joint energy in the potential per joint, (1 - "
          "w_oks - w) x the TFF's + w_oks x OKS + w x the flow's; at most 1 - tff-oks-weight; "
          "0 = no flow computed",
          K::kFloat, 0, 1),
      &S::tff_flow_weight));
  rows.push_back(memberSetting<S>(
      number("auto-tff-gap", "Auto TFF gap",
             "similarity=auto: frames at least this many seconds of stream time apart are matched "
             "with the TFF, closer ones with oks (the TFF network does not run for them); tff and "
             "auto: from this gap on the flow joins the TFF's mix (tff-flow-weight); 0 = every "
             "frame, for fast motion at the camera's rate (sport; docs/tracking.md)",
             K::kFloat, 0, 3600),
      &S::auto_tff_gap));
  rows.push_back(memberSetting<S>(
      plain("geometric-fallback", "Geometric fallback",
            "Tracks the similarity leaves unmatched get a second chance on OKS with their "
            "predicted pose (coast-min-oks)"),
      &S::geometric_fallback));
  rows.push_back(memberSetting<S>(
      number("coast-min-oks", "Coast min OKS",
             "Lowest OKS between a track's predicted pose and a new pose for the geometric "
             "fallback and for lost tracks",
             K::kFloat, 0, 1),
      &S::coast_min_oks));
  rows.push_back(memberSetting<S>(
      number("duplicate-oks", "Duplicate OKS",
             "Of two poses in a frame whose OKS is at least this, the lower-scored one is "
             "dropped (the detector's second view of one person close up); 0 = off",
             K::kFloat, 0, 1),
      &S::duplicate_oks));
  rows.push_back(memberSetting<S>(
      number("min-person-size", "Min person size",
             "Frame pixels: poses whose keypoint box has a shorter longer side are ignored; 0 = "
             "off",
             K::kFloat, 0, 100000),
      &S::min_person_size));
  rows.push_back(memberSetting<S>(
      plain("camera-compensation", "Camera compensation",
            "Estimate the camera motion on every inferred frame and move every track with it "
            "before poses are compared"),
      &S::camera_compensation));
  rows.push_back(memberSetting<S>(
      plain("output-tentative", "Output tentative",
            "Report tracks before they reach min-track-length (false hides them: the paper's "
            "pruning, live)"),
      &S::output_tentative));
  rows.push_back(memberSetting<S>(
      plain("smoothing", "Smoothing", "One-Euro smoothing of the keypoints of each track"),
      &S::smoothing));
  rows.push_back(memberSetting<S>(
      number("euro-min-cutoff", "One-Euro min cutoff",
             "smoothing: the One-Euro filter's lowest cut-off frequency in Hz (lower: steadier "
             "keypoints when still, more lag)",
             K::kFloat, 0.001, 1000),
      &S::euro_min_cutoff));
  rows.push_back(memberSetting<S>(
      number("euro-beta", "One-Euro beta",
             "smoothing: how fast the cut-off rises with the keypoint's speed, per pixel/s "
             "(higher: less lag when moving)",
             K::kFloat, 0, 1000),
      &S::euro_beta));
  rows.push_back(memberSetting<S>(
      number("euro-d-cutoff", "One-Euro speed cutoff",
             "smoothing: cut-off frequency in Hz of the speed estimate that drives the cut-off",
             K::kFloat, 0.001, 1000),
      &S::euro_d_cutoff));
  rows.push_back(memberSetting<S>(
      plain("backend", "Backend",
            "Inference engine of the networks: OpenCV's dnn module (default, opencv, cuda) or "
            "OpenVINO's runtime (openvino, about 3x faster on a CPU; docs/benchmarks.md)"),
      &S::engine, &DO::backend));
  rows.push_back(memberSetting<S>(
      plain("target", "Target",
            "OpenCV dnn target device (with backend=openvino: cpu, and the device property "
            "chooses)"),
      &S::engine, &DO::target));
  rows.push_back(memberSetting<S>(
      number("num-threads", "Threads",
             "Inference threads (0 = the engine's default). OpenCV's setting is process-wide; "
             "OpenVINO's is per model instance",
             K::kInt, 0, 1024),
      &S::engine, &DO::num_threads));
  rows.push_back(memberSetting<S>(
      plain("device", "Device", "OpenVINO device (backend=openvino): CPU, GPU, GPU.1, AUTO, ..."),
      &S::engine, &DO::device));
  rows.push_back(memberSetting<S>(
      number("num-streams", "Streams",
             "OpenVINO execution streams: inference requests of the model instance that run at "
             "the same time (0 = OpenVINO's choice for latency, 1 on a CPU)",
             K::kInt, 0, 64),
      &S::engine, &DO::num_streams));
  rows.push_back(memberSetting<S>(
      plain("model-instance-id", "Model instance id",
            "Elements of a process with the same id share one compiled model of each network "
            "(backend=openvino, as DL Streamer's model-instance-id): one copy of the weights, "
            "infer requests of its own per element; their engine settings must agree. Empty = a "
            "model of its own"),
      &S::engine, &DO::model_instance_id));
  rows.push_back(memberSetting<S>(
      plain("precision", "Precision",
            "OpenVINO inference precision: empty = the device's default (bf16 on CPUs with "
            "AVX-512 BF16 or AMX, about 1.8x faster than f32), f32 (the numbers of cv::dnn), "
            "bf16, f16 (models/README.md)"),
      &S::engine, &DO::precision));
  return rows;
}

[[noreturn]] void refuse(const SettingInfo& info, const std::string& why) {
  throw Error(std::string(info.name) + ": " + why);
}

}  // namespace

const std::vector<SettingSpec<TrackerSettings>>& trackerSettingsSchema() {
  static const std::vector<Spec> rows = makeSchema();
  return rows;
}

std::string settingValueText(const SettingInfo& info, const SettingValue& value) {
  if (info.kind == SettingKind::kEnum && std::holds_alternative<int>(value) && info.enumeration)
    for (const auto& v : info.enumeration->values)
      if (v.value == std::get<int>(value)) return v.nick;
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, bool>) {
          return v ? "true" : "false";
        } else if constexpr (std::is_same_v<T, std::string>) {
          return v;
        } else if constexpr (std::is_same_v<T, float>) {
          char text[32];
          std::snprintf(text, sizeof text, "%g", static_cast<double>(v));
          return text;
        } else {
          return std::to_string(v);
        }
      },
      value);
}

int parseSettingEnum(const SettingInfo& info, std::string_view nick) {
  if (info.kind != SettingKind::kEnum || !info.enumeration) refuse(info, "is not an enumeration");
  for (const auto& v : info.enumeration->values)
    if (nick == v.nick) return v.value;
  refuse(
      info,
      unknownEnumError(info.enumeration->what, nick, joinNicks(info.enumeration->values)).what());
}

void checkSettingValue(const SettingInfo& info, const SettingValue& value) {
  // A float row's bounds as floats, as its GParamSpec holds them: 0.01 is 0.00999... in a float,
  // and a value set through the property must pass here too.
  const bool as_float = info.kind == SettingKind::kFloat;
  const double min = as_float ? static_cast<float>(info.min) : info.min;
  const double max = as_float ? static_cast<float>(info.max) : info.max;
  auto range = [&](double v) {
    if (!(v >= min && v <= max))
      refuse(info, settingValueText(info, value) + " is out of range (" +
                       settingValueText(info, SettingValue{static_cast<float>(info.min)}) + " to " +
                       settingValueText(info, SettingValue{static_cast<float>(info.max)}) + ")");
  };
  switch (info.kind) {
    case SettingKind::kBool:
      if (!std::holds_alternative<bool>(value)) refuse(info, "expected true or false");
      return;
    case SettingKind::kInt:
      if (!std::holds_alternative<int>(value)) refuse(info, "expected an integer");
      return range(std::get<int>(value));
    case SettingKind::kUInt:
      if (!std::holds_alternative<unsigned>(value)) refuse(info, "expected an integer >= 0");
      return range(std::get<unsigned>(value));
    case SettingKind::kFloat:
      if (!std::holds_alternative<float>(value)) refuse(info, "expected a number");
      return range(std::get<float>(value));
    case SettingKind::kString:
      if (!std::holds_alternative<std::string>(value)) refuse(info, "expected text");
      return;
    case SettingKind::kEnum:
      if (std::holds_alternative<int>(value) && info.enumeration)
        for (const auto& v : info.enumeration->values)
          if (v.value == std::get<int>(value)) return;
      refuse(info, "not one of its names");
  }
}

}  // namespace jointflow
