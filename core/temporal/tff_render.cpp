// Ground-truth Temporal Flow Fields, paper Eq. 2-4 (see temporal_flow.hpp for the contract).
#include <algorithm>
#include <cmath>
#include <string>

#include "jointflow/error.hpp"
#include "jointflow/temporal_flow.hpp"

namespace jointflow {

cv::Mat renderTemporalFlowField(const std::vector<JointMotion>& motions, int num_joints,
                                cv::Size grid, float sigma) {
  if (num_joints < 1)
    throw Error("renderTemporalFlowField: num_joints must be >= 1, got " +
                std::to_string(num_joints));
  if (grid.width < 1 || grid.height < 1)
    throw Error("renderTemporalFlowField: the grid must be at least 1x1 cells, got " +
                std::to_string(grid.width) + "x" + std::to_string(grid.height));
  if (!(sigma >= 0.f) || !std::isfinite(sigma))
    throw Error("renderTemporalFlowField: sigma must be a finite width >= 0 cells, got " +
                std::to_string(sigma));

  const int sizes[] = {1, 2 * num_joints, grid.height, grid.width};
  cv::Mat field(4, sizes, CV_32F, cv::Scalar(0));
  // n(p) of Eq. 4, one plane per joint.
  cv::Mat count(num_joints, grid.height * grid.width, CV_32S, cv::Scalar(0));
  const size_t plane = static_cast<size_t>(grid.height) * grid.width;
  auto* data = field.ptr<float>();

  for (const JointMotion& m : motions) {
    if (m.joint < 0 || m.joint >= num_joints)
      throw Error("renderTemporalFlowField: joint index " + std::to_string(m.joint) +
                  " is outside 0.." + std::to_string(num_joints - 1));
    const cv::Point2f d = m.to - m.from;
    const float lambda = std::hypot(d.x, d.y);
    if (!(lambda > 0.f) || !std::isfinite(lambda)) continue;  // no motion: no field
    const cv::Point2f v = d / lambda;
    const cv::Point2f v_perp(-v.y, v.x);
    // Omega lies inside the segment's bounding box grown by sigma.
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min(m.from.x, m.to.x) - sigma)));
    const int x1 =
        std::min(grid.width - 1, static_cast<int>(std::ceil(std::max(m.from.x, m.to.x) + sigma)));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min(m.from.y, m.to.y) - sigma)));
    const int y1 =
        std::min(grid.height - 1, static_cast<int>(std::ceil(std::max(m.from.y, m.to.y) + sigma)));
    float* fx = data + plane * (2 * m.joint);
    float* fy = data + plane * (2 * m.joint + 1);
    int* n = count.ptr<int>(m.joint);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const cv::Point2f r(x - m.from.x, y - m.from.y);
        const float along = v.dot(r);
        const float across = std::abs(v_perp.dot(r));
        if (along < 0.f || along > lambda || across > sigma) continue;  // Eq. 2
        const size_t i = static_cast<size_t>(y) * grid.width + x;
        fx[i] += v.x;  // Eq. 3, summed over persons
        fy[i] += v.y;
        ++n[i];
      }
    }
  }

  for (int j = 0; j < num_joints; ++j) {  // Eq. 4: average over the n(p) non-zero vectors
    float* fx = data + plane * (2 * j);
    float* fy = data + plane * (2 * j + 1);
    const int* n = count.ptr<int>(j);
    for (size_t i = 0; i < plane; ++i) {
      if (n[i] > 1) {
        fx[i] /= static_cast<float>(n[i]);
        fy[i] /= static_cast<float>(n[i]);
      }
    }
  }
  return field;
}

std::vector<JointMotion> jointMotions(const Pose& previous, const Pose& current,
                                      const GridTransform& grid_to_frame, float min_score) {
  std::vector<JointMotion> motions;
  for (int j = 0; j < kNumJoints; ++j) {
    const Keypoint& a = previous.keypoints[j];
    const Keypoint& b = current.keypoints[j];
    if (a.score <= 0.f || b.score <= 0.f || a.score < min_score || b.score < min_score) continue;
    motions.push_back({j, grid_to_frame.toGrid({a.x, a.y}), grid_to_frame.toGrid({b.x, b.y})});
  }
  return motions;
}

}  // namespace jointflow
