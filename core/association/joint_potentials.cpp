// The TFF joint and person potentials (paper Eq. 5-7) and the optical-flow energy (Eq. 9).
#include <algorithm>
#include <cmath>

#include "jointflow/similarity.hpp"

namespace jointflow {
namespace {

// A grid point clamped to the grid: the index of its top-left neighbour, the steps to the right
// and lower neighbours (0 on the last column / row) and the fractional position.
struct BilinearTap {
  size_t index;
  int right, down;
  float fx, fy;
};

inline BilinearTap bilinearTap(float x, float y, int w, int h) {
  x = x < 0.f ? 0.f : (x > w - 1 ? static_cast<float>(w - 1) : x);
  y = y < 0.f ? 0.f : (y > h - 1 ? static_cast<float>(h - 1) : y);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  return {static_cast<size_t>(y0) * w + x0, x0 < w - 1 ? 1 : 0, y0 < h - 1 ? w : 0, x - x0, y - y0};
}

inline float apply(const BilinearTap& t, const float* plane) {
  const float* p = plane + t.index;
  const float top = p[0] + t.fx * (p[t.right] - p[0]);
  const float bottom = p[t.down] + t.fx * (p[t.down + t.right] - p[t.down]);
  return top + t.fy * (bottom - top);
}

}  // namespace

float sampleBilinear(const cv::Mat& map, int channel, cv::Point2f p) {
  const int h = map.size[2], w = map.size[3];
  const float* plane = map.ptr<float>() + static_cast<size_t>(channel) * h * w;
  return apply(bilinearTap(p.x, p.y, w, h), plane);
}

// Eq. 5. The integral is the mean of the samples at o = k / (samples - 1).
float flowFieldAggregate(const cv::Mat& tff, int joint, cv::Point2f from_grid, cv::Point2f to_grid,
                         int samples) {
  const cv::Point2f d = to_grid - from_grid;
  const float length = std::sqrt(d.x * d.x + d.y * d.y);
  if (!(length > 0.f)) return 0.f;
  const float ux = d.x / length, uy = d.y / length;
  const int h = tff.size[2], w = tff.size[3];
  const size_t plane = static_cast<size_t>(h) * w;
  const float* tx = tff.ptr<float>() + plane * (2 * joint);
  const float* ty = tx + plane;
  const int n = std::max(samples, 2);
  const float step = 1.f / static_cast<float>(n - 1);
  float sum = 0.f;
  auto inside = [&](cv::Point2f p) {
    return p.x >= 0.f && p.y >= 0.f && p.x < w - 1 && p.y < h - 1;
  };
  if (inside(from_grid) && inside(to_grid)) {
    // The common case, a segment inside the grid: every sample has all four neighbours, so the
    // loop needs no clamping (the same arithmetic as bilinearTap + apply).
    for (int k = 0; k < n; ++k) {
      const float o = k * step;
      const float x = from_grid.x + o * d.x, y = from_grid.y + o * d.y;
      const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
      const float fx = x - x0, fy = y - y0;
      const size_t i = static_cast<size_t>(y0) * w + x0;
      const float* px = tx + i;
      const float* py = ty + i;
      const float top = (px[0] + fx * (px[1] - px[0])) * ux + (py[0] + fx * (py[1] - py[0])) * uy;
      const float bottom =
          (px[w] + fx * (px[w + 1] - px[w])) * ux + (py[w] + fx * (py[w + 1] - py[w])) * uy;
      sum += top + fy * (bottom - top);
    }
  } else {
    for (int k = 0; k < n; ++k) {
      const float o = k * step;
      const BilinearTap t = bilinearTap(from_grid.x + o * d.x, from_grid.y + o * d.y, w, h);
      sum += apply(t, tx) * ux + apply(t, ty) * uy;
    }
  }
  return sum / static_cast<float>(n);
}

// Eq. 6: tau_delta is compared with the distance in frame pixels, as the paper states it.
float jointPotential(const cv::Mat& tff, const GridTransform& grid_to_frame, int joint,
                     cv::Point2f from_frame, cv::Point2f to_frame, float tau_delta, int samples) {
  const cv::Point2f d = to_frame - from_frame;
  if (d.x * d.x + d.y * d.y < tau_delta * tau_delta) return 1.f;
  return flowFieldAggregate(tff, joint, grid_to_frame.toGrid(from_frame),
                            grid_to_frame.toGrid(to_frame), samples);
}

// Eq. 7.
float tffPersonPotential(const cv::Mat& tff, const GridTransform& grid_to_frame,
                         const Pose& previous, const Pose& current,
                         const JointThresholds& thresholds, float tau_delta, int samples,
                         int* common) {
  float psi = 0.f;
  int n = 0;
  for (int j = 0; j < kNumJoints; ++j) {
    const Keypoint& a = previous.keypoints[j];
    const Keypoint& b = current.keypoints[j];
    if (!isDetected(a, thresholds[j]) || !isDetected(b, thresholds[j])) continue;  // 1(.,.)
    psi += jointPotential(tff, grid_to_frame, j, {a.x, a.y}, {b.x, b.y}, tau_delta, samples);
    ++n;
  }
  if (common) *common = n;
  return psi;
}

// Eq. 9.
float flowEnergy(cv::Point2f from, cv::Point2f to, cv::Point2f flow, float sigma_flow) {
  const cv::Point2f r = to - (from + flow);
  return std::exp(-(r.x * r.x + r.y * r.y) / (sigma_flow * sigma_flow));
}

}  // namespace jointflow
