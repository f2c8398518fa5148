// The stream time of each frame, the one time policy of the product: the core's association and
// the GStreamer element both take a frame's time from here.
//
// A frame's time is its own (the running time of its PTS, in seconds) when that is finite and
// after the previous frame's; otherwise (no PTS, a PTS that stands still or runs back) it is the
// previous frame's time plus one frame duration, so that time never stands still or runs back and
// every time-based setting (lost-time, smoothing) keeps running. The first frame without a time is
// at 0. The frame duration comes from the stream (the caps' frame rate) or the settings'
// frame_rate.
#pragma once

namespace jointflow {

class FrameClock {
 public:
  /// `frame_duration` in seconds, > 0.
  explicit FrameClock(double frame_duration = 1.0 / 30);

  /// The time of the next frame, given its own time `t` (NaN when it has none); advances.
  double next(double t);
  /// A new stream: the next frame is a first frame. The count of fallbacks is kept.
  void reset();
  /// From the stream's frame rate; ignored unless > 0 and finite.
  void setFrameDuration(double seconds);

  double time() const { return time_; }          ///< of the last frame (0 before any)
  double frameDuration() const { return frame_duration_; }
  /// Frames whose own time was missing or not after the previous one's, over the clock's life.
  int fallbacks() const { return fallbacks_; }

 private:
  double frame_duration_;
  double time_ = 0.0;
  bool first_ = true;
  int fallbacks_ = 0;
};

}  // namespace jointflow
