// One frame of poseval's assignGTmulti: what the AP and MOT parts need from a frame.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "jointflow/hota.hpp"
#include "jointflow/posetrack.hpp"

namespace jointflow::eval {

/// A predicted joint's score and whether it matched the ground truth its person was given to.
struct ScoredJoint {
  double score = 0.0;
  bool matched = false;
};

/// The input of one MotAccumulator::update for one joint class.
struct JointMotInput {
  std::vector<std::int64_t> gt_ids;
  std::vector<std::int64_t> pred_ids;
  std::vector<double> distances;  ///< gt x pred, NaN where d > threshold
};

struct FrameMatch {
  std::array<std::vector<ScoredJoint>, posetrack::kNumPoseTrackJoints> scored;
  std::array<int, posetrack::kNumPoseTrackJoints> num_gt{};
  std::array<JointMotInput, posetrack::kNumPoseTrackJoints> mot;
  /// Per joint: the people having it on each side (their real ids, also in frames poseval's quirk
  /// fills with a dummy) and PoseTrack21's keypoint similarity max(0, 1 - d / 0.5001).
  std::array<HotaFrame, posetrack::kNumPoseTrackJoints> hota;
};

/// Matches the predictions of one frame to its ground truth (both already cleaned of people
/// without points and of ignored joints). `where` names the frame in errors.
FrameMatch matchFrame(const posetrack::Frame& gt, const posetrack::Frame& pred, double threshold,
                      bool empty_frame_one_miss, const std::string& where);

}  // namespace jointflow::eval
