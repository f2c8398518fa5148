// Offline pruning of short tracks (paper, Sec. 6.2: tracks shorter than 7 frames are removed).
#include <map>

#include "jointflow/pose_associator.hpp"

namespace jointflow {

std::set<std::int64_t> longTracks(const std::vector<std::vector<std::int64_t>>& ids_per_frame,
                                  int min_length) {
  std::map<std::int64_t, int> length;
  for (const auto& ids : ids_per_frame)
    for (std::int64_t id : ids) ++length[id];
  std::set<std::int64_t> kept;
  for (const auto& [id, frames] : length)
    if (frames >= min_length) kept.insert(id);
  return kept;
}

void pruneShortTracks(std::vector<std::vector<TrackedPose>>& frames, int min_length) {
  std::vector<std::vector<std::int64_t>> ids(frames.size());
  for (size_t f = 0; f < frames.size(); ++f)
    for (const TrackedPose& p : frames[f]) ids[f].push_back(p.track_id);
  const std::set<std::int64_t> kept_ids = longTracks(ids, min_length);
  std::map<std::int64_t, std::int64_t> renumbered;
  for (auto& frame : frames) {
    std::vector<TrackedPose> kept;
    for (TrackedPose p : frame) {
      if (!kept_ids.count(p.track_id)) continue;
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
