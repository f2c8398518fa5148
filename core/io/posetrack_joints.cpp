#include "jointflow/posetrack_joints.hpp"

#include <algorithm>
#include <unordered_set>

#include "jointflow/error.hpp"

namespace jointflow::posetrack {

const std::array<std::string_view, kNumPoseTrackJoints> kPoseTrackJointNames = {
    "right_ankle", "right_knee",  "right_hip",   "left_hip",       "left_knee",
    "left_ankle",  "right_wrist", "right_elbow", "right_shoulder", "left_shoulder",
    "left_elbow",  "left_wrist",  "neck",        "nose",           "head_top"};

const std::array<std::string_view, 17> kPoseTrack18KeypointNames = {
    "nose",           "head_bottom", "head_top",    "left_ear",   "right_ear",   "left_shoulder",
    "right_shoulder", "left_elbow",  "right_elbow", "left_wrist", "right_wrist", "left_hip",
    "right_hip",      "left_knee",   "right_knee",  "left_ankle", "right_ankle"};

const std::array<int, kNumPoseTrackJoints> kCocoOfPoseTrackJoint = {
    kRightAnkle, kRightKnee,  kRightHip,   kLeftHip,       kLeftKnee,
    kLeftAnkle,  kRightWrist, kRightElbow, kRightShoulder, kLeftShoulder,
    kLeftElbow,  kLeftWrist,  -1,          kNose,          -1};

std::optional<int> poseTrackJointFromName(std::string_view name) {
  if (name == "head_bottom") return kPtNeck;
  for (int j = 0; j < kNumPoseTrackJoints; ++j) {
    if (j != kPtNeck && kPoseTrackJointNames[j] == name) return j;
  }
  return std::nullopt;
}

namespace {

struct ScoredPoint {
  double x = 0.0, y = 0.0, score = 0.0;
};

/// Mean of the given COCO joints that are detected (score > 0); nullopt when none is.
/// The score is the lowest among those used.
std::optional<ScoredPoint> meanOfDetected(const Pose& pose, std::initializer_list<int> joints) {
  ScoredPoint sum;
  sum.score = 1e9;
  int n = 0;
  for (int j : joints) {
    const Keypoint& k = pose.keypoints[j];
    if (k.score <= 0.f) continue;
    sum.x += k.x;
    sum.y += k.y;
    sum.score = std::min<double>(sum.score, k.score);
    ++n;
  }
  if (n == 0) return std::nullopt;
  return ScoredPoint{sum.x / n, sum.y / n, sum.score};
}

/// Midpoint of both shoulders (both needed: one shoulder alone is far off the midline).
std::optional<ScoredPoint> shoulderMidOf(const Pose& pose) {
  const Keypoint& l = pose.keypoints[kLeftShoulder];
  const Keypoint& r = pose.keypoints[kRightShoulder];
  if (l.score <= 0.f || r.score <= 0.f) return std::nullopt;
  return ScoredPoint{(l.x + r.x) / 2.0, (l.y + r.y) / 2.0, std::min(l.score, r.score)};
}

/// The face point: the nose, else the mean of the detected eyes, else of the detected ears.
std::optional<ScoredPoint> faceOf(const Pose& pose) {
  std::optional<ScoredPoint> face = meanOfDetected(pose, {kNose});
  if (!face) face = meanOfDetected(pose, {kLeftEye, kRightEye});
  if (!face) face = meanOfDetected(pose, {kLeftEar, kRightEar});
  return face;
}

/// S + k * (F - S), scored by the lower of the two.
ScoredPoint along(const ScoredPoint& s, const ScoredPoint& f, double k) {
  return {s.x + k * (f.x - s.x), s.y + k * (f.y - s.y), std::min(s.score, f.score)};
}

}  // namespace

PoseTrackJoints toPoseTrackJoints(const Pose& pose, float joint_threshold) {
  PoseTrackJoints out;
  auto put = [&](int pt_joint, const std::optional<ScoredPoint>& p) {
    if (!p || p->score <= 0.0 || p->score < joint_threshold) return;
    out[pt_joint] = PoseTrackPoint{p->x, p->y, p->score, 1};
  };
  for (int j = 0; j < kNumPoseTrackJoints; ++j) {
    const int coco = kCocoOfPoseTrackJoint[j];
    if (coco < 0) continue;
    const Keypoint& k = pose.keypoints[coco];
    put(j, ScoredPoint{k.x, k.y, k.score});
  }
  // Neck and head top by the fitted rule in posetrack_joints.hpp.
  const std::optional<ScoredPoint> mid = shoulderMidOf(pose);
  const std::optional<ScoredPoint> face = mid ? faceOf(pose) : std::nullopt;
  if (mid && face) {
    const ScoredPoint neck = along(*mid, *face, kNeckAlongFace);
    put(kPtNeck, neck);
    ScoredPoint top = along(*mid, *face, 1.0 + kHeadTopExtension);
    top.score = std::min(face->score, neck.score);
    const Keypoint& l = pose.keypoints[kLeftShoulder];
    const Keypoint& r = pose.keypoints[kRightShoulder];
    double nx = l.y - r.y, ny = r.x - l.x;  // normal of the shoulder line, length w
    if (nx * (face->x - mid->x) + ny * (face->y - mid->y) < 0) nx = -nx, ny = -ny;
    if (nx != 0.0 || ny != 0.0) {  // mean with the estimate from the shoulders
      top.x = 0.5 * (top.x + mid->x + kHeadTopAboveShoulders * nx);
      top.y = 0.5 * (top.y + mid->y + kHeadTopAboveShoulders * ny);
    }
    put(kPtHeadTop, top);
  } else {
    put(kPtNeck, mid);
  }
  return out;
}

std::vector<int> TrackIdMap::assign(const std::vector<std::int64_t>& tracker_ids) {
  if (tracker_ids.size() > static_cast<std::size_t>(kMaxIds)) {
    throw Error("PoseTrack track ids: " + std::to_string(tracker_ids.size()) +
                " people in one frame, but PoseTrack allows ids 0..999 only");
  }
  std::unordered_set<std::int64_t> present(tracker_ids.begin(), tracker_ids.end());
  if (present.size() != tracker_ids.size()) {
    throw Error("PoseTrack track ids: a tracker id appears twice in one frame");
  }
  // Numbers held by the tracks of this frame that already have one must not be given out.
  std::array<bool, kMaxIds> taken{};
  for (std::int64_t id : tracker_ids) {
    auto it = number_of_.find(id);
    if (it != number_of_.end()) taken[it->second] = true;
  }
  std::vector<int> out;
  out.reserve(tracker_ids.size());
  for (std::int64_t id : tracker_ids) {
    auto it = number_of_.find(id);
    if (it != number_of_.end()) {
      out.push_back(it->second);
      continue;
    }
    while (taken[next_]) next_ = (next_ + 1) % kMaxIds;
    const int number = next_;
    next_ = (next_ + 1) % kMaxIds;
    if (owner_[number]) number_of_.erase(*owner_[number]);  // the old track loses it
    owner_[number] = id;
    number_of_[id] = number;
    taken[number] = true;
    out.push_back(number);
  }
  return out;
}

}  // namespace jointflow::posetrack
