#include "jointflow/frame_clock.hpp"

#include <cmath>

namespace jointflow {

FrameClock::FrameClock(double frame_duration) : frame_duration_(1.0 / 30) {
  setFrameDuration(frame_duration);
}

double FrameClock::next(double t) {
  const bool usable = std::isfinite(t) && (first_ || t > time_);
  if (!usable) ++fallbacks_;
  time_ = usable ? t : first_ ? 0.0 : time_ + frame_duration_;
  first_ = false;
  return time_;
}

void FrameClock::reset() {
  time_ = 0.0;
  first_ = true;
}

void FrameClock::setFrameDuration(double seconds) {
  if (std::isfinite(seconds) && seconds > 0) frame_duration_ = seconds;
}

}  // namespace jointflow
