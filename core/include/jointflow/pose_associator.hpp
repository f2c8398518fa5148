// Online association of per-frame poses into tracks, without any network: the part of the
// Tracker after the spatial and temporal models. Benchmarks and evaluation feed it the same
// detections for every similarity.
//
// Per frame (docs/tracking.md has the details):
//   1. detections are filtered: minimum person size, duplicate suppression, at most max_persons;
//   2. the tracks seen in the previous frame are matched to the poses scoring >= track_score with
//      the chosen similarity (Psi, paper Eq. 5-9) and matcher (Eq. 1);
//   3. the tracks left over are matched to the low-scoring poses the same way (ByteTrack);
//   4. the camera motion is estimated and applied to the predictions of coasting tracks (and of the
//      tracks steps 2-3 left unmatched, with geometric_fallback), which are matched to the poses
//      still free on OKS with those predictions;
//   5. every high-scoring pose still free starts a track; tracks unmatched for more than
//      coast_frames end.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/spatial_model.hpp"
#include "jointflow/tracker.hpp"
#include "jointflow/types.hpp"

namespace jointflow {

/// One frame's input to the association.
struct AssociationFrame {
  Poses poses;                  ///< detections in frame pixels
  cv::Mat tff;                  ///< {1, 34, H, W} from the previous frame to this one ("tff")
  GridTransform grid_to_frame;  ///< grid of `tff`
  cv::Mat grey;                 ///< 8-bit grey frame ("flow"; camera motion when given)
};

class PoseAssociator {
 public:
  /// Uses the association fields of TrackerSettings (the model fields are ignored). Throws
  /// jointflow::Error naming the setting at fault for values out of range or unknown names.
  explicit PoseAssociator(const TrackerSettings& settings);
  ~PoseAssociator();
  PoseAssociator(PoseAssociator&&) noexcept;
  PoseAssociator& operator=(PoseAssociator&&) noexcept;

  /// Associates one frame's poses with the tracks and returns the tracked poses of this frame,
  /// in the order of the input poses. Throws jointflow::Error when the similarity lacks its input
  /// (e.g. "flow" without a grey image).
  std::vector<TrackedPose> update(const AssociationFrame& frame);
  /// The same from a spatial model's result.
  std::vector<TrackedPose> update(const SpatialResult& result, const cv::Mat& tff = {},
                                  const cv::Mat& grey = {});

  /// Forgets every track and the previous frame; ids keep counting up.
  void reset();

  /// Number of live tracks (matched in this frame or coasting).
  int liveTracks() const;
  /// The camera motion estimated for the last frame (2x3, previous -> current frame pixels).
  cv::Matx23f cameraMotion() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Offline pruning of tracks shorter than min_length frames (paper: 7), for file processing:
/// removes their poses from `frames` and renumbers the remaining ids 1, 2, ... in order of first
/// appearance.
void pruneShortTracks(std::vector<std::vector<TrackedPose>>& frames, int min_length);

/// Throws jointflow::Error naming the first association setting out of range.
void validateAssociationSettings(const TrackerSettings& settings);

}  // namespace jointflow
