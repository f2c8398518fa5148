#include "one_euro_filter.hpp"

#include <cmath>

namespace jointflow {
namespace {

// Smoothing factor of an exponential filter with cut-off frequency `cutoff` at sample period dt.
float alpha(float cutoff, float dt) {
  const float tau = 1.f / (2.f * static_cast<float>(M_PI) * cutoff);
  return 1.f / (1.f + tau / dt);
}

}  // namespace

float OneEuroFilter::filter(float x, float dt) {
  if (!started_ || !(dt > 0.f)) {
    started_ = true;
    x_ = x;
    dx_ = 0.f;
    return x;
  }
  const float dx = (x - x_) / dt;
  dx_ += alpha(d_cutoff_, dt) * (dx - dx_);
  const float cutoff = min_cutoff_ + beta_ * std::abs(dx_);
  x_ += alpha(cutoff, dt) * (x - x_);
  return x_;
}

}  // namespace jointflow
