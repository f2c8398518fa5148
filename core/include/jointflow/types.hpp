// Basic pose types shared by every part of JointFlow.
//
// A pose is always 17 keypoints in COCO order, in frame pixels (x right, y down). A keypoint whose
// score is 0 was not detected. Models with other joint sets map onto COCO-17 in their decoder;
// the PoseTrack joint set is derived from COCO-17 only when reading or writing PoseTrack files
// (see posetrack_joints.hpp).
#pragma once

#include <array>
#include <string_view>
#include <utility>
#include <vector>

namespace jointflow {

constexpr int kNumJoints = 17;

/// COCO-17 joint indices.
enum Joint : int {
  kNose = 0,
  kLeftEye,
  kRightEye,
  kLeftEar,
  kRightEar,
  kLeftShoulder,
  kRightShoulder,
  kLeftElbow,
  kRightElbow,
  kLeftWrist,
  kRightWrist,
  kLeftHip,
  kRightHip,
  kLeftKnee,
  kRightKnee,
  kLeftAnkle,
  kRightAnkle,
};

/// COCO keypoint names, in joint order ("nose", "left_eye", ...).
extern const std::array<std::string_view, kNumJoints> kJointNames;

/// The COCO skeleton: 19 limbs as pairs of joint indices (used by drawing and OpenPose decoding).
extern const std::vector<std::pair<int, int>> kCocoSkeleton;

/// Left/right swap of each joint (for horizontal flips).
extern const std::array<int, kNumJoints> kFlipJoint;

/// COCO keypoint sigmas used by OKS (Ronchi & Perona / cocoapi), in joint order.
extern const std::array<float, kNumJoints> kCocoSigmas;

struct Keypoint {
  float x = 0.f;
  float y = 0.f;
  float score = 0.f;  ///< 0 = not detected; models give values in [0, 1].
};

struct Box {
  float x = 0.f;  ///< left
  float y = 0.f;  ///< top
  float w = 0.f;
  float h = 0.f;
  float area() const { return w > 0.f && h > 0.f ? w * h : 0.f; }
};

struct Pose {
  std::array<Keypoint, kNumJoints> keypoints{};
  float score = 0.f;  ///< person score in [0, 1]
  Box box;            ///< person box in frame pixels (from the model, or from the keypoints)

  /// Number of keypoints with score >= threshold.
  int countVisible(float threshold) const;
  /// Tight box around the keypoints with score >= threshold; empty box when none.
  Box keypointBox(float threshold) const;
};

using Poses = std::vector<Pose>;

/// Area common to two boxes, in square pixels; 0 when they do not overlap.
float intersectionArea(const Box& a, const Box& b);

/// Intersection over union of two boxes; 0 when either is empty.
float iou(const Box& a, const Box& b);

}  // namespace jointflow
