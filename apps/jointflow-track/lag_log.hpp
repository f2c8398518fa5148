// --output-lag: each frame's lag as it leaves the tracker, one CSV line per frame, for the latency
// benchmark (bench/live_bench.sh latency) and for looking at a camera's delay frame by frame. The
// lag is the tracker's own measure (gst-plugin/frame_lag.hpp), which its statistics put in
// histograms.
#pragma once

#include <gst/gst.h>

#include <cstdio>
#include <string>

namespace jointflow::cli {

class LagLog {
 public:
  /// Creates @path with its header; throws jointflow::Error when it cannot.
  explicit LagLog(const std::string& path);
  ~LagLog();
  LagLog(const LagLog&) = delete;
  LagLog& operator=(const LagLog&) = delete;

  /// A buffer on the tracker's source pad (streaming thread):
  /// "unix_time,lag_seconds,inferred,capture_lag_seconds".
  void record(GstPad* pad, GstBuffer* buffer, bool inferred);

 private:
  std::FILE* file_;
};

}  // namespace jointflow::cli
