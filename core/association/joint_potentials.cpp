// The TFF joint potentials (paper Eq. 5-6) and the optical-flow energy (Eq. 9). Eq. 7, the sum
// over joints, is personPotential in similarity.hpp; bilinear sampling is sampleBilinear there.
#include <cmath>

#include "jointflow/similarity.hpp"

namespace jointflow {

// Eq. 5. The integral is the mean of the samples at o = k / (samples - 1).
float flowFieldAggregate(const cv::Mat& tff, int joint, cv::Point2f from_grid, cv::Point2f to_grid,
                         int samples) {
  const cv::Point2f d = to_grid - from_grid;
  const float length = std::sqrt(d.x * d.x + d.y * d.y);
  if (!(length > 0.f)) return 0.f;
  const cv::Point2f u = d / length;
  const int n = samples < 2 ? 2 : samples;
  const float step = 1.f / static_cast<float>(n - 1);
  float sum = 0.f;
  for (int k = 0; k < n; ++k) {
    const cv::Point2f p = from_grid + (k * step) * d;
    sum += sampleBilinear(tff, 2 * joint, p) * u.x + sampleBilinear(tff, 2 * joint + 1, p) * u.y;
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

// Eq. 9.
float flowEnergy(cv::Point2f from, cv::Point2f to, cv::Point2f flow, float sigma_flow) {
  const cv::Point2f r = to - (from + flow);
  return std::exp(-(r.x * r.x + r.y * r.y) / (sigma_flow * sigma_flow));
}

}  // namespace jointflow
