// YOLO pose decoding (Ultralytics YOLOv8/YOLO11 "-pose" networks exported to ONNX), on the
// network's one output tensor.
//
// The exported graph does the anchor, stride and distribution-focal-loss decoding itself: its
// output (`output0`) holds one column per anchor of the three levels (strides 8, 16, 32, so N =
// 21 H W / 1024 for an H x W input), 56 values each:
//   0-3    cx, cy, w, h of the person box, input pixels;
//   4      person score (sigmoid applied);
//   5-55   per COCO joint j: x, y (input pixels) at 5 + 3j, 6 + 3j and its visibility score
//          (sigmoid applied) at 7 + 3j, joints in COCO order as jointflow::Joint.
// Ultralytics' coordinates put pixel i's left edge at i; JointFlow's put its centre at i (the
// letterbox's convention, letterbox.hpp), so the decoder subtracts 0.5 from every position.
// What is left to do, here: keep the anchors scoring at least the threshold, then greedy
// non-maximum suppression of their boxes, highest score first (Ultralytics' own order and
// default IoU, 0.7, so that people side by side in a crowd survive).
#pragma once

#include <opencv2/core.hpp>

#include "jointflow/types.hpp"

namespace jointflow {

/// Values per anchor of a YOLO pose output: box (4), score (1), 17 joints x (x, y, score).
constexpr int kYoloPoseValues = 5 + 3 * kNumJoints;

struct YoloPoseDecodeOptions {
  float score_threshold = 0.25f;  ///< lowest person score kept (Ultralytics' default conf)
  float nms_iou = 0.7f;           ///< a box overlapping a better one by more than this is dropped
  int max_persons = 300;          ///< most poses returned (Ultralytics' max_det)
};

/// The anchors of `output` scoring at least `score_threshold`, as poses in input pixels
/// (JointFlow's convention), in anchor order, not yet suppressed. `output` is CV_32F,
/// continuous, {1, 56, N} (Ultralytics' layout) or {1, N, 56} (transposed). Throws
/// jointflow::Error for any other shape.
Poses yoloPoseCandidates(const cv::Mat& output, float score_threshold);

/// Greedy non-maximum suppression on the poses' boxes: highest score first (the earlier one on a
/// tie), each pose dropped when its box overlaps a kept one by IoU > nms_iou; at most
/// max_persons, highest score first.
Poses suppressOverlappingPoses(const Poses& candidates, float nms_iou, int max_persons);

/// yoloPoseCandidates + suppressOverlappingPoses: the poses of one output, in input pixels,
/// highest score first.
Poses decodeYoloPose(const cv::Mat& output, const YoloPoseDecodeOptions& options);

}  // namespace jointflow
