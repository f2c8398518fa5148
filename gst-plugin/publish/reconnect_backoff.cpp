#include "reconnect_backoff.hpp"

#include <algorithm>

namespace jointflow::gst {

ReconnectBackoff::ReconnectBackoff(Duration first, Duration max)
    : first_(std::max(first, Duration(1))), max_(std::max(max, first_)) {}

ReconnectBackoff::Duration ReconnectBackoff::nominal(std::uint32_t failures) const {
  Duration d = first_;
  // Doubling until the cap; the loop ends after at most ~63 steps (the cap stops it first).
  for (std::uint32_t k = 1; k < failures && d < max_; ++k) d = std::min(max_, d * 2);
  return d;
}

ReconnectBackoff::Duration ReconnectBackoff::delay(std::uint32_t failures, double uniform01) const {
  const Duration d = nominal(failures);
  const double u = std::clamp(uniform01, 0.0, 1.0);
  return Duration(static_cast<Duration::rep>(static_cast<double>(d.count()) * (0.5 + 0.5 * u)));
}

}  // namespace jointflow::gst
