/**
 * SECTION:element-jointflowjsonwriter
 * @title: jointflowjsonwriter
 *
 * Writes one JSON object per frame (JSON Lines) with the poses `jointflowtrack` attached:
 *
 * |[
 * {"frame":0,"timestamp":0,"resolution":{"width":768,"height":576},"predicted":false,
 *  "objects":[{"id":1,"tentative":true,"age":1,"confidence":0.71,"x":..,"y":..,"w":..,"h":..,
 *              "detection":{"bounding_box":{"x_min":..,"y_min":..,"x_max":..,"y_max":..},
 *                           "confidence":0.71,"label":"person","label_id":0},
 *              "keypoints":{"nose":{"x":..,"y":..,"score":..}, "left_eye":{..}, ...}}]}
 * ]|
 *
 * `timestamp` is the buffer's PTS in nanoseconds (null when the buffer has none); coordinates are
 * pixels of the frame. With `source-id` set, each record also has `"source_id"`: the records are
 * then byte for byte those `jointflowmetapublish` sends (both come from one serializer). The video
 * passes through untouched, so the element can sit anywhere after `jointflowtrack`. Each line is
 * flushed as it is written, so that a reader can follow the file.
 *
 * ## Example launch line
 * |[
 * gst-launch-1.0 filesrc location=vtest.avi ! decodebin ! videoconvert ! jointflowtrack !
 *     jointflowjsonwriter location=poses.jsonl ! fakesink
 * ]|
 */
#include "gstjointflowjsonwriter.h"

#include <gst/video/video.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

#include "jointflowmeta.h"
#include "output_properties.hpp"
#include "pose_json.hpp"
#include "setting_properties.hpp"

GST_DEBUG_CATEGORY_STATIC(gst_jointflow_json_writer_debug);
#define GST_CAT_DEFAULT gst_jointflow_json_writer_debug

struct _GstJointFlowJsonWriter {
  GstBaseTransform parent;

  // The properties, under the object lock; location does not change while the file is open.
  jointflow::gst::JsonWriterSettings* settings;
  FILE* file;
  gboolean owns_file;
  jointflow::gst::FrameRecorder* recorder;
};

G_DEFINE_TYPE(GstJointFlowJsonWriter, gst_jointflow_json_writer, GST_TYPE_BASE_TRANSFORM);
GST_ELEMENT_REGISTER_DEFINE(jointflowjsonwriter, "jointflowjsonwriter", GST_RANK_NONE,
                            GST_TYPE_JOINTFLOW_JSON_WRITER);

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS("video/x-raw(ANY)"));
static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS("video/x-raw(ANY)"));

static bool writesToStdout(const std::string& location) {
  return location.empty() || location == "-";
}

static void gst_jointflow_json_writer_set_property(GObject* object, guint prop_id,
                                                   const GValue* value, GParamSpec* pspec) {
  auto* self = GST_JOINTFLOW_JSON_WRITER(object);
  GST_OBJECT_LOCK(self);
  const bool open = self->file != nullptr;
  GST_OBJECT_UNLOCK(self);
  if (open && std::strcmp(pspec->name, "location") == 0) {
    // The file is opened at start: a new location mid-stream would split the records.
    g_warning("jointflowjsonwriter: location can only be changed in the NULL or READY state");
    return;
  }
  jointflow::gst::setSettingProperty(object, *self->settings,
                                     jointflow::gst::jsonWriterProperties(), prop_id, value, pspec);
}

static void gst_jointflow_json_writer_get_property(GObject* object, guint prop_id, GValue* value,
                                                   GParamSpec* pspec) {
  jointflow::gst::getSettingProperty(object, *GST_JOINTFLOW_JSON_WRITER(object)->settings,
                                     jointflow::gst::jsonWriterProperties(), prop_id, value, pspec);
}

static gboolean gst_jointflow_json_writer_start(GstBaseTransform* trans) {
  auto* self = GST_JOINTFLOW_JSON_WRITER(trans);
  GST_OBJECT_LOCK(self);
  const std::string location = self->settings->location;
  std::string source_id = self->settings->source_id;
  GST_OBJECT_UNLOCK(self);
  FILE* file = stdout;
  gboolean owns = FALSE;
  if (!writesToStdout(location)) {
    file = std::fopen(location.c_str(), "w");
    if (file == nullptr) {
      GST_ELEMENT_ERROR(
          self, RESOURCE, OPEN_WRITE,
          ("Could not open \"%s\" for writing: %s", location.c_str(), g_strerror(errno)),
          (nullptr));
      return FALSE;
    }
    owns = TRUE;
  }
  GST_OBJECT_LOCK(self);
  self->file = file;
  self->owns_file = owns;
  self->recorder->reset(std::move(source_id));
  GST_OBJECT_UNLOCK(self);
  return TRUE;
}

static gboolean gst_jointflow_json_writer_stop(GstBaseTransform* trans) {
  auto* self = GST_JOINTFLOW_JSON_WRITER(trans);
  GST_OBJECT_LOCK(self);
  FILE* file = self->file;
  const gboolean owns = self->owns_file;
  self->file = nullptr;
  GST_OBJECT_UNLOCK(self);
  if (file == nullptr) return TRUE;
  if (owns ? std::fclose(file) != 0 : std::fflush(file) != 0) {
    GST_ELEMENT_ERROR(self, RESOURCE, CLOSE,
                      ("Could not finish writing \"%s\": %s", self->settings->location.c_str(),
                       g_strerror(errno)),
                      (nullptr));
    return FALSE;
  }
  return TRUE;
}

static gboolean gst_jointflow_json_writer_set_caps(GstBaseTransform* trans, GstCaps* incaps,
                                                   GstCaps*) {
  GST_JOINTFLOW_JSON_WRITER(trans)->recorder->setCaps(incaps);
  return TRUE;
}

static GstFlowReturn gst_jointflow_json_writer_transform_ip(GstBaseTransform* trans,
                                                            GstBuffer* buffer) {
  auto* self = GST_JOINTFLOW_JSON_WRITER(trans);
  const std::string line = self->recorder->next(buffer) + "\n";
  if (std::fwrite(line.data(), 1, line.size(), self->file) != line.size() ||
      std::fflush(self->file) != 0) {
    GST_ELEMENT_ERROR(
        self, RESOURCE, WRITE,
        ("Could not write to \"%s\": %s",
         writesToStdout(self->settings->location) ? "stdout" : self->settings->location.c_str(),
         g_strerror(errno)),
        (nullptr));
    return GST_FLOW_ERROR;
  }
  return GST_FLOW_OK;
}

static void gst_jointflow_json_writer_finalize(GObject* object) {
  auto* self = GST_JOINTFLOW_JSON_WRITER(object);
  delete self->settings;
  delete self->recorder;
  G_OBJECT_CLASS(gst_jointflow_json_writer_parent_class)->finalize(object);
}

static void gst_jointflow_json_writer_class_init(GstJointFlowJsonWriterClass* klass) {
  auto* gobject_class = G_OBJECT_CLASS(klass);
  auto* element_class = GST_ELEMENT_CLASS(klass);
  auto* trans_class = GST_BASE_TRANSFORM_CLASS(klass);

  GST_DEBUG_CATEGORY_INIT(gst_jointflow_json_writer_debug, "jointflowjsonwriter", 0,
                          "JointFlow JSON Lines writer");

  gobject_class->set_property = gst_jointflow_json_writer_set_property;
  gobject_class->get_property = gst_jointflow_json_writer_get_property;
  gobject_class->finalize = gst_jointflow_json_writer_finalize;

  jointflow::gst::installSettingProperties(gobject_class, jointflow::gst::jsonWriterProperties());

  gst_element_class_set_static_metadata(
      element_class, "JointFlow JSON writer", "Filter/Analyzer/Video",
      "Writes the tracked poses of every frame as JSON Lines (frame, timestamp, resolution, "
      "objects with id, box, score and named keypoints)",
      "JointFlow developers");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);

  trans_class->start = gst_jointflow_json_writer_start;
  trans_class->stop = gst_jointflow_json_writer_stop;
  trans_class->set_caps = gst_jointflow_json_writer_set_caps;
  trans_class->transform_ip = gst_jointflow_json_writer_transform_ip;
  trans_class->transform_ip_on_passthrough = TRUE;
}

static void gst_jointflow_json_writer_init(GstJointFlowJsonWriter* self) {
  self->settings = new jointflow::gst::JsonWriterSettings();
  self->file = nullptr;
  self->owns_file = FALSE;
  self->recorder = new jointflow::gst::FrameRecorder();
  // The video is never modified: buffers pass through without being made writable.
  gst_base_transform_set_passthrough(GST_BASE_TRANSFORM(self), TRUE);
  gst_base_transform_set_in_place(GST_BASE_TRANSFORM(self), TRUE);
}
