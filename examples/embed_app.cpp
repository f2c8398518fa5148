// Embedding jointflowtrack in an application and reading the tracks from the metadata.
//
//   GST_PLUGIN_PATH=build/gst-plugin build/examples/embed_app VIDEO [MAX_FRAMES]
//
// The pipeline is built from a description; a pad probe on the tracker's output reads
// GstJointFlowMeta (jointflowmeta.h, link the gstjointflowmeta library) and prints every person.
// An appsink works the same way: gst_buffer_get_jointflow_meta() on the sample's buffer.
#include <gst/gst.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "jointflowmeta.h"

namespace {

struct Progress {
  guint64 frame = 0;
  guint64 max_frames = 0;
};

GstPadProbeReturn printTracks(GstPad* pad, GstPadProbeInfo* info, gpointer data) {
  auto* progress = static_cast<Progress*>(data);
  GstBuffer* buffer = GST_PAD_PROBE_INFO_BUFFER(info);
  const GstJointFlowMeta* meta = gst_buffer_get_jointflow_meta(buffer);
  if (meta == nullptr) return GST_PAD_PROBE_OK;
  std::printf("frame %llu  t=%.2fs  %u people%s\n",
              static_cast<unsigned long long>(progress->frame),
              GST_BUFFER_PTS_IS_VALID(buffer) ? GST_BUFFER_PTS(buffer) / 1e9 : -1.0,
              gst_jointflow_meta_get_n_persons(meta), meta->predicted ? " (predicted)" : "");
  for (guint i = 0; i < gst_jointflow_meta_get_n_persons(meta); ++i) {
    const JointFlowPerson* p = gst_jointflow_meta_get_person(meta, i);
    const JointFlowKeypoint& nose = p->keypoints[JOINTFLOW_KEYPOINT_NOSE];
    std::printf("  track %-4lld %s score %.2f  box %.0f,%.0f %.0fx%.0f  %s %.0f,%.0f (%.2f)\n",
                static_cast<long long>(p->track_id), p->tentative ? "tentative" : "confirmed",
                p->score, p->x, p->y, p->width, p->height,
                jointflow_keypoint_name(JOINTFLOW_KEYPOINT_NOSE), nose.x, nose.y, nose.score);
  }
  // Enough frames: end the stream here, so that the pipeline finishes cleanly.
  if (progress->max_frames && ++progress->frame >= progress->max_frames) {
    gst_pad_push_event(pad, gst_event_new_eos());
    return GST_PAD_PROBE_REMOVE;
  }
  return GST_PAD_PROBE_OK;
}

}  // namespace

int main(int argc, char** argv) {
  gst_init(&argc, &argv);
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s VIDEO [MAX_FRAMES]\n", argv[0]);
    return 2;
  }
  Progress progress;
  progress.max_frames = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 20;

  gchar* uri =
      gst_uri_is_valid(argv[1]) ? g_strdup(argv[1]) : gst_filename_to_uri(argv[1], nullptr);
  const std::string description = std::string("uridecodebin uri=\"") + (uri ? uri : "") +
                                  "\" ! videoconvert ! jointflowtrack name=track ! fakesink";
  g_free(uri);
  GError* error = nullptr;
  GstElement* pipeline = gst_parse_launch(description.c_str(), &error);
  if (pipeline == nullptr || error != nullptr) {
    std::fprintf(stderr,
                 "could not build the pipeline: %s\n(is GST_PLUGIN_PATH=build/gst-plugin set?)\n",
                 error ? error->message : "unknown error");
    g_clear_error(&error);
    return 1;
  }
  GstElement* track = gst_bin_get_by_name(GST_BIN(pipeline), "track");
  GstPad* src = gst_element_get_static_pad(track, "src");
  gst_pad_add_probe(src, GST_PAD_PROBE_TYPE_BUFFER, printTracks, &progress, nullptr);
  gst_object_unref(src);
  gst_object_unref(track);

  gst_element_set_state(pipeline, GST_STATE_PLAYING);
  GstBus* bus = gst_element_get_bus(pipeline);
  GstMessage* msg = gst_bus_timed_pop_filtered(
      bus, GST_CLOCK_TIME_NONE, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  int status = 0;
  if (GST_MESSAGE_TYPE(msg) == GST_MESSAGE_ERROR) {
    gst_message_parse_error(msg, &error, nullptr);
    std::fprintf(stderr, "error from %s: %s\n", GST_OBJECT_NAME(GST_MESSAGE_SRC(msg)),
                 error->message);
    g_clear_error(&error);
    status = 1;
  }
  gst_message_unref(msg);
  gst_object_unref(bus);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(pipeline);
  return status;
}
