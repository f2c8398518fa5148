// Offline pruning of short tracks (paper, Sec. 6.2: tracks shorter than 7 frames are removed).
#include <map>

#include "jointflow/pose_associator.hpp"

namespace jointflow {

void pruneShortTracks(std::vector<std::vector<TrackedPose>>& frames, int min_length) {
  std::map<std::int64_t, int> length;
  for (const auto& frame : frames)
    for (const TrackedPose& p : frame) ++length[p.track_id];
  std::map<std::int64_t, std::int64_t> renumbered;
  for (auto& frame : frames) {
    std::vector<TrackedPose> kept;
    for (TrackedPose p : frame) {
      if (length[p.track_id] < min_length) continue;
      auto it = renumbered.try_emplace(p.track_id, static_cast<std::int64_t>(renumbered.size()) + 1)
                    .first;
      p.track_id = it->second;
      p.tentative = false;
      kept.push_back(p);
    }
    frame = std::move(kept);
  }
}

}  // namespace jointflow
