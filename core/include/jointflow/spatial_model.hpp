// The spatial part of JointFlow: "any multi-person pose estimator" (paper, Sec. 3).
//
// A SpatialModel takes one frame and returns the poses of all people in it, in frame pixels, plus
// the two maps the Temporal Flow Field network needs, on one common grid:
//   - features: a backbone feature map, and
//   - beliefs:  one joint belief map per COCO joint, values in [0, 1].
// `grid_to_frame` maps a grid cell position to frame pixels exactly, undoing the letterbox,
// padding, scaling and stride of the model input.
//
// Implementations (create them with createSpatialModel):
//   "movenet"  MoveNet MultiPose (CenterNet-style decoding, any number of persons),
//   "posenet"  PoseNet MobileNetV1 (standard multi-person decoding),
//   "openpose" any model with joint belief maps and Part Affinity Fields (Cao et al. 2017).
// A SpatialModel is not thread-safe: use one instance per thread (or per stream).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/engine_options.hpp"
#include "jointflow/model_files.hpp"  // defaultModelsDir(): where the shipped models are
#include "jointflow/setting_enums.hpp"
#include "jointflow/types.hpp"

namespace jointflow {

/// Affine map between grid cells and frame pixels, per axis: frame = grid * scale + offset.
struct GridTransform {
  float scale_x = 1.f;
  float scale_y = 1.f;
  float offset_x = 0.f;
  float offset_y = 0.f;

  cv::Point2f toFrame(cv::Point2f grid) const {
    return {grid.x * scale_x + offset_x, grid.y * scale_y + offset_y};
  }
  cv::Point2f toGrid(cv::Point2f frame) const {
    return {(frame.x - offset_x) / scale_x, (frame.y - offset_y) / scale_y};
  }
};

struct SpatialResult {
  Poses poses;                  ///< in frame pixels, highest person score first
  cv::Mat features;             ///< CV_32F, 4-D {1, C, H, W}
  cv::Mat beliefs;              ///< CV_32F, 4-D {1, 17, H, W}, COCO joint order, values in [0, 1]
  GridTransform grid_to_frame;  ///< maps (column, row) of the two maps above to frame pixels
  cv::Size frame_size;          ///< size of the frame the poses refer to
};

/// How the frame is brought to the network's input size.
struct InputSize {
  enum class Mode {
    kFixed,   ///< letterboxed into exactly `fixed` (aspect ratio kept, padded)
    kNative,  ///< the frame's own size, padded to the model's size multiple
    kMaxSide  ///< scaled so that the longer side is `max_side` (never enlarged), then padded
  };
  Mode mode = Mode::kMaxSide;
  cv::Size fixed{256, 256};
  int max_side = 640;

  /// Parses "native", "WxH" (fixed) or "max:N"; throws jointflow::Error on anything else.
  static InputSize parse(const std::string& text);
  std::string toString() const;
};

/// The ranges of SpatialOptions' numbers, written once: validateSpatialOptions checks them, and
/// the settings schema (core/tracking/settings_schema.cpp) takes its rows' ranges from here. The
/// thresholds (person, keypoint, NMS, part) are scores, in [0, 1].
constexpr float kMaxScale = 4.f;        ///< each of scales in (0, kMaxScale]
constexpr int kMaxPersonsLimit = 1000;  ///< max_persons in [1, kMaxPersonsLimit]
constexpr int kMinTileSize = 32;        ///< tiles.size in [kMinTileSize, kMaxTileSize]
constexpr int kMaxTileSize = 8192;
constexpr float kMaxTileOverlap = 0.5f;  ///< tiles.overlap in [0, kMaxTileOverlap]
constexpr float kMinTileScale = 0.25f;   ///< tiles.scale in [kMinTileScale, kMaxTileScale]
constexpr float kMaxTileScale = 4.f;

/// Tiled inference, for people too small for the network in the whole frame: the frame is cut
/// into overlapping square tiles, each run through the network on its own (at `scale`), and the
/// poses of all tiles (and of the whole frame, `full_frame`) are merged (tiling.hpp). Why: at
/// max:640 the walkers of a 1920x1080 street scene, 50-200 px tall, are shrunk to a third, and
/// MoveNet finds 40 % of MOT17-mini's people (OpenVINO); tiles of 640 px at their own size with
/// the whole frame find 65 %, at 89 % precision against 95 %. A native 1920 px input finds 58 %:
/// it loses the people near the frame's full height.
///
/// On by default (`auto`) since 7 December 2026, with tiles of 640 px, not 512 (docs/tiles.md,
/// OpenVINO, the old default measured in the same runs):
///   - vtest.avi against our labels (per visit): ID switches 20 -> 2, IDF1 90.1 -> 91.0; per
///     person IDF1 95.0 -> 96.3. Where one whole-frame pose covered two walkers 40-120 px tall,
///     the tiles see them at their own size as two.
///   - the Bonn sequence (people 200-450 px): MOTA 89.3 -> 89.1 (cv::dnn 89.9 -> 89.5); with
///     512 px tiles 87.6, which cut more of its people.
///   - cost, one network run per tile and one for the whole frame: 768x576 has 2 tiles (vtest.avi
///     49.8 -> 16.2 frames/s here), 1920x1080 8 (41 -> 4.6 frames/s). A frame that fits in one
///     tile, and that the whole frame's run already sees at least at the tile's scale, adds none.
/// `tiles=false` is the old default, for large frames on a small CPU.
struct TileOptions {
  /// auto: on with MoveNet at one scale, off with other models (not measured with tiles; YOLO
  /// runs no tiles) or several scales (which do not go together with tiles)
  TileMode mode = TileMode::kAuto;
  int size = 640;          ///< side of a tile in frame pixels
  float overlap = 0.2f;    ///< least fraction of a tile's side shared with its neighbour, [0, 0.5]
  float scale = 1.f;       ///< network pixels per frame pixel in a tile (> 1 enlarges small people)
  bool full_frame = true;  ///< also run the whole frame at input_size (people larger than a tile)

  /// Whether tiles run: only kOn (createSpatialModel turns auto into on or off for its model).
  bool enabled() const { return mode == TileMode::kOn; }
};

struct SpatialOptions {
  std::string model_path;  ///< ONNX file; empty = the shipped default of the type
  /// Default: longer side 640 px, measured with MoveNet (tests/spatial/real_models_test.cpp): on
  /// the Bonn sequence (people 200-450 px tall, 960x540) max:640 finds 161 of 164 people (98.2 %)
  /// with 164 predictions, max:768 162 (98.8 %) but 190 predictions, native 158 (96.3 %) with
  /// 182, 256x256 129 (78.7 %). On vtest.avi frame 200 (people 40-100 px, 768x576) max:640 finds
  /// all 7 people, 5 of them with score >= 0.3; native finds 7 with 7: use native for small people.
  InputSize input_size;
  std::vector<float> scales{1.f};  ///< multi-scale inference (paper: 0.5, 1, 1.5, 2)
  /// Most poses returned per frame (MoveNet's decoder: its K). 100, not MoveNet's own 6 or the 20
  /// of before: a street scene shows 30-60 people (MOT17-04: 25 a frame), and a cap drops the
  /// lowest-scored of them. The Bonn sequence (4 people): MOTA 89.4 -> 89.9, recall 92.3 -> 92.8
  /// (a joint's score is the best of all K persons' weights there, docs/track-quality.md's run).
  int max_persons = 100;
  float person_threshold = 0.15f;          ///< poses below this person score are dropped
  float keypoint_threshold = 0.1f;         ///< keypoints below this score are reported with score 0
  float nms_threshold = 0.2f;              ///< tau_NMS for belief-map peaks (OpenPose decoder)
  std::vector<std::pair<int, int>> limbs;  ///< OpenPose decoder limb list; empty = COCO default
  float part_threshold = 0.5f;             ///< PoseNet: lowest score of a root part candidate
  float nms_radius = 20.f;                 ///< PoseNet: pose NMS radius in network input pixels
  TileOptions tiles;                       ///< tiled inference; auto by default
};

enum class PixelOrder { kBGR, kRGB };

/// Where the time of the last estimate() went, in milliseconds (for benchmarks and logs).
struct SpatialTimings {
  double preprocess_ms = 0.0;  ///< letterbox, colour order, blob
  double forward_ms = 0.0;     ///< the network's forward passes
  double decode_ms = 0.0;      ///< copying the heads, bringing scales together, decoding, mapping
  int runs = 0;                ///< network runs: one per scale, or per tile and the whole frame
};

class SpatialModel {
 public:
  virtual ~SpatialModel() = default;

  /// Estimates all poses in an 8-bit 3-channel image. Throws jointflow::Error for an empty
  /// image, a wrong type or channel count, or an image too small for the model.
  virtual SpatialResult estimate(const cv::Mat& image, PixelOrder order = PixelOrder::kBGR) = 0;

  /// The same in two steps, so that other work can overlap the network: submit() prepares the
  /// image and starts the network on it (on an asynchronous engine it returns while the network
  /// runs; the image is not needed after it returns), collect() waits for the oldest submitted
  /// frame and decodes it. A second submit() before collect() is allowed: at most two frames are
  /// pending. OpenVINO queues the second frame's run behind the first, and collect() reads the
  /// first frame's outputs while the second runs; cv::dnn fetches them at the second submit() and
  /// keeps them. estimate() = submit() + collect() and needs none pending.
  virtual void submit(const cv::Mat& image, PixelOrder order = PixelOrder::kBGR) = 0;
  virtual SpatialResult collect() = 0;
  virtual int pending() const = 0;  ///< frames submitted and not collected
  /// True when submit() returns before the network is done (OpenVINO); cv::dnn runs it in submit().
  virtual bool asynchronous() const { return false; }
  /// The engine the network runs on, e.g. "cv::dnn 4.6.0" or "OpenVINO 2026.4.1-... CPU".
  virtual std::string engine() const = 0;

  virtual ModelType type() const = 0;       ///< kMoveNet, kPoseNet or kOpenPose, never kAuto
  virtual int featureChannels() const = 0;  ///< C of SpatialResult::features
  virtual const SpatialOptions& options() const = 0;
  /// Timings of the last estimate() call; zeros before the first.
  virtual SpatialTimings lastTimings() const { return {}; }
};

/// Throws jointflow::Error naming the option (and the element's property) when an option is out of
/// range or options do not go together (tiles with several scales); createSpatialModel calls it.
void validateSpatialOptions(const SpatialOptions& options);

/// Creates a spatial model that runs on `engine`; ModelType::kAuto chooses the type from the ONNX
/// file's output names.
/// Throws jointflow::Error naming the file and what was expected when the file is missing,
/// unreadable or not a model of that type.
std::unique_ptr<SpatialModel> createSpatialModel(ModelType type, const SpatialOptions& options,
                                                 const EngineOptions& engine = {});

}  // namespace jointflow
