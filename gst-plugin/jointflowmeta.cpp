// GstJointFlowMeta: registration, copy/scale transforms and accessors (API in jointflowmeta.h).
//
// This file is compiled into a small static library that the plugin and every application
// reading the meta link. Both copies register the meta by name and look the name up first, so
// whichever copy runs first registers it and the other finds it: there is one GType and one
// GstMetaInfo per process.
#include "jointflowmeta.h"

#include <gst/video/video.h>

#include <cstring>
#include <string_view>

#include "jointflow/types.hpp"

static_assert(JOINTFLOW_N_KEYPOINTS == jointflow::kNumJoints, "the meta carries COCO-17 poses");

namespace {

constexpr const char* kApiName = "GstJointFlowMetaAPI";
constexpr const char* kImplName = "GstJointFlowMeta";

gboolean metaInit(GstMeta* meta, gpointer, GstBuffer*) {
  auto* m = reinterpret_cast<GstJointFlowMeta*>(meta);
  m->width = m->height = 0;
  m->predicted = FALSE;
  m->n_persons = 0;
  m->persons = nullptr;
  return TRUE;
}

void metaFree(GstMeta* meta, GstBuffer*) {
  auto* m = reinterpret_cast<GstJointFlowMeta*>(meta);
  g_free(m->persons);
  m->persons = nullptr;
  m->n_persons = 0;
}

GstJointFlowMeta* copyTo(GstBuffer* dest, const GstJointFlowMeta* src) {
  GstJointFlowMeta* out = gst_buffer_add_jointflow_meta(dest, src->width, src->height);
  if (!out) return nullptr;
  out->predicted = src->predicted;
  out->n_persons = src->n_persons;
  out->persons = static_cast<JointFlowPerson*>(
      g_memdup2(src->persons, sizeof(JointFlowPerson) * src->n_persons));
  return out;
}

// Scales every coordinate by the ratio of output to input size (videoscale and friends).
void scale(GstJointFlowMeta* m, guint out_width, guint out_height) {
  if (m->width == 0 || m->height == 0) return;
  const float sx = static_cast<float>(out_width) / static_cast<float>(m->width);
  const float sy = static_cast<float>(out_height) / static_cast<float>(m->height);
  for (guint i = 0; i < m->n_persons; ++i) {
    JointFlowPerson& p = m->persons[i];
    p.x *= sx;
    p.y *= sy;
    p.width *= sx;
    p.height *= sy;
    for (JointFlowKeypoint& k : p.keypoints) {
      k.x *= sx;
      k.y *= sy;
    }
  }
  m->width = out_width;
  m->height = out_height;
}

gboolean metaTransform(GstBuffer* dest, GstMeta* meta, GstBuffer*, GQuark type, gpointer data) {
  const auto* src = reinterpret_cast<const GstJointFlowMeta*>(meta);
  if (GST_META_TRANSFORM_IS_COPY(type)) {
    // A region copy keeps the same frame, hence the same coordinates.
    return copyTo(dest, src) != nullptr;
  }
  if (GST_VIDEO_META_TRANSFORM_IS_SCALE(type)) {
    const auto* t = static_cast<const GstVideoMetaTransform*>(data);
    GstJointFlowMeta* out = copyTo(dest, src);
    if (!out) return FALSE;
    scale(out, GST_VIDEO_INFO_WIDTH(t->out_info), GST_VIDEO_INFO_HEIGHT(t->out_info));
    return TRUE;
  }
  return FALSE;  // any other transform (crop, flip, ...) would leave the coordinates wrong
}

}  // namespace

extern "C" {

GType gst_jointflow_meta_api_get_type(void) {
  static gsize type = 0;
  if (g_once_init_enter(&type)) {
    GType t = g_type_from_name(kApiName);
    if (t == 0) {
      // The same tags as GstVideoRegionOfInterestMeta: video elements that change the size call
      // our transform (scale), the others copy the meta.
      static const gchar* tags[] = {GST_META_TAG_VIDEO_STR, GST_META_TAG_VIDEO_ORIENTATION_STR,
                                    GST_META_TAG_VIDEO_SIZE_STR, nullptr};
      t = gst_meta_api_type_register(kApiName, tags);
    }
    g_once_init_leave(&type, t);
  }
  return static_cast<GType>(type);
}

const GstMetaInfo* gst_jointflow_meta_get_info(void) {
  static const GstMetaInfo* info = nullptr;
  if (g_once_init_enter(&info)) {
    const GstMetaInfo* i = gst_meta_get_info(kImplName);
    if (i == nullptr) {
      i = gst_meta_register(GST_JOINTFLOW_META_API_TYPE, kImplName, sizeof(GstJointFlowMeta),
                            metaInit, metaFree, metaTransform);
    }
    g_once_init_leave(&info, i);
  }
  return info;
}

GstJointFlowMeta* gst_buffer_get_jointflow_meta(GstBuffer* buffer) {
  g_return_val_if_fail(GST_IS_BUFFER(buffer), nullptr);
  return reinterpret_cast<GstJointFlowMeta*>(
      gst_buffer_get_meta(buffer, GST_JOINTFLOW_META_API_TYPE));
}

GstJointFlowMeta* gst_buffer_add_jointflow_meta(GstBuffer* buffer, guint width, guint height) {
  g_return_val_if_fail(GST_IS_BUFFER(buffer), nullptr);
  auto* m = reinterpret_cast<GstJointFlowMeta*>(
      gst_buffer_add_meta(buffer, GST_JOINTFLOW_META_INFO, nullptr));
  if (m) {
    m->width = width;
    m->height = height;
  }
  return m;
}

guint gst_jointflow_meta_get_n_persons(const GstJointFlowMeta* meta) {
  g_return_val_if_fail(meta != nullptr, 0);
  return meta->n_persons;
}

const JointFlowPerson* gst_jointflow_meta_get_person(const GstJointFlowMeta* meta, guint index) {
  g_return_val_if_fail(meta != nullptr, nullptr);
  return index < meta->n_persons ? &meta->persons[index] : nullptr;
}

JointFlowPerson* gst_jointflow_meta_add_person(GstJointFlowMeta* meta,
                                               const JointFlowPerson* person) {
  g_return_val_if_fail(meta != nullptr && person != nullptr, nullptr);
  meta->persons = g_renew(JointFlowPerson, meta->persons, meta->n_persons + 1);
  meta->persons[meta->n_persons] = *person;
  return &meta->persons[meta->n_persons++];
}

const gchar* jointflow_keypoint_name(guint index) {
  // The core's names are string literals, hence NUL-terminated.
  return index < JOINTFLOW_N_KEYPOINTS ? jointflow::kJointNames[index].data() : nullptr;
}

gint jointflow_keypoint_from_name(const gchar* name) {
  if (name == nullptr) return -1;
  for (guint i = 0; i < JOINTFLOW_N_KEYPOINTS; ++i)
    if (jointflow::kJointNames[i] == std::string_view(name)) return static_cast<gint>(i);
  return -1;
}

guint jointflow_skeleton_get_n_limbs(void) {
  return static_cast<guint>(jointflow::kCocoSkeleton.size());
}

gboolean jointflow_skeleton_get_limb(guint index, guint* a, guint* b) {
  if (index >= jointflow::kCocoSkeleton.size()) return FALSE;
  if (a) *a = static_cast<guint>(jointflow::kCocoSkeleton[index].first);
  if (b) *b = static_cast<guint>(jointflow::kCocoSkeleton[index].second);
  return TRUE;
}

}  // extern "C"
