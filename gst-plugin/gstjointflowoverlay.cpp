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
#include "setting_properties.hpp"
#include "video_formats.hpp"

GST_DEBUG_CATEGORY_STATIC(gst_jointflow_overlay_debug);
#define GST_CAT_DEFAULT gst_jointflow_overlay_debug

using jointflow::gst::FramePainter;
using jointflow::gst::Rgb;

namespace {

// What the properties set; the defaults are the properties' defaults.
struct DrawSettings {
  bool boxes = false;
  bool ids = true;
  bool tentative = true;
  unsigned trail_length = 15;
  unsigned thickness = 2;
  float keypoint_threshold = 0.2f;
};

// The properties, one row each (setting_properties.hpp); all apply at once.
const std::vector<jointflow::SettingSpec<DrawSettings>>& overlayProperties() {
  using jointflow::memberSetting;
  using D = DrawSettings;
  using K = jointflow::SettingKind;
  static const std::vector<jointflow::SettingSpec<D>> rows = {
      memberSetting<D>(
          {"draw-boxes", "Draw boxes", "Draw each person's box", K::kBool, 0, 0, nullptr, true},
          &D::boxes),
      memberSetting<D>({"draw-ids", "Draw ids", "Draw each person's track id above its box",
                        K::kBool, 0, 0, nullptr, true},
                       &D::ids),
      memberSetting<D>({"draw-tentative", "Draw tentative tracks",
                        "Draw tracks that are still tentative (shorter than jointflowtrack's "
                        "min-track-length); they are drawn with thin lines",
                        K::kBool, 0, 0, nullptr, true},
                       &D::tentative),
      memberSetting<D>({"trail-length", "Trail length",
                        "Frames of motion trail drawn behind each track (0 = none)", K::kUInt, 0,
                        1000, nullptr, true},
                       &D::trail_length),
      memberSetting<D>({"thickness", "Line thickness", "Skeleton and box line width in pixels",
                        K::kUInt, 1, 64, nullptr, true},
                       &D::thickness),
      memberSetting<D>({"keypoint-threshold", "Keypoint threshold",
                        "Keypoints scoring below this are not drawn, nor the limbs they end",
                        K::kFloat, 0, 1, nullptr, true},
                       &D::keypoint_threshold),
  };
  return rows;
}

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

  DrawSettings* settings;  ///< the properties, guarded by the object lock
  OverlayState* state;
};

G_DEFINE_TYPE(GstJointFlowOverlay, gst_jointflow_overlay, GST_TYPE_VIDEO_FILTER);
GST_ELEMENT_REGISTER_DEFINE(jointflowoverlay, "jointflowoverlay", GST_RANK_NONE,
                            GST_TYPE_JOINTFLOW_OVERLAY);

static void gst_jointflow_overlay_set_property(GObject* object, guint prop_id, const GValue* value,
                                               GParamSpec* pspec) {
  jointflow::gst::setSettingProperty(object, *GST_JOINTFLOW_OVERLAY(object)->settings,
                                     overlayProperties(), prop_id, value, pspec);
}

static void gst_jointflow_overlay_get_property(GObject* object, guint prop_id, GValue* value,
                                               GParamSpec* pspec) {
  jointflow::gst::getSettingProperty(object, *GST_JOINTFLOW_OVERLAY(object)->settings,
                                     overlayProperties(), prop_id, value, pspec);
}

namespace {

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
  GST_OBJECT_LOCK(self);
  const DrawSettings s = *self->settings;
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
  delete GST_JOINTFLOW_OVERLAY(object)->settings;
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

  jointflow::gst::installSettingProperties(gobject_class, overlayProperties());

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
  self->settings = new DrawSettings();
  self->state = new OverlayState();
}
