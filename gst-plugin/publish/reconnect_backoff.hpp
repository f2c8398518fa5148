// When jointflowmetapublish tries to connect again: exponential backoff with jitter. The k-th
// wait (k = 1 after the first failure) is drawn in [d/2, d] with d = min(max, first * 2^(k-1)),
// so that many cameras that lost one broker together do not all come back in the same instant
// ("equal jitter"), while a single one still waits at least half the nominal delay.
#pragma once

#include <chrono>
#include <cstdint>

namespace jointflow::gst {

class ReconnectBackoff {
 public:
  using Duration = std::chrono::milliseconds;

  /// @first > 0 is the nominal first wait; @max >= @first caps the growth (a smaller @max is
  /// taken as @first).
  ReconnectBackoff(Duration first, Duration max);

  /// The nominal (jitter-free) wait after @failures consecutive failures (>= 1).
  Duration nominal(std::uint32_t failures) const;
  /// The wait to take: nominal(@failures) scaled into [1/2, 1] by @uniform01 in [0, 1].
  Duration delay(std::uint32_t failures, double uniform01) const;

  Duration first() const { return first_; }
  Duration max() const { return max_; }

 private:
  Duration first_;
  Duration max_;
};

}  // namespace jointflow::gst
