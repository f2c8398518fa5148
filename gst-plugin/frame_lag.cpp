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

std::optional<double> captureLagSeconds(GstBuffer* buffer) {
  // NTP counts from 1900, Unix time from 1970: 70 years, 17 of them leap years.
  constexpr double kNtpToUnixSeconds = 2208988800.0;
  static GstCaps* const ntp = gst_caps_new_empty_simple("timestamp/x-ntp");
  static GstCaps* const unix_time = gst_caps_new_empty_simple("timestamp/x-unix");
  double captured = 0;
  if (auto* m = gst_buffer_get_reference_timestamp_meta(buffer, ntp))
    captured = static_cast<double>(m->timestamp) / GST_SECOND - kNtpToUnixSeconds;
  else if (auto* u = gst_buffer_get_reference_timestamp_meta(buffer, unix_time))
    captured = static_cast<double>(u->timestamp) / GST_SECOND;
  else
    return std::nullopt;
  const double lag = static_cast<double>(g_get_real_time()) / G_USEC_PER_SEC - captured;
  return lag > 0 ? lag : 0.0;
}

}  // namespace jointflow::gst
