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
  // Static caps: GStreamer marks them as living for the process, so the leaks tracer (which the
  // rtsp-outage test runs) does not report them, as it would caps made once and kept.
  static GstStaticCaps ntp_caps = GST_STATIC_CAPS("timestamp/x-ntp");
  static GstStaticCaps unix_caps = GST_STATIC_CAPS("timestamp/x-unix");
  auto timeOn = [buffer](GstStaticCaps* reference) -> std::optional<double> {
    GstCaps* caps = gst_static_caps_get(reference);
    const GstReferenceTimestampMeta* m = gst_buffer_get_reference_timestamp_meta(buffer, caps);
    gst_caps_unref(caps);
    if (!m) return std::nullopt;
    return static_cast<double>(m->timestamp) / GST_SECOND;
  };
  double captured = 0;
  if (const auto ntp = timeOn(&ntp_caps))
    captured = *ntp - kNtpToUnixSeconds;
  else if (const auto unix_time = timeOn(&unix_caps))
    captured = *unix_time;
  else
    return std::nullopt;
  const double lag = static_cast<double>(g_get_real_time()) / G_USEC_PER_SEC - captured;
  return lag > 0 ? lag : 0.0;
}

}  // namespace jointflow::gst
