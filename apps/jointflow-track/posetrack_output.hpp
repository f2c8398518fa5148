// jointflow-track's PoseTrack 2018 output: one frame per buffer the tracker passed, named after
// the source frame it came from, written by the core's writer (posetrack.hpp).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "jointflow/posetrack.hpp"
#include "jointflowmeta.h"

namespace jointflow::cli {

class PoseTrackOutput {
 public:
  /// `frame_names[k]` names source frame k (a folder's files); without one, frames are named
  /// "%06d.jpg" after their index, as PoseTrack names the frames of a video.
  PoseTrackOutput(std::string sequence, std::string file_prefix,
                  std::vector<std::string> frame_names, float joint_threshold);

  /// The poses of source frame `index` (meta may be null: no person). Source frames skipped
  /// since the last call (not decodable, dropped) are listed without people: PoseTrack files list
  /// every frame of the sequence. An index not after the last one is taken as the next frame.
  void addFrame(std::int64_t index, const GstJointFlowMeta* meta);
  /// Lists the frames up to `count` (the source's frame count, when known) without people.
  void fillTo(std::int64_t count);

  /// Drops the people of tracks seen on fewer than `min_frames` frames (the paper's offline
  /// pruning, Sec. 6.2; 0 = none).
  void pruneShortTracks(int min_frames);

  /// DIR/<sequence>.json
  std::string path(const std::string& dir) const;
  void write(const std::string& dir) const;

 private:
  void addEmptyFrame(std::int64_t index);
  std::string fileName(std::int64_t index) const;

  posetrack::Sequence sequence_;
  std::vector<std::vector<std::int64_t>> tracker_ids_;  ///< per frame, of its people
  posetrack::TrackIdMap ids_;
  std::string file_prefix_;
  std::vector<std::string> frame_names_;
  float joint_threshold_;
};

}  // namespace jointflow::cli
