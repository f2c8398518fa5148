/**
 * SECTION:element-jointflowoverlay
 * @title: jointflowoverlay
 *
 * Draws the poses that `jointflowtrack` attached to each frame: the COCO skeleton of every
 * person in a colour chosen by its track id, the id itself, optionally the person box, and a
 * short motion trail of each track. Tentative tracks (shorter than min-track-length) are drawn
 * thinner. Frames without JointFlow meta but with GstVideoRegionOfInterestMeta (for example from
 * another detector) get their boxes and "object_id" ids drawn instead.
 *
 * It draws in place in the negotiated format (packed RGB orders, I420, NV12): no conversion.
 *
 * ## Example launch line
 * |[
 * gst-launch-1.0 filesrc location=vtest.avi ! decodebin ! videoconvert ! jointflowtrack !
 *     jointflowoverlay draw-boxes=true ! videoconvert ! autovideosink
 * ]|
 */
#include "gstjointflowoverlay.h"

#include <gst/video/gstvideometa.h>

#include <deque>
#include <string>
#include <unordered_map>

#include "frame_painter.hpp"
#include "jointflowmeta.h"
#include "video_formats.hpp"

GST_DEBUG_CATEGORY_STATIC(gst_jointflow_overlay_debug);
#define GST_CAT_DEFAULT gst_jointflow_overlay_debug

using jointflow::gst::FramePainter;
using jointflow::gst::Rgb;

namespace {

enum {
  PROP_0,
  PROP_DRAW_BOXES,
  PROP_DRAW_IDS,
  PROP_DRAW_TENTATIVE,
  PROP_TRAIL_LENGTH,
  PROP_THICKNESS,
  PROP_KEYPOINT_THRESHOLD,
};

constexpr gboolean DEFAULT_DRAW_BOXES = FALSE;
constexpr gboolean DEFAULT_DRAW_IDS = TRUE;
constexpr gboolean DEFAULT_DRAW_TENTATIVE = TRUE;
constexpr guint DEFAULT_TRAIL_LENGTH = 15;
constexpr guint DEFAULT_THICKNESS = 2;
constexpr gfloat DEFAULT_KEYPOINT_THRESHOLD = 0.2f;

struct TrailPoint {
  guint64 frame;
  cv::Point2f at;
};

// Per-element drawing state: the recent positions of each track, for the motion trails.
struct OverlayState {
  std::unordered_map<gint64, std::deque<TrailPoint>> trails;
  guint64 frame = 0;

  void reset() {
    trails.clear();
    frame = 0;
  }
  void add(gint64 id, cv::Point2f at) { trails[id].push_back({frame, at}); }
  // Forgets positions older than @length frames, and tracks with none left.
  void prune(guint length) {
    for (auto it = trails.begin(); it != trails.end();) {
      auto& points = it->second;
      while (!points.empty() && points.front().frame + length <= frame) points.pop_front();
      it = points.empty() ? trails.erase(it) : std::next(it);
    }
  }
};

}  // namespace

struct _GstJointFlowOverlay {
  GstVideoFilter parent;

  gboolean draw_boxes;
  gboolean draw_ids;
  gboolean draw_tentative;
  guint trail_length;
  guint thickness;
  gfloat keypoint_threshold;

  OverlayState* state;
};

G_DEFINE_TYPE(GstJointFlowOverlay, gst_jointflow_overlay, GST_TYPE_VIDEO_FILTER);
GST_ELEMENT_REGISTER_DEFINE(jointflowoverlay, "jointflowoverlay", GST_RANK_NONE,
                            GST_TYPE_JOINTFLOW_OVERLAY);

static void gst_jointflow_overlay_set_property(GObject* object, guint prop_id, const GValue* value,
                                               GParamSpec* pspec) {
  auto* self = GST_JOINTFLOW_OVERLAY(object);
  GST_OBJECT_LOCK(self);
  switch (prop_id) {
    case PROP_DRAW_BOXES:
      self->draw_boxes = g_value_get_boolean(value);
      break;
    case PROP_DRAW_IDS:
      self->draw_ids = g_value_get_boolean(value);
      break;
    case PROP_DRAW_TENTATIVE:
      self->draw_tentative = g_value_get_boolean(value);
      break;
    case PROP_TRAIL_LENGTH:
      self->trail_length = g_value_get_uint(value);
      break;
    case PROP_THICKNESS:
      self->thickness = g_value_get_uint(value);
      break;
    case PROP_KEYPOINT_THRESHOLD:
      self->keypoint_threshold = g_value_get_float(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, prop_id, pspec);
      break;
  }
  GST_OBJECT_UNLOCK(self);
}

static void gst_jointflow_overlay_get_property(GObject* object, guint prop_id, GValue* value,
                                               GParamSpec* pspec) {
  auto* self = GST_JOINTFLOW_OVERLAY(object);
  GST_OBJECT_LOCK(self);
  switch (prop_id) {
    case PROP_DRAW_BOXES:
      g_value_set_boolean(value, self->draw_boxes);
      break;
    case PROP_DRAW_IDS:
      g_value_set_boolean(value, self->draw_ids);
      break;
    case PROP_DRAW_TENTATIVE:
      g_value_set_boolean(value, self->draw_tentative);
      break;
    case PROP_TRAIL_LENGTH:
      g_value_set_uint(value, self->trail_length);
      break;
    case PROP_THICKNESS:
      g_value_set_uint(value, self->thickness);
      break;
    case PROP_KEYPOINT_THRESHOLD:
      g_value_set_float(value, self->keypoint_threshold);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, prop_id, pspec);
      break;
  }
  GST_OBJECT_UNLOCK(self);
}

namespace {

struct DrawSettings {
  gboolean boxes, ids, tentative;
  guint trail_length, thickness;
  gfloat keypoint_threshold;
};

const Rgb kLabelText{255, 255, 255};

void drawTrail(FramePainter& painter, const std::deque<TrailPoint>& trail, Rgb colour) {
  if (trail.size() < 2) return;
  std::vector<cv::Point2f> points;
  points.reserve(trail.size());
  for (const auto& p : trail) points.push_back(p.at);
  painter.polyline(points, colour, 1);
}

void drawPerson(FramePainter& painter, const JointFlowPerson& p, const DrawSettings& s) {
  const Rgb colour = jointflow::gst::colourForId(p.track_id);
  const int thickness = p.tentative ? 1 : static_cast<int>(s.thickness);
  const guint n_limbs = jointflow_skeleton_get_n_limbs();
  for (guint l = 0; l < n_limbs; ++l) {
    guint a = 0, b = 0;
    jointflow_skeleton_get_limb(l, &a, &b);
    const JointFlowKeypoint& ka = p.keypoints[a];
    const JointFlowKeypoint& kb = p.keypoints[b];
    if (ka.score <= 0.f || kb.score <= 0.f) continue;
    if (ka.score < s.keypoint_threshold || kb.score < s.keypoint_threshold) continue;
    painter.line({ka.x, ka.y}, {kb.x, kb.y}, colour, thickness);
  }
  for (const JointFlowKeypoint& k : p.keypoints) {
    if (k.score <= 0.f || k.score < s.keypoint_threshold) continue;
    painter.circle({k.x, k.y}, 1.5f + thickness, colour, true);
  }
  if (s.boxes) painter.rectangle({p.x, p.y}, {p.x + p.width, p.y + p.height}, colour, thickness);
  if (s.ids) painter.label(std::to_string(p.track_id), {p.x, p.y - 4.f}, kLabelText, colour, 0.5);
}

// Where a track's trail runs through: the middle of the box's bottom edge (the feet).
cv::Point2f anchor(float x, float y, float w, float h) {
  return {x + w / 2.f, y + h};
}

void drawPoses(FramePainter& painter, OverlayState& state, const GstJointFlowMeta* meta,
               const DrawSettings& s) {
  for (guint i = 0; i < gst_jointflow_meta_get_n_persons(meta); ++i) {
    const JointFlowPerson* p = gst_jointflow_meta_get_person(meta, i);
    if (p->tentative && !s.tentative) continue;
    state.add(p->track_id, anchor(p->x, p->y, p->width, p->height));
  }
  if (s.trail_length > 0)
    for (const auto& [id, trail] : state.trails)
      drawTrail(painter, trail, jointflow::gst::colourForId(id));
  for (guint i = 0; i < gst_jointflow_meta_get_n_persons(meta); ++i) {
    const JointFlowPerson* p = gst_jointflow_meta_get_person(meta, i);
    if (p->tentative && !s.tentative) continue;
    drawPerson(painter, *p, s);
  }
}

// Boxes of GstVideoRegionOfInterestMeta, for streams analysed by other elements.
void drawRegions(FramePainter& painter, OverlayState& state, GstBuffer* buffer,
                 const DrawSettings& s) {
  gpointer iter = nullptr;
  GstMeta* m;
  while ((m = gst_buffer_iterate_meta_filtered(buffer, &iter,
                                               GST_VIDEO_REGION_OF_INTEREST_META_API_TYPE))) {
    auto* roi = reinterpret_cast<GstVideoRegionOfInterestMeta*>(m);
    gint id = -1;
    if (GstStructure* obj = gst_video_region_of_interest_meta_get_param(roi, "object_id"))
      gst_structure_get_int(obj, "id", &id);
    const Rgb colour = jointflow::gst::colourForId(id >= 0 ? id : roi->id);
    const float x = roi->x, y = roi->y, w = roi->w, h = roi->h;
    painter.rectangle({x, y}, {x + w, y + h}, colour, static_cast<int>(s.thickness));
    if (id >= 0) {
      state.add(id, anchor(x, y, w, h));
      if (s.trail_length > 0) drawTrail(painter, state.trails[id], colour);
      if (s.ids) painter.label(std::to_string(id), {x, y - 4.f}, kLabelText, colour, 0.5);
    }
  }
}

}  // namespace

static GstFlowReturn gst_jointflow_overlay_transform_frame_ip(GstVideoFilter* filter,
                                                              GstVideoFrame* frame) {
  auto* self = GST_JOINTFLOW_OVERLAY(filter);
  DrawSettings s;
  GST_OBJECT_LOCK(self);
  s = {self->draw_boxes,   self->draw_ids,  self->draw_tentative,
       self->trail_length, self->thickness, self->keypoint_threshold};
  GST_OBJECT_UNLOCK(self);

  OverlayState& state = *self->state;
  if (GST_BUFFER_FLAG_IS_SET(frame->buffer, GST_BUFFER_FLAG_DISCONT)) state.trails.clear();
  state.frame++;
  state.prune(s.trail_length);

  FramePainter painter(frame);
  if (const GstJointFlowMeta* meta = gst_buffer_get_jointflow_meta(frame->buffer))
    drawPoses(painter, state, meta, s);
  else
    drawRegions(painter, state, frame->buffer, s);
  return GST_FLOW_OK;
}

static gboolean gst_jointflow_overlay_sink_event(GstBaseTransform* trans, GstEvent* event) {
  auto* self = GST_JOINTFLOW_OVERLAY(trans);
  // After a flush (seek) the old positions belong to another part of the stream.
  if (GST_EVENT_TYPE(event) == GST_EVENT_FLUSH_STOP) self->state->trails.clear();
  return GST_BASE_TRANSFORM_CLASS(gst_jointflow_overlay_parent_class)->sink_event(trans, event);
}

static gboolean gst_jointflow_overlay_start(GstBaseTransform* trans) {
  GST_JOINTFLOW_OVERLAY(trans)->state->reset();
  return TRUE;
}

static gboolean gst_jointflow_overlay_stop(GstBaseTransform* trans) {
  GST_JOINTFLOW_OVERLAY(trans)->state->reset();
  return TRUE;
}

static void gst_jointflow_overlay_finalize(GObject* object) {
  delete GST_JOINTFLOW_OVERLAY(object)->state;
  G_OBJECT_CLASS(gst_jointflow_overlay_parent_class)->finalize(object);
}

static void gst_jointflow_overlay_class_init(GstJointFlowOverlayClass* klass) {
  auto* gobject_class = G_OBJECT_CLASS(klass);
  auto* element_class = GST_ELEMENT_CLASS(klass);
  auto* trans_class = GST_BASE_TRANSFORM_CLASS(klass);
  auto* filter_class = GST_VIDEO_FILTER_CLASS(klass);

  GST_DEBUG_CATEGORY_INIT(gst_jointflow_overlay_debug, "jointflowoverlay", 0,
                          "JointFlow pose overlay");

  gobject_class->set_property = gst_jointflow_overlay_set_property;
  gobject_class->get_property = gst_jointflow_overlay_get_property;
  gobject_class->finalize = gst_jointflow_overlay_finalize;

  const auto flags =
      static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS | GST_PARAM_CONTROLLABLE);
  g_object_class_install_property(
      gobject_class, PROP_DRAW_BOXES,
      g_param_spec_boolean("draw-boxes", "Draw boxes", "Draw each person's box", DEFAULT_DRAW_BOXES,
                           flags));
  g_object_class_install_property(
      gobject_class, PROP_DRAW_IDS,
      g_param_spec_boolean("draw-ids", "Draw ids", "Draw each person's track id above its box",
                           DEFAULT_DRAW_IDS, flags));
  g_object_class_install_property(
      gobject_class, PROP_DRAW_TENTATIVE,
      g_param_spec_boolean("draw-tentative", "Draw tentative tracks",
                           "Draw tracks that are still tentative (shorter than jointflowtrack's "
                           "min-track-length); they are drawn with thin lines",
                           DEFAULT_DRAW_TENTATIVE, flags));
  g_object_class_install_property(
      gobject_class, PROP_TRAIL_LENGTH,
      g_param_spec_uint("trail-length", "Trail length",
                        "Frames of motion trail drawn behind each track (0 = none)", 0, 1000,
                        DEFAULT_TRAIL_LENGTH, flags));
  g_object_class_install_property(
      gobject_class, PROP_THICKNESS,
      g_param_spec_uint("thickness", "Line thickness", "Skeleton and box line width in pixels", 1,
                        64, DEFAULT_THICKNESS, flags));
  g_object_class_install_property(
      gobject_class, PROP_KEYPOINT_THRESHOLD,
      g_param_spec_float("keypoint-threshold", "Keypoint threshold",
                         "Keypoints scoring below this are not drawn, nor the limbs they end", 0.f,
                         1.f, DEFAULT_KEYPOINT_THRESHOLD, flags));

  gst_element_class_set_static_metadata(
      element_class, "JointFlow pose overlay", "Filter/Effect/Video",
      "Draws tracked multi-person poses (skeletons coloured by track id, ids, boxes, trails)",
      "JointFlow developers");
  jointflow::gst::addVideoPadTemplates(element_class);

  trans_class->sink_event = gst_jointflow_overlay_sink_event;
  trans_class->start = gst_jointflow_overlay_start;
  trans_class->stop = gst_jointflow_overlay_stop;
  filter_class->transform_frame_ip = gst_jointflow_overlay_transform_frame_ip;
}

static void gst_jointflow_overlay_init(GstJointFlowOverlay* self) {
  self->draw_boxes = DEFAULT_DRAW_BOXES;
  self->draw_ids = DEFAULT_DRAW_IDS;
  self->draw_tentative = DEFAULT_DRAW_TENTATIVE;
  self->trail_length = DEFAULT_TRAIL_LENGTH;
  self->thickness = DEFAULT_THICKNESS;
  self->keypoint_threshold = DEFAULT_KEYPOINT_THRESHOLD;
  self->state = new OverlayState();
}
