// The Temporal Flow Field network runner (paper, Sec. 4.1 "Model"), on cv::dnn or OpenVINO.
//
// Channel contract (models/README.md): the ONNX input "input" is float32 [1, 2*(C+17), h, w] =
//   features(t-1) [C], beliefs(t-1) [17], features(t) [C], beliefs(t) [17]
// (SpatialResult::features and ::beliefs of the previous and the current frame, one grid H x W),
// and the output "tff" is float32 [1, 34, H, W] on the maps' grid: channel 2j = x, 2j+1 = y of COCO
// joint j. A network of stride 1 takes the maps as they are (h = H); one of stride 2 (the shipped
// tff_movenet.onnx) takes them averaged over 2x2 cells (h = H / 2), which the runner does. The
// runner tells the two apart by the output of a trial run at load.
//
// One-frame state: the runner keeps the maps of the last call and pairs them with the next call's
// maps, so each frame's maps are computed once. It is not thread-safe; use one per stream.
//
// Scale: a TFF network learns motions and people at the grid scale of its training maps. The
// shipped tff_movenet.onnx is trained at the run-time default input policy max:640 (grids of at
// most kTrainedMaxGridSide = 160 cells a side). With max_grid_side > 0, a longer grid is
// area-resampled to that many cells before the network and the field resampled back (bilinear;
// an isotropic rescale leaves the vectors' directions unchanged), which bounds the cost. It is
// off by default because it measured worse: on the Bonn sequence at input-size native (grid
// 240x136) the shipped network made 75 / 44 joint id switches at strides 3 / 4 on resampled maps
// against 42 / 11 on the native ones (docs/tracking.md): area-averaged MoveNet features are not
// the features MoveNet computes at the smaller input, while people 1.5x larger in cells are within
// the range the training videos span.
//
// Camera motion: predict() can move the previous frame's maps by the camera motion first, so the
// network compares the two frames as a still camera saw them and its field holds the people's own
// motion only. A camera that shakes by ~100 px per frame moves every joint and the background
// further than the network was trained to follow (identity benchmark, shake: tff 1252 joint id
// switches on raw maps); the association then starts each joint's line integral from its
// previous detection moved by the same motion (docs/tracking.md, step 4).
#pragma once

#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "jointflow/spatial_model.hpp"

namespace jointflow {

class TemporalFlowModel {
 public:
  /// Longest grid side of the shipped model's training maps: input policy max:640 / stride 4.
  static constexpr int kTrainedMaxGridSide = 160;

  /// Loads the ONNX file for a spatial model whose feature maps have `feature_channels` channels.
  /// Throws jointflow::Error naming the file when it is missing or unreadable, and saying what
  /// was expected when its input does not take 2*(feature_channels+17) channels, its output is not
  /// named "tff" or does not have 34 channels on the input's grid or on twice it (stride 2).
  /// max_grid_side: grids with a longer side run resampled to it (above); 0 = never (default).
  TemporalFlowModel(const std::string& onnx_path, int feature_channels,
                    const EngineOptions& dnn = {}, int max_grid_side = 0);
  ~TemporalFlowModel();
  TemporalFlowModel(TemporalFlowModel&&) noexcept;
  TemporalFlowModel& operator=(TemporalFlowModel&&) noexcept;

  /// Feeds one frame's maps (features {1, C, H, W}, beliefs {1, 17, H, W}, CV_32F). Returns the
  /// TFF {1, 34, H, W} between the previous call's maps and these, or an empty Mat when there is
  /// no previous frame (the first call, after reset(), or after the grid size changed). Throws
  /// jointflow::Error for maps of the wrong type, channel count or mismatched grids.
  /// `camera`: the camera motion previous -> this frame in grid cells (cameraMotionOnGrid); the
  /// previous maps are moved by it (bilinear, zero outside) before the network sees them.
  cv::Mat predict(const cv::Mat& features, const cv::Mat& beliefs,
                  const cv::Matx23f& camera = cv::Matx23f(1, 0, 0, 0, 1, 0));

  /// Keeps one frame's maps as the previous frame's for the next predict(), without running the
  /// network (similarity auto between close frames): the next field pairs with this frame, not
  /// with an older one. Throws as predict() does.
  void remember(const cv::Mat& features, const cv::Mat& beliefs);

  /// Forgets the previous frame's maps (a cut or seek in the stream).
  void reset();

  bool hasPrevious() const;
  int featureChannels() const;
  int inputChannels() const;  ///< 2 * (featureChannels() + 17)
  int maxGridSide() const;    ///< 0 = no resampling
  const std::string& path() const;

 private:
  // predict() (run) and remember() (not run): the input is made and kept either way.
  cv::Mat step(const cv::Mat& features, const cv::Mat& beliefs, const cv::Matx23f& camera,
               bool run);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A camera motion in frame pixels (previous -> current frame, 2x3) expressed on the maps' grid.
cv::Matx23f cameraMotionOnGrid(const cv::Matx23f& frame_motion, const GridTransform& grid_to_frame);

}  // namespace jointflow
