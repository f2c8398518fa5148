// Synthetic people and sequences for the tracking tests: exact geometry, known identities.
#pragma once

#include <functional>
#include <map>
#include <vector>

#include "jointflow/pose_associator.hpp"
#include "jointflow/temporal_flow.hpp"
#include "jointflow/types.hpp"

namespace jointflow::test {

/// A standing person, 120 px tall and about 40 px wide, whose hip centre is at `at`.
inline Pose standingPerson(cv::Point2f at, float score = 0.9f) {
  // Offsets from the hip centre in px, COCO order.
  static const float offsets[kNumJoints][2] = {
      {0, -100}, {-4, -104}, {4, -104}, {-9, -100}, {9, -100}, {-18, -78},
      {18, -78}, {-22, -48}, {22, -48}, {-22, -20}, {22, -20}, {-10, 0},
      {10, 0},   {-11, 32},  {11, 32},  {-12, 62},  {12, 62}};
  Pose p;
  for (int j = 0; j < kNumJoints; ++j)
    p.keypoints[j] = {at.x + offsets[j][0], at.y + offsets[j][1], score};
  p.score = score;
  p.box = p.keypointBox(0.f);
  return p;
}

/// One frame of ground truth: identity -> pose.
using GroundTruthFrame = std::map<int, Pose>;

/// The grid of the oracle TFF: stride 4 in frame pixels, as MoveNet's maps.
inline GridTransform oracleGrid() {
  return {4.f, 4.f, 0.f, 0.f};
}

/// The TFF rendered from the ground truth of two consecutive frames (paper Eq. 2-4).
inline cv::Mat oracleTff(const GroundTruthFrame& previous, const GroundTruthFrame& current,
                         cv::Size frame, float sigma = 1.f) {
  std::vector<JointMotion> motions;
  for (const auto& [id, pose] : current) {
    auto it = previous.find(id);
    if (it == previous.end()) continue;
    const auto m = jointMotions(it->second, pose, oracleGrid(), 0.f);
    motions.insert(motions.end(), m.begin(), m.end());
  }
  return renderTemporalFlowField(motions, kNumJoints, {frame.width / 4, frame.height / 4}, sigma);
}

struct IdentityReport {
  int id_switches = 0;  ///< times an identity was reported under another track id than before
  bool exact = true;    ///< every identity kept one track id and no two shared one
};

/// Runs an associator over a sequence (poses fed in the order of the map) and compares the track
/// ids with the identities. `with_tff` feeds the oracle TFF; `grey`, if given, the frame images.
inline IdentityReport runSequence(
    PoseAssociator& associator, const std::vector<GroundTruthFrame>& frames, cv::Size frame_size,
    bool with_tff, const std::function<cv::Mat(size_t)>& grey = nullptr,
    const std::function<void(size_t, AssociationFrame&)>& prepare = nullptr) {
  IdentityReport report;
  std::map<int, std::int64_t> last_track;
  std::map<std::int64_t, int> owner;
  for (size_t t = 0; t < frames.size(); ++t) {
    AssociationFrame in;
    std::vector<int> ids;
    for (const auto& [id, pose] : frames[t]) {
      in.poses.push_back(pose);
      ids.push_back(id);
    }
    in.grid_to_frame = oracleGrid();
    if (with_tff && t > 0) in.tff = oracleTff(frames[t - 1], frames[t], frame_size);
    if (grey) in.grey = grey(t);
    if (prepare) prepare(t, in);
    for (const TrackedPose& tp : associator.update(in)) {
      const int id = ids.at(tp.detection);
      auto it = last_track.find(id);
      if (it != last_track.end() && it->second != tp.track_id) {
        ++report.id_switches;
        report.exact = false;
      }
      last_track[id] = tp.track_id;
      auto [o, inserted] = owner.emplace(tp.track_id, id);
      if (!inserted && o->second != id) report.exact = false;
    }
  }
  return report;
}

inline TrackerSettings settingsFor(const std::string& similarity) {
  TrackerSettings s;
  s.similarity = parseEnum<SimilarityType>(similarity);
  return s;
}

}  // namespace jointflow::test
