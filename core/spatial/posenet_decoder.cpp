#include "jointflow/posenet_decoder.hpp"

#include <algorithm>
#include <cmath>
#include <queue>

#include "tensor.hpp"

namespace jointflow {

// tfjs posenet's poseChain, (parent, child); the order defines the displacement channels.
const std::array<std::pair<int, int>, 16> kPoseNetEdges = {{
    {kNose, kLeftEye},
    {kLeftEye, kLeftEar},
    {kNose, kRightEye},
    {kRightEye, kRightEar},
    {kNose, kLeftShoulder},
    {kLeftShoulder, kLeftElbow},
    {kLeftElbow, kLeftWrist},
    {kLeftShoulder, kLeftHip},
    {kLeftHip, kLeftKnee},
    {kLeftKnee, kLeftAnkle},
    {kNose, kRightShoulder},
    {kRightShoulder, kRightElbow},
    {kRightElbow, kRightWrist},
    {kRightShoulder, kRightHip},
    {kRightHip, kRightKnee},
    {kRightKnee, kRightAnkle},
}};

namespace {

struct Candidate {
  float score;
  int row, col, joint;
  bool operator<(const Candidate& o) const { return score < o.score; }
};

class Decoder {
 public:
  Decoder(const PoseNetHeads& heads, const PoseNetDecodeOptions& options)
      : h_(heads),
        o_(options),
        rows_(detail::rows(heads.scores)),
        cols_(detail::cols(heads.scores)) {}

  Poses run() {
    std::priority_queue<Candidate> queue = partCandidates();
    Poses poses;
    const float r2 = o_.nms_radius * o_.nms_radius;
    while (static_cast<int>(poses.size()) < o_.max_persons && !queue.empty()) {
      const Candidate root = queue.top();
      queue.pop();
      const cv::Point2f root_px = imagePoint(root.row, root.col, root.joint);
      if (withinNmsRadius(poses, r2, root_px, root.joint)) continue;
      Pose pose = decodePose(root, root_px);
      // Instance score: joints not claimed by an earlier pose, averaged over all 17.
      float sum = 0.f;
      for (int j = 0; j < kNumJoints; ++j) {
        const auto& k = pose.keypoints[j];
        if (!withinNmsRadius(poses, r2, {k.x, k.y}, j)) sum += k.score;
      }
      pose.score = sum / kNumJoints;
      poses.push_back(pose);
    }
    // Positions were in input pixels during decoding (the NMS radius is in pixels): to cells.
    for (auto& pose : poses) {
      for (auto& k : pose.keypoints) k.x /= o_.stride, k.y /= o_.stride;
      pose.box = pose.keypointBox(0.f);
    }
    return poses;
  }

 private:
  float at(const cv::Mat& t, int ch, int r, int c) const {
    return t.ptr<float>(0, ch)[r * cols_ + c];
  }

  std::priority_queue<Candidate> partCandidates() const {
    std::priority_queue<Candidate> queue;
    const int rad = o_.local_maximum_radius;
    for (int j = 0; j < kNumJoints; ++j) {
      for (int r = 0; r < rows_; ++r) {
        for (int c = 0; c < cols_; ++c) {
          const float s = at(h_.scores, j, r, c);
          if (s < o_.part_threshold) continue;
          bool is_max = true;
          for (int rr = std::max(r - rad, 0); rr <= std::min(r + rad, rows_ - 1) && is_max; ++rr) {
            for (int cc = std::max(c - rad, 0); cc <= std::min(c + rad, cols_ - 1); ++cc) {
              if (at(h_.scores, j, rr, cc) > s) {
                is_max = false;
                break;
              }
            }
          }
          if (is_max) queue.push({s, r, c, j});
        }
      }
    }
    return queue;
  }

  cv::Point2f imagePoint(int r, int c, int joint) const {
    return {c * o_.stride + at(h_.offsets, joint + kNumJoints, r, c),
            r * o_.stride + at(h_.offsets, joint, r, c)};
  }

  cv::Point nearestCell(cv::Point2f p) const {
    return {std::clamp(static_cast<int>(std::round(p.x / o_.stride)), 0, cols_ - 1),
            std::clamp(static_cast<int>(std::round(p.y / o_.stride)), 0, rows_ - 1)};
  }

  static bool withinNmsRadius(const Poses& poses, float r2, cv::Point2f p, int joint) {
    for (const auto& pose : poses) {
      const auto& k = pose.keypoints[joint];
      const float dx = k.x - p.x, dy = k.y - p.y;
      if (dx * dx + dy * dy <= r2) return true;
    }
    return false;
  }

  Keypoint traverse(int edge, const Keypoint& source, int target,
                    const cv::Mat& displacements) const {
    const int num_edges = static_cast<int>(kPoseNetEdges.size());
    const cv::Point s = nearestCell({source.x, source.y});
    cv::Point2f p(source.x + at(displacements, num_edges + edge, s.y, s.x),
                  source.y + at(displacements, edge, s.y, s.x));
    for (int i = 0; i < o_.refine_steps; ++i) {
      const cv::Point t = nearestCell(p);
      p = imagePoint(t.y, t.x, target);
    }
    const cv::Point t = nearestCell(p);
    return {p.x, p.y, at(h_.scores, target, t.y, t.x)};
  }

  Pose decodePose(const Candidate& root, cv::Point2f root_px) const {
    Pose pose;
    std::array<bool, kNumJoints> done{};
    pose.keypoints[root.joint] = {root_px.x, root_px.y, root.score};
    done[root.joint] = true;
    const int num_edges = static_cast<int>(kPoseNetEdges.size());
    for (int e = num_edges - 1; e >= 0; --e) {  // towards the root of the tree: child -> parent
      const auto [parent, child] = kPoseNetEdges[e];
      if (done[child] && !done[parent]) {
        pose.keypoints[parent] = traverse(e, pose.keypoints[child], parent, h_.displacement_bwd);
        done[parent] = true;
      }
    }
    for (int e = 0; e < num_edges; ++e) {  // away from it: parent -> child
      const auto [parent, child] = kPoseNetEdges[e];
      if (done[parent] && !done[child]) {
        pose.keypoints[child] = traverse(e, pose.keypoints[parent], child, h_.displacement_fwd);
        done[child] = true;
      }
    }
    return pose;
  }

  const PoseNetHeads& h_;
  const PoseNetDecodeOptions& o_;
  int rows_, cols_;
};

}  // namespace

Poses decodePoseNet(const PoseNetHeads& heads, const PoseNetDecodeOptions& options) {
  detail::checkTensor(heads.scores, "PoseNet scores", kNumJoints, 0, {});
  const cv::Size grid(detail::cols(heads.scores), detail::rows(heads.scores));
  detail::checkTensor(heads.offsets, "PoseNet offsets", 2 * kNumJoints, 0, grid);
  detail::checkTensor(heads.displacement_fwd, "PoseNet displacement_fwd", 32, 0, grid);
  detail::checkTensor(heads.displacement_bwd, "PoseNet displacement_bwd", 32, 0, grid);
  return Decoder(heads, options).run();
}

}  // namespace jointflow
