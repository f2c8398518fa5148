// Test helper: YOLO pose outputs ({1, 56, N}, yolo_pose_decoder.hpp) written from known people, so
// that what the decoder and the model return can be checked exactly.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/yolo_pose_decoder.hpp"

namespace jointflow::test {

/// One anchor's values in the network's terms: box centre and size, keypoints in input pixels
/// with Ultralytics' convention (pixel i's left edge at i).
struct YoloAnchor {
  float cx, cy, w, h, score;
  std::array<Keypoint, kNumJoints> joints;
};

/// A person of `w` x `h` centred at (cx, cy): joint j at a place of its own inside the box (so
/// that a swapped joint order shows), scored 0.9 - 0.05 j.
inline YoloAnchor yoloPerson(float cx, float cy, float w, float h, float score) {
  YoloAnchor a{cx, cy, w, h, score, {}};
  for (int j = 0; j < kNumJoints; ++j) {
    a.joints[j] = {cx - 0.4f * w + 0.05f * w * j, cy - 0.45f * h + 0.055f * h * j,
                   0.9f - 0.05f * j};
  }
  return a;
}

/// {1, 56, N} with the anchors first and the rest of the N columns all zero (score 0).
inline cv::Mat yoloOutput(const std::vector<YoloAnchor>& anchors, int n) {
  cv::Mat out(std::vector<int>{1, kYoloPoseValues, n}, CV_32F, cv::Scalar(0));
  auto at = [&](int v, int a) -> float& { return out.ptr<float>(0, v)[a]; };
  for (int a = 0; a < static_cast<int>(anchors.size()); ++a) {
    const YoloAnchor& p = anchors[a];
    at(0, a) = p.cx, at(1, a) = p.cy, at(2, a) = p.w, at(3, a) = p.h, at(4, a) = p.score;
    for (int j = 0; j < kNumJoints; ++j) {
      at(5 + 3 * j, a) = p.joints[j].x;
      at(6 + 3 * j, a) = p.joints[j].y;
      at(7 + 3 * j, a) = p.joints[j].score;
    }
  }
  return out;
}

}  // namespace jointflow::test
