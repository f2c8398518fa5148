// The one time policy (frame_clock.hpp): a frame's own time when it moves forward, else one frame
// duration after the previous frame; the first frame without a time at 0.
#include <limits>

#include <catch2/catch.hpp>

#include "jointflow/frame_clock.hpp"

using jointflow::FrameClock;

TEST_CASE("FrameClock: own times, gaps kept, missing and stale times one frame on",
          "[tracking][time]") {
  const double none = std::numeric_limits<double>::quiet_NaN();
  FrameClock clock(0.1);
  CHECK(clock.next(5.0) == 5.0);   // a stream may start at any time
  CHECK(clock.next(5.04) == 5.04);
  CHECK(clock.next(9.0) == 9.0);   // a gap (an outage, dropped frames) is kept: tracks age
  CHECK(clock.next(none) == Approx(9.1));
  CHECK(clock.next(9.1) == Approx(9.2));  // not after the previous frame: one frame on
  CHECK(clock.next(3.0) == Approx(9.3));  // running back: one frame on
  CHECK(clock.fallbacks() == 3);
  clock.setFrameDuration(0.5);  // the caps' frame rate
  CHECK(clock.next(none) == Approx(9.8));
  clock.setFrameDuration(0);  // nonsense is ignored
  clock.setFrameDuration(none);
  CHECK(clock.frameDuration() == 0.5);
  clock.reset();  // a new stream
  CHECK(clock.next(none) == 0.0);
  CHECK(clock.next(2.0) == 2.0);
  CHECK(clock.fallbacks() == 5);  // counted over the clock's life
}
