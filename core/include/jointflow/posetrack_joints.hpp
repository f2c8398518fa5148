// The PoseTrack joint set and how JointFlow's COCO-17 poses are written in it.
//
// PoseTrack scores 15 joints, numbered as in its 2017 "annolist" files (the ids below). Its 2018
// files list 17 keypoints by name (nose, head_bottom, head_top, left_ear, right_ear, shoulders,
// ...); the ears are not scored and head_bottom is the neck.
//
// COCO-17 models have eyes and ears but neither a neck nor a head top, so the writer derives them:
//   neck     = midpoint of the two shoulders; score = the lower shoulder score.
//              On the Bonn PoseTrack ground truth (31 sequences, 6313 people) this point lies a
//              median 0.34 head sizes from the annotated head_bottom, within PCKh@0.5 for 82 %.
//   head_top = F + kHeadTopExtension * (F - neck), F the face point: the nose, else the mean of
//              the detected eyes, else the mean of the detected ears; score = min(face, neck).
//              kHeadTopExtension = 0.47 is the median of (head_top - nose) projected on
//              (nose - shoulder midpoint) over the 26 annotated people of the PoseTrack18
//              fixtures in ../shared/data (the Bonn data has no nose to measure it on).
// poseval counts every written joint whatever its score (a low-score joint is a false positive
// for MOTA), so joints below the caller's score threshold are not written at all.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "jointflow/types.hpp"

namespace jointflow::posetrack {

constexpr int kNumPoseTrackJoints = 15;

/// PoseTrack joint ids (the "id" of a point in a PoseTrack 2017 file; poseval's order).
enum PoseTrackJoint : int {
  kPtRightAnkle = 0,
  kPtRightKnee,
  kPtRightHip,
  kPtLeftHip,
  kPtLeftKnee,
  kPtLeftAnkle,
  kPtRightWrist,
  kPtRightElbow,
  kPtRightShoulder,
  kPtLeftShoulder,
  kPtLeftElbow,
  kPtLeftWrist,
  kPtNeck,  ///< "head_bottom" in PoseTrack 2018 files
  kPtNose,
  kPtHeadTop,
};

/// poseval's joint names, by PoseTrack id ("right_ankle", ..., "neck", "nose", "head_top").
extern const std::array<std::string_view, kNumPoseTrackJoints> kPoseTrackJointNames;

/// The 17 keypoint names of a PoseTrack 2018 file, in the order its "categories" list them.
extern const std::array<std::string_view, 17> kPoseTrack18KeypointNames;

/// PoseTrack id of a PoseTrack 2018 keypoint name ("head_bottom" -> kPtNeck); nullopt for names
/// poseval does not score (the ears) or does not know.
std::optional<int> poseTrackJointFromName(std::string_view name);

/// COCO-17 joint that maps directly onto each PoseTrack joint; -1 for the derived neck and head
/// top.
extern const std::array<int, kNumPoseTrackJoints> kCocoOfPoseTrackJoint;

/// Ratio of the head top's distance beyond the face point to the neck-to-face distance.
constexpr float kHeadTopExtension = 0.47f;

/// One joint of a person in PoseTrack coordinates (frame pixels).
struct PoseTrackPoint {
  double x = 0.0;
  double y = 0.0;
  std::optional<double> score;  ///< predictions carry one; ground truth does not
  int visible = 1;              ///< ground truth's is_visible flag (not used by the metrics)
};

using PoseTrackJoints = std::array<std::optional<PoseTrackPoint>, kNumPoseTrackJoints>;

/// The PoseTrack joints of a COCO-17 pose by the rules above; joints whose score is below
/// `joint_threshold` (or 0, i.e. undetected) are left out.
PoseTrackJoints toPoseTrackJoints(const Pose& pose, float joint_threshold);

/// Maps the tracker's stream-wide ids (counting up without end) onto PoseTrack track ids in
/// 0..999 (poseval's limit), unique within each frame. A track keeps its number, also across
/// frames it is missing from, until the number is given to a new track: new tracks take the
/// numbers in turn (0, 1, ..., 999, 0, ...), skipping those of the tracks in the same frame. So
/// numbers are reused only after 1000 new tracks, which poseval cannot tell apart from a returning
/// track (unavoidable within its id range).
class TrackIdMap {
 public:
  static constexpr int kMaxIds = 1000;

  /// PoseTrack ids for the tracker ids present in one frame, in the same order. Throws
  /// jointflow::Error for a repeated id or for more than 1000 ids in one frame.
  std::vector<int> assign(const std::vector<std::int64_t>& tracker_ids);

 private:
  std::unordered_map<std::int64_t, int> number_of_;
  std::array<std::optional<std::int64_t>, kMaxIds> owner_{};
  int next_ = 0;
};

}  // namespace jointflow::posetrack
