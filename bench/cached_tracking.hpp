// Every similarity on the same detections, through the tracker's own code path: the spatial model
// runs once per frame, and the SpatialResult goes to one jointflow::Tracker per similarity
// (Tracker::process(result, image)), so the benchmarks compare association alone and run what a
// user runs (TFF network, camera motion, coasting, future re-identification). Shared by
// bench/track_quality.cpp and bench/identity.cpp.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/posetrack.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow/tracker.hpp"

namespace jointflow::bench {

/// One frame's input: the frame (BGR) and its spatial result.
struct CachedFrame {
  cv::Mat image;
  SpatialResult spatial;
  double spatial_seconds = 0.0;  ///< time SpatialModel::estimate took
};

/// Runs the spatial model on a frame.
CachedFrame estimateFrame(SpatialModel& model, cv::Mat image);

/// What one similarity's tracker output over a run of frames.
struct TrackRun {
  std::string similarity;
  std::vector<std::vector<TrackedPose>> frames;  ///< per frame, the tracked poses
  double seconds = 0.0;  ///< Tracker::process after the spatial model (TFF network included)
};

/// One Tracker per similarity, each with `base` but its similarity (and the shipped TFF model for
/// "tff"). The trackers are made once and reset between runs.
class SimilarityTrackers {
 public:
  SimilarityTrackers(const std::vector<std::string>& similarities, const TrackerSettings& base);

  /// Resets every tracker, then hands frames 0 .. count - 1 (made by `frame_at`, which may
  /// compute or look them up; at `time_at` seconds of stream time) to every tracker in turn,
  /// frame by frame, so only one frame is held at a time. `progress` (may be empty) is called
  /// after each frame.
  std::vector<TrackRun> run(int count, const std::function<const CachedFrame&(int)>& frame_at,
                            const std::function<double(int)>& time_at,
                            const std::function<void(int)>& progress = {});

  const std::vector<std::string>& similarities() const { return similarities_; }

 private:
  std::vector<std::string> similarities_;
  std::vector<std::unique_ptr<Tracker>> trackers_;
};

/// A run's predictions in PoseTrack form, one frame per frame of `ground_truth` (file names and
/// ids taken from it). Track ids are the tracker's own: the evaluation takes any integer, so they
/// are not folded into PoseTrack's 0..999. Joints scoring below `joint_threshold` are left out
/// (poseval counts every written joint).
posetrack::Sequence predictionSequence(const posetrack::Sequence& ground_truth, const TrackRun& run,
                                       float joint_threshold);

/// Splits "a,b,c" at the commas, dropping empty items.
std::vector<std::string> splitList(const std::string& text);

}  // namespace jointflow::bench
