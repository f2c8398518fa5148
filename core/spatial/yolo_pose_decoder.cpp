#include "jointflow/yolo_pose_decoder.hpp"

#include <algorithm>
#include <numeric>
#include <sstream>

#include "jointflow/error.hpp"

namespace jointflow {
namespace {

/// Value v of anchor a, whichever way round the output lies.
struct AnchorReader {
  const float* data;
  int anchors;
  bool values_first;  // {1, 56, N}: value v of anchor a at v * N + a
  float operator()(int a, int v) const {
    return values_first ? data[static_cast<size_t>(v) * anchors + a]
                        : data[static_cast<size_t>(a) * kYoloPoseValues + v];
  }
};

AnchorReader readerOf(const cv::Mat& out) {
  const bool shaped = !out.empty() && out.type() == CV_32F && out.isContinuous() && out.dims == 3 &&
                      out.size[0] == 1 &&
                      (out.size[1] == kYoloPoseValues || out.size[2] == kYoloPoseValues);
  if (!shaped) {
    std::ostringstream msg;
    msg << "YOLO pose output: expected a continuous CV_32F tensor {1, " << kYoloPoseValues
        << ", N} or {1, N, " << kYoloPoseValues << "}, got dims=" << out.dims << " (";
    for (int i = 0; i < out.dims; ++i) msg << (i ? "x" : "") << out.size[i];
    msg << ") type=" << out.type();
    throw Error(msg.str());
  }
  // N is never 56 (21 H W / 1024 with H, W multiples of 32), so the layout is unambiguous.
  const bool values_first = out.size[1] == kYoloPoseValues;
  return {out.ptr<float>(), values_first ? out.size[2] : out.size[1], values_first};
}

}  // namespace

Poses yoloPoseCandidates(const cv::Mat& output, float score_threshold) {
  const AnchorReader at = readerOf(output);
  Poses poses;
  for (int a = 0; a < at.anchors; ++a) {
    const float score = at(a, 4);
    if (!(score >= score_threshold)) continue;
    Pose p;
    p.score = score;
    const float w = at(a, 2), h = at(a, 3);
    p.box = {at(a, 0) - 0.5f * w - 0.5f, at(a, 1) - 0.5f * h - 0.5f, w, h};
    for (int j = 0; j < kNumJoints; ++j)
      p.keypoints[j] = {at(a, 5 + 3 * j) - 0.5f, at(a, 6 + 3 * j) - 0.5f, at(a, 7 + 3 * j)};
    poses.push_back(p);
  }
  return poses;
}

Poses suppressOverlappingPoses(const Poses& candidates, float nms_iou, int max_persons) {
  std::vector<size_t> order(candidates.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return candidates[a].score > candidates[b].score; });
  Poses kept;
  for (size_t i : order) {
    if (static_cast<int>(kept.size()) >= max_persons) break;
    const Pose& p = candidates[i];
    const bool covered = std::any_of(kept.begin(), kept.end(),
                                     [&](const Pose& k) { return iou(k.box, p.box) > nms_iou; });
    if (!covered) kept.push_back(p);
  }
  return kept;
}

Poses decodeYoloPose(const cv::Mat& output, const YoloPoseDecodeOptions& options) {
  return suppressOverlappingPoses(yoloPoseCandidates(output, options.score_threshold),
                                  options.nms_iou, options.max_persons);
}

}  // namespace jointflow
