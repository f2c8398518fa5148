// The PoseTrack joint set and how JointFlow's COCO-17 poses are written in it.
//
// PoseTrack scores 15 joints, numbered as in its 2017 "annolist" files (the ids below). Its 2018
// files list 17 keypoints by name (nose, head_bottom, head_top, left_ear, right_ear, shoulders,
// ...); the ears are not scored and head_bottom is the neck.
//
// COCO-17 models have eyes and ears but neither a neck nor a head top, so the writer derives them
// from the shoulder midpoint S and the face point F (the nose, else the mean of the detected eyes,
// else of the detected ears), v = F - S:
//   neck     = S + kNeckAlongFace * v; score = min(both shoulders, face). Without a face point:
//              S, score = the lower shoulder score.
//   head_top = the mean of two estimates: F + kHeadTopExtension * v (from the face) and
//              S + kHeadTopAboveShoulders * w * n (from the shoulders: w their distance, n the unit
//              normal of the shoulder line on the face's side); the face estimate alone when the
//              shoulders coincide. Score = min(face, neck). None without a face point. (Their
//              errors are largely independent: a tilted head moves the nose, not the shoulders.
//              On the 13 PoseTrack 2018 people below, the mean is within PCKh@0.5 for 10, each
//              estimate alone for 7.)
// The constants are fitted by training/fit_head_joints.py (medians of per-person ratios) on real
// annotations, never on the Bonn test sequence:
//   kHeadTopExtension = 0.605: the head top's distance beyond the nose along v, in units of |v|,
//     with MoveNet's nose and shoulders (21 matches of the 13 annotated people of the PoseTrack
//     2018 fixtures in ../shared/data, MoveNet at max:640/960/1280/native; quartiles 0.45-0.80;
//     on the annotated nose and shoulders: 0.47).
//   kNeckAlongFace = 0.309 = R x (1 + kHeadTopExtension), R = 0.193 the neck's place on the line
//     from S to the head top, median over 6124 people of the Bonn train annotations (no nose
//     there; quartiles 0.13-0.25; the PoseTrack 2018 fixtures give 0.22). The previous rule, neck
//     = S, lay a median 0.34 head sizes below the annotated head_bottom.
//   kHeadTopAboveShoulders = 0.971: (head_top - S) . n / w, median over 6112 people of the Bonn
//     train annotations (quartiles 0.83-1.26).
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

/// The head top's distance beyond the face point, in units of the shoulder-midpoint-to-face
/// distance (fitted: above).
constexpr float kHeadTopExtension = 0.605f;
/// The neck's distance from the shoulder midpoint towards the face point, in the same unit.
constexpr float kNeckAlongFace = 0.309f;
/// The head top's height above the shoulder midpoint, in shoulder widths (fitted: above).
constexpr float kHeadTopAboveShoulders = 0.971f;

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
