// A live frame's lag (frame_lag.hpp).
#include "frame_lag.hpp"

namespace jointflow::gst {

std::optional<double> frameLagSeconds(GstElement* element, const GstSegment& segment,
                                      GstBuffer* buffer) {
  if (segment.format != GST_FORMAT_TIME) return std::nullopt;
  const GstClockTime running =
      gst_segment_to_running_time(&segment, GST_FORMAT_TIME, GST_BUFFER_PTS(buffer));
  if (!GST_CLOCK_TIME_IS_VALID(running)) return std::nullopt;
  GstClock* clock = gst_element_get_clock(element);
  if (!clock) return std::nullopt;
  const GstClockTime now = gst_clock_get_time(clock);
  gst_object_unref(clock);
  const GstClockTime base = gst_element_get_base_time(element);
  if (now < base) return std::nullopt;
  const GstClockTimeDiff lag = GST_CLOCK_DIFF(running, now - base);
  return lag > 0 ? static_cast<double>(lag) / GST_SECOND : 0.0;
}

}  // namespace jointflow::gst
