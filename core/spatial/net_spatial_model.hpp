// Internal: what the three network-backed spatial models share. Per frame and scale: letterbox,
// forward, read the heads by name; then bring all scales onto the grid of the scale closest to 1
// and average them; then decode in grid cells and map to frame pixels.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "../engine/mat_pool.hpp"
#include "../engine/network.hpp"
#include "jointflow/grid_resample.hpp"
#include "jointflow/letterbox.hpp"
#include "jointflow/spatial_model.hpp"

namespace jointflow::detail {

/// One output of the network: its name and the displacement fields among its channels.
struct HeadSpec {
  std::string name;
  std::vector<DisplacementChannels> displacements;
};

struct NetSpec {
  ModelType type = ModelType::kMoveNet;
  std::string what;             ///< human-readable name for messages
  std::vector<HeadSpec> heads;  ///< required outputs
  std::string features;         ///< output holding the backbone features
  SizeRule rule;                ///< accepted input sizes
  double input_scale = 1.0;     ///< network input = (RGB - input_mean) * input_scale
  double input_mean = 0.0;
  /// input = stride * cell. 0: inferred from the output grid (input size / grid size).
  float stride = 0.f;
  /// Output grid size for an input size (H or W); nullptr = input / stride.
  int (*grid_of_input)(int) = nullptr;
};

class NetSpatialModel : public SpatialModel {
 public:
  /// Opens the network on `engine` (the models keep no engine setting: the network has it).
  NetSpatialModel(NetSpec spec, SpatialOptions options, const EngineOptions& engine);

  SpatialResult estimate(const cv::Mat& image, PixelOrder order) override;
  void submit(const cv::Mat& image, PixelOrder order) override;
  SpatialResult collect() override;
  int pending() const override;
  bool asynchronous() const override { return net_->asynchronous(); }
  std::string engine() const override { return net_->engineName(); }
  ModelType type() const override { return spec_.type; }
  int featureChannels() const override { return feature_channels_; }
  const SpatialOptions& options() const override { return options_; }
  SpatialTimings lastTimings() const override { return timings_; }

 protected:
  using Tensors = std::map<std::string, cv::Mat>;

  /// Applied to one scale's outputs before the scales are brought together (e.g. a sigmoid).
  virtual void prepare(Tensors& /*outputs*/) const {}
  /// Poses in grid cells (x = column, y = row) from the fused outputs.
  virtual Poses decode(const Tensors& fused, float stride) const = 0;
  /// The {1, 17, H, W} joint belief maps, values in [0, 1], from the fused outputs.
  virtual cv::Mat beliefs(const Tensors& fused) const = 0;

  NetSpec spec_;
  SpatialOptions options_;

 private:
  /// One network run of a frame: a part of it (the whole frame, or a tile) at an input size.
  struct View {
    cv::Rect crop;  ///< in frame pixels
    InputSize policy;
    float scale = 1.f;
  };
  struct ScaleOutput {
    Tensors tensors;
    GridTransform grid_to_frame;
    cv::Size grid;
    float stride = 0.f;
    cv::Rect crop;  ///< the view's part of the frame
  };
  /// A frame between submit() and collect(): the scales run so far; the last one may still be on
  /// the engine (`in_flight`) with its letterbox in `box`.
  struct Frame {
    cv::Size size;
    std::vector<ScaleOutput> scales;
    Letterbox box;
    cv::Rect crop;  ///< of the view in `box`
    bool in_flight = false;
    std::chrono::steady_clock::time_point started;
    SpatialTimings timings;
    bool tiled = false;  ///< its runs are tiles (tiledAt, decided once at submit())
  };
  /// The runs of a frame of `size`: one per scale, or, `tiled`, the tiles (and the whole frame).
  std::vector<View> views(cv::Size size, bool tiled) const;
  /// Whether a frame of `size` runs tiles: tiles on, unless its one tile is the whole frame and
  /// the whole frame's run sees it at least at the tiles' scale (a second run of the same).
  bool tiledAt(cv::Size size) const;
  /// The letterbox of one view: the network's input image; sets f.box and f.crop.
  cv::Mat inputImage(Frame& f, const cv::Mat& image, const View& view);
  /// Starts the network on the input image; the frame is then in flight.
  void launch(Frame& f, const cv::Mat& input, PixelOrder order);
  void finishScale(Frame& f);
  void drain(Frame& f);
  ScaleOutput readOutputs(const Letterbox& box, std::vector<cv::Mat> outs, Frame& f);
  SpatialResult fuse(Frame& f);
  /// fuse() for tiles: each run decoded on its own, the poses merged (tiling.hpp).
  SpatialResult fuseTiles(Frame& f);
  /// Without a full-frame run: the tiles' features and beliefs on one grid over the frame, at the
  /// tiles' scale, into `result`.
  void stitchMaps(const Frame& f, SpatialResult& result) const;
  /// Decoded poses of grid cells to frame pixels, below the thresholds dropped or zeroed.
  Poses toFrame(Poses poses, const GridTransform& t) const;

  std::unique_ptr<Network> net_;
  /// The letterboxed input images: the one of the frame before may still be on the engine.
  MatPool images_;
  std::vector<std::string> names_;
  int feature_channels_ = 0;
  SpatialTimings timings_;
  /// Oldest first, at most two: on the engine, or with their outputs fetched already (an engine
  /// with one run at a time: the older one, when the newer one started).
  std::vector<Frame> frames_;
};

}  // namespace jointflow::detail
