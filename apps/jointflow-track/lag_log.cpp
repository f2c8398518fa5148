// --output-lag (lag_log.hpp).
#include "lag_log.hpp"

#include <cerrno>
#include <cstring>

#include "frame_lag.hpp"
#include "jointflow/error.hpp"

namespace jointflow::cli {

LagLog::LagLog(const std::string& path) : file_(std::fopen(path.c_str(), "w")) {
  if (!file_) throw Error("--output-lag " + path + ": " + std::strerror(errno));
  std::fputs("unix_time,lag_seconds,inferred,capture_lag_seconds\n", file_);
}

LagLog::~LagLog() {
  std::fclose(file_);
}

void LagLog::record(GstPad* pad, GstBuffer* buffer, bool inferred) {
  GstEvent* event = gst_pad_get_sticky_event(pad, GST_EVENT_SEGMENT, 0);
  if (!event) return;
  GstSegment segment;
  gst_event_copy_segment(event, &segment);
  gst_event_unref(event);
  const auto lag = gst::frameLagSeconds(GST_PAD_PARENT(pad), segment, buffer);
  if (!lag) return;
  std::fprintf(file_, "%.6f,%.6f,%d,", static_cast<double>(g_get_real_time()) / G_USEC_PER_SEC,
               *lag, inferred ? 1 : 0);
  // Empty where the frame does not carry the camera's capture time (frame_lag.hpp).
  if (const auto capture = gst::captureLagSeconds(buffer)) std::fprintf(file_, "%.6f", *capture);
  std::fputc('\n', file_);
  std::fflush(file_);  // a run that is killed keeps its lines
}

}  // namespace jointflow::cli
