// The paper's geometric baselines (Eq. 8): IoU of pose boxes, PCKh and OKS between two poses.
#include <algorithm>
#include <cmath>

#include "jointflow/similarity.hpp"

namespace jointflow {
namespace {

Box detectedBox(const Pose& p, const JointThresholds& thresholds) {
  Pose only = p;
  for (int j = 0; j < kNumJoints; ++j)
    if (!isDetected(p.keypoints[j], thresholds[j])) only.keypoints[j].score = 0.f;
  return only.keypointBox(0.f);
}

float distance(const Keypoint& a, const Keypoint& b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

}  // namespace

float poseBoxIou(const Pose& a, const Pose& b, const JointThresholds& thresholds) {
  return iou(detectedBox(a, thresholds), detectedBox(b, thresholds));
}

// PoseTrack's head size is 0.6 x the diagonal of the annotated head box; COCO poses have no head
// box, so it is estimated from the body. On the Bonn train ground truth (6085 people) 0.6 x the
// head-box diagonal is a median 0.63 x the shoulder width (quartiles 0.53 and 0.81). Anthropometric
// tables put head height at about 1.6 x head breadth (ear to ear) for the fallback when the
// shoulders are missing, and a standing person at about 7.5 head heights for the last one.
float headSize(const Pose& pose, const JointThresholds& t) {
  const auto& k = pose.keypoints;
  if (isDetected(k[kLeftShoulder], t[kLeftShoulder]) &&
      isDetected(k[kRightShoulder], t[kRightShoulder])) {
    const float d = 0.63f * distance(k[kLeftShoulder], k[kRightShoulder]);
    if (d > 0.f) return d;
  }
  if (isDetected(k[kLeftEar], t[kLeftEar]) && isDetected(k[kRightEar], t[kRightEar])) {
    const float d = 1.6f * distance(k[kLeftEar], k[kRightEar]);
    if (d > 0.f) return d;
  }
  const Box box = detectedBox(pose, t);
  return std::max(box.w, box.h) / 7.5f;
}

float pckh(const Pose& a, const Pose& b, const JointThresholds& thresholds, int min_joints) {
  const float radius = 0.5f * 0.5f * (headSize(a, thresholds) + headSize(b, thresholds));
  int common = 0, correct = 0;
  for (int j = 0; j < kNumJoints; ++j) {
    if (!isDetected(a.keypoints[j], thresholds[j]) || !isDetected(b.keypoints[j], thresholds[j]))
      continue;
    ++common;
    if (distance(a.keypoints[j], b.keypoints[j]) <= radius) ++correct;
  }
  return common ? static_cast<float>(correct) / std::max(common, min_joints) : 0.f;
}

float oks(const Pose& a, const Pose& b, const JointThresholds& thresholds, float sigma_px,
          int min_joints) {
  const float area = std::max(detectedBox(a, thresholds).area(), detectedBox(b, thresholds).area());
  const float extra = sigma_px * sigma_px;
  float sum = 0.f;
  int common = 0;
  for (int j = 0; j < kNumJoints; ++j) {
    if (!isDetected(a.keypoints[j], thresholds[j]) || !isDetected(b.keypoints[j], thresholds[j]))
      continue;
    ++common;
    const float d = distance(a.keypoints[j], b.keypoints[j]);
    const float k = 2.f * kCocoSigmas[j];
    const float variance = area * k * k + extra;
    // With a degenerate scale only an exact match counts.
    sum += variance > 0.f ? std::exp(-d * d / (2.f * variance)) : (d == 0.f ? 1.f : 0.f);
  }
  return common ? sum / std::max(common, min_joints) : 0.f;
}

}  // namespace jointflow
