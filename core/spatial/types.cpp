#include "jointflow/types.hpp"

#include <algorithm>
#include <limits>

namespace jointflow {

const std::array<std::string_view, kNumJoints> kJointNames = {
    "nose",           "left_eye",   "right_eye",   "left_ear",   "right_ear",   "left_shoulder",
    "right_shoulder", "left_elbow", "right_elbow", "left_wrist", "right_wrist", "left_hip",
    "right_hip",      "left_knee",  "right_knee",  "left_ankle", "right_ankle"};

const std::vector<std::pair<int, int>> kCocoSkeleton = {
    {kLeftAnkle, kLeftKnee},     {kLeftKnee, kLeftHip},
    {kRightAnkle, kRightKnee},   {kRightKnee, kRightHip},
    {kLeftHip, kRightHip},       {kLeftShoulder, kLeftHip},
    {kRightShoulder, kRightHip}, {kLeftShoulder, kRightShoulder},
    {kLeftShoulder, kLeftElbow}, {kRightShoulder, kRightElbow},
    {kLeftElbow, kLeftWrist},    {kRightElbow, kRightWrist},
    {kLeftEye, kRightEye},       {kNose, kLeftEye},
    {kNose, kRightEye},          {kLeftEye, kLeftEar},
    {kRightEye, kRightEar},      {kLeftEar, kLeftShoulder},
    {kRightEar, kRightShoulder}};

const std::array<int, kNumJoints> kFlipJoint = {
    kNose,         kRightEye,   kLeftEye,   kRightEar,   kLeftEar,   kRightShoulder,
    kLeftShoulder, kRightElbow, kLeftElbow, kRightWrist, kLeftWrist, kRightHip,
    kLeftHip,      kRightKnee,  kLeftKnee,  kRightAnkle, kLeftAnkle};

const std::array<float, kNumJoints> kCocoSigmas = {.026f, .025f, .025f, .035f, .035f, .079f,
                                                   .079f, .072f, .072f, .062f, .062f, .107f,
                                                   .107f, .087f, .087f, .089f, .089f};

int Pose::countVisible(float threshold) const {
  return static_cast<int>(std::count_if(keypoints.begin(), keypoints.end(),
                                        [&](const Keypoint& k) { return k.score >= threshold; }));
}

Box Pose::keypointBox(float threshold) const {
  float x0 = std::numeric_limits<float>::max(), y0 = x0;
  float x1 = std::numeric_limits<float>::lowest(), y1 = x1;
  bool any = false;
  for (const auto& k : keypoints) {
    if (k.score < threshold || k.score <= 0.f) continue;
    any = true;
    x0 = std::min(x0, k.x);
    y0 = std::min(y0, k.y);
    x1 = std::max(x1, k.x);
    y1 = std::max(y1, k.y);
  }
  if (!any) return {};
  return {x0, y0, x1 - x0, y1 - y0};
}

float intersectionArea(const Box& a, const Box& b) {
  const float ix = std::max(0.f, std::min(a.x + a.w, b.x + b.w) - std::max(a.x, b.x));
  const float iy = std::max(0.f, std::min(a.y + a.h, b.y + b.h) - std::max(a.y, b.y));
  return ix * iy;
}

float iou(const Box& a, const Box& b) {
  const float inter = intersectionArea(a, b);
  const float uni = a.area() + b.area() - inter;
  return uni > 0.f ? inter / uni : 0.f;
}

}  // namespace jointflow
