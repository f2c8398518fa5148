// Source frame indices of the buffers at the tracker (frame_index.hpp).
#include "frame_index.hpp"

#include <cmath>

namespace jointflow::cli {

std::int64_t FrameIndexer::index(GstPad* pad, GstBuffer* buffer) {
  const std::int64_t counted = count_++;
  gint num = 0, den = 1;
  if (GstCaps* caps = gst_pad_get_current_caps(pad)) {
    gst_structure_get_fraction(gst_caps_get_structure(caps, 0), "framerate", &num, &den);
    gst_caps_unref(caps);
  }
  GstClockTime stream_time = GST_CLOCK_TIME_NONE;
  if (GstEvent* event = gst_pad_get_sticky_event(pad, GST_EVENT_SEGMENT, 0)) {
    const GstSegment* segment = nullptr;
    gst_event_parse_segment(event, &segment);
    if (segment && segment->format == GST_FORMAT_TIME && GST_BUFFER_PTS_IS_VALID(buffer))
      stream_time = gst_segment_to_stream_time(segment, GST_FORMAT_TIME, GST_BUFFER_PTS(buffer));
    gst_event_unref(event);
  }
  if (num <= 0 || den <= 0 || !GST_CLOCK_TIME_IS_VALID(stream_time)) {
    if (!warned_)
      g_printerr(
          "jointflow-track: the video has no timestamps or no frame rate; PoseTrack frames are "
          "numbered in output order\n");
    warned_ = true;
    return counted;
  }
  // Rounded: container timestamps are often a few microseconds off the frame grid.
  return static_cast<std::int64_t>(std::llround(static_cast<double>(stream_time) * num /
                                                (static_cast<double>(den) * GST_SECOND)));
}

GstPadProbeReturn stampFolderFrames(GstPad*, GstPadProbeInfo* info, gpointer data) {
  auto* clock = static_cast<FolderClock*>(data);
  GstBuffer* buffer = GST_PAD_PROBE_INFO_BUFFER(info);
  if (!buffer) return GST_PAD_PROBE_OK;
  buffer = gst_buffer_make_writable(buffer);
  GST_BUFFER_PTS(buffer) = clock->stamped * clock->frame_duration;
  GST_BUFFER_DURATION(buffer) = clock->frame_duration;
  ++clock->stamped;
  GST_PAD_PROBE_INFO_DATA(info) = buffer;
  return GST_PAD_PROBE_OK;
}

}  // namespace jointflow::cli
