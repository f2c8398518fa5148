// Test helper: renders joint belief maps and Part Affinity Fields of known poses onto a grid,
// the way Cao et al. 2017 define their training targets, so that decoding them must give the
// poses back.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/types.hpp"

namespace jointflow::test {

/// Beliefs {1, 17, H, W}: max over persons of exp(-d^2 / (2 sigma^2)) around each present joint
/// (score > 0), positions in cells.
inline cv::Mat renderBeliefs(const Poses& poses, cv::Size grid, float sigma) {
  cv::Mat t(std::vector<int>{1, kNumJoints, grid.height, grid.width}, CV_32F, cv::Scalar(0));
  for (const auto& p : poses) {
    for (int j = 0; j < kNumJoints; ++j) {
      const auto& k = p.keypoints[j];
      if (k.score <= 0.f) continue;
      float* m = t.ptr<float>(0, j);
      for (int r = 0; r < grid.height; ++r) {
        for (int c = 0; c < grid.width; ++c) {
          const float d2 = (c - k.x) * (c - k.x) + (r - k.y) * (r - k.y);
          m[r * grid.width + c] =
              std::max(m[r * grid.width + c], std::exp(-d2 / (2 * sigma * sigma)));
        }
      }
    }
  }
  return t;
}

/// PAFs {1, 2L, H, W}: the unit vector of limb l on cells within `width` of its segment.
inline cv::Mat renderPafs(const Poses& poses, const std::vector<std::pair<int, int>>& limbs,
                          cv::Size grid, float width) {
  const int n = static_cast<int>(limbs.size());
  cv::Mat t(std::vector<int>{1, 2 * n, grid.height, grid.width}, CV_32F, cv::Scalar(0));
  for (const auto& p : poses) {
    for (int l = 0; l < n; ++l) {
      const auto& a = p.keypoints[limbs[l].first];
      const auto& b = p.keypoints[limbs[l].second];
      if (a.score <= 0.f || b.score <= 0.f) continue;
      const float dx = b.x - a.x, dy = b.y - a.y, len = std::sqrt(dx * dx + dy * dy);
      const float ux = dx / len, uy = dy / len;
      float* mx = t.ptr<float>(0, 2 * l);
      float* my = t.ptr<float>(0, 2 * l + 1);
      for (int r = 0; r < grid.height; ++r) {
        for (int c = 0; c < grid.width; ++c) {
          const float along = (c - a.x) * ux + (r - a.y) * uy;
          const float across = std::abs((c - a.x) * uy - (r - a.y) * ux);
          if (along < -width || along > len + width || across > width) continue;
          mx[r * grid.width + c] = ux;
          my[r * grid.width + c] = uy;
        }
      }
    }
  }
  return t;
}

}  // namespace jointflow::test
