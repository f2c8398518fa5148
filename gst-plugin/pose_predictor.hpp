// Poses for the frames on which the networks do not run (jointflowtrack's inference-interval, or
// frames skipped because they arrived late): each track seen on the last inferred frame is moved
// on with its own velocity, measured between its last two inferred frames. Holding the last poses
// instead would make them stand still and then jump at the next inference; dropping them would
// make them flicker. Extrapolation stops after `max_horizon` frames, after which poses hold.
//
// No GStreamer here: positions are frame indices of the stream.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "jointflow/tracker.hpp"

namespace jointflow::gst {

class PosePredictor {
 public:
  explicit PosePredictor(int max_horizon = 30) : max_horizon_(max_horizon) {}

  /// Records the tracker's output for the inferred frame @frame (frame indices increase).
  void observe(const std::vector<TrackedPose>& poses, std::int64_t frame);

  /// The poses of the last inferred frame moved on to @frame (> the last observed frame).
  std::vector<TrackedPose> predict(std::int64_t frame) const;

  /// Forgets every track (a cut, a seek, a new resolution).
  void reset() {
    tracks_.clear();
    order_.clear();
  }

 private:
  struct Motion {
    TrackedPose last;
    std::int64_t frame = 0;
    std::array<float, 2 * kNumJoints> velocity{};  ///< px per frame, x and y per joint
    float box_vx = 0.f, box_vy = 0.f;
  };
  std::unordered_map<std::int64_t, Motion> tracks_;  ///< tracks of the last inferred frame
  std::vector<std::int64_t> order_;                  ///< their output order
  int max_horizon_;
};

}  // namespace jointflow::gst
