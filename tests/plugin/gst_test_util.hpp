// Helpers of the GStreamer tests: GStreamer set up once per process, synthetic frames with
// synthetic JointFlow meta, and a capture of the warnings GLib prints for refused values.
#pragma once

#include <gst/check/gstharness.h>
#include <gst/gst.h>
#include <gst/video/video.h>

#include <string>
#include <vector>

#include "jointflowmeta.h"

namespace jointflow::test {

/// gst_init once. The test environment (tests/plugin/meson.build) points GST_PLUGIN_PATH at the
/// build's plugin folder and GST_REGISTRY at a file in the build folder.
inline void initGst() {
  static const bool done = [] {
    gst_init(nullptr, nullptr);
    return true;
  }();
  (void)done;
}

inline std::string capsFor(const std::string& format, int width, int height) {
  return "video/x-raw,format=" + format + ",width=" + std::to_string(width) +
         ",height=" + std::to_string(height) + ",framerate=30/1";
}

/// A frame of @format filled with black (Y=16, U=V=128 for YUV; 0 for RGB), with PTS @pts.
inline GstBuffer* blackFrame(const std::string& format, int width, int height, GstClockTime pts) {
  GstVideoInfo info;
  gst_video_info_set_format(&info, gst_video_format_from_string(format.c_str()), width, height);
  GstBuffer* buffer = gst_buffer_new_allocate(nullptr, GST_VIDEO_INFO_SIZE(&info), nullptr);
  GstVideoFrame frame;
  gst_video_frame_map(&frame, &info, buffer, GST_MAP_WRITE);
  const bool yuv = GST_VIDEO_INFO_IS_YUV(&info);
  for (guint p = 0; p < GST_VIDEO_FRAME_N_PLANES(&frame); ++p) {
    const int value = yuv ? (p == 0 ? 16 : 128) : 0;
    const int rows = GST_VIDEO_FRAME_COMP_HEIGHT(&frame, p == 0 ? 0 : 1);
    memset(GST_VIDEO_FRAME_PLANE_DATA(&frame, p), value,
           static_cast<size_t>(GST_VIDEO_FRAME_PLANE_STRIDE(&frame, p)) * rows);
  }
  gst_video_frame_unmap(&frame);
  GST_BUFFER_PTS(buffer) = pts;
  GST_BUFFER_DURATION(buffer) = GST_SECOND / 30;
  return buffer;
}

/// A person whose keypoints are all at score 0 except those set afterwards.
inline JointFlowPerson person(gint64 id, float x, float y, float w, float h) {
  JointFlowPerson p{};
  p.track_id = id;
  p.tentative = FALSE;
  p.age = 10;
  p.score = 0.9f;
  p.x = x;
  p.y = y;
  p.width = w;
  p.height = h;
  return p;
}

/// The text of an ERROR message; "" for any other message.
inline std::string errorText(GstMessage* msg) {
  if (GST_MESSAGE_TYPE(msg) != GST_MESSAGE_ERROR) return "";
  GError* err = nullptr;
  gst_message_parse_error(msg, &err, nullptr);
  std::string text = err->message;
  g_error_free(err);
  return text;
}

/// The error message a pipeline posted, or "" when none.
inline std::string busError(GstElement* pipeline) {
  GstBus* bus = gst_element_get_bus(pipeline);
  GstMessage* msg = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR);
  std::string text;
  if (msg) {
    text = errorText(msg);
    gst_message_unref(msg);
  }
  gst_object_unref(bus);
  return text;
}

/// Plays @pipeline until EOS or an error, at most @timeout_s seconds, then sets it to NULL and
/// unrefs it. Returns whether it reached EOS.
inline bool playToEos(GstElement* pipeline, int timeout_s) {
  gst_element_set_state(pipeline, GST_STATE_PLAYING);
  GstBus* bus = gst_element_get_bus(pipeline);
  GstMessage* msg =
      gst_bus_timed_pop_filtered(bus, static_cast<GstClockTime>(timeout_s) * GST_SECOND,
                                 static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  const bool eos = msg && GST_MESSAGE_TYPE(msg) == GST_MESSAGE_EOS;
  if (msg) gst_message_unref(msg);
  gst_object_unref(bus);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(pipeline);
  return eos;
}

/// The frames GStreamer decodes from a video file, or -1 when it does not play to its end within
/// a minute.
inline int countVideoFrames(const std::string& file) {
  GstElement* pipeline = gst_parse_launch(
      ("filesrc location=" + file + " ! decodebin ! fakesink name=sink").c_str(), nullptr);
  GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline), "sink");
  int frames = 0;
  GstPad* pad = gst_element_get_static_pad(sink, "sink");
  gst_pad_add_probe(
      pad, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad*, GstPadProbeInfo*, gpointer data) {
        ++*static_cast<int*>(data);
        return GST_PAD_PROBE_OK;
      },
      &frames, nullptr);
  gst_object_unref(pad);
  gst_object_unref(sink);
  return playToEos(pipeline, 60) ? frames : -1;
}

/// Counts the warnings GLib logs while it lives (properties refused by their GParamSpec range or
/// by the element's own validation), without letting them through to stderr.
class WarningCounter {
 public:
  WarningCounter() {
    previous_ = g_log_set_default_handler(
        [](const gchar*, GLogLevelFlags level, const gchar* message, gpointer data) {
          auto* self = static_cast<WarningCounter*>(data);
          if (level & (G_LOG_LEVEL_WARNING | G_LOG_LEVEL_CRITICAL)) {
            self->count++;
            self->last = message ? message : "";
          }
        },
        this);
  }
  ~WarningCounter() { g_log_set_default_handler(previous_, nullptr); }
  WarningCounter(const WarningCounter&) = delete;
  WarningCounter& operator=(const WarningCounter&) = delete;

  int count = 0;
  std::string last;

 private:
  GLogFunc previous_;
};

}  // namespace jointflow::test
