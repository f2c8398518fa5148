/**
 * SECTION:element-jointflowtrack
 * @title: jointflowtrack
 *
 * Estimates the 2D poses of every person in each frame and links them over time into tracks,
 * online (JointFlow: Temporal Flow Fields for Multi Person Pose Tracking, BMVC 2018). Each output
 * buffer carries a GstJointFlowMeta with all poses of the frame (17 COCO keypoints with scores,
 * track id, tentative flag, box, person score; see jointflowmeta.h) and one
 * GstVideoRegionOfInterestMeta of type "person" per person with DL Streamer-style "detection"
 * and "object_id" parameters. The video itself passes through unchanged.
 *
 * Packed RGB and BGR frames go to the networks without a copy; 4-byte RGB orders lose their
 * fourth byte, and I420/NV12 are converted to BGR for the networks only.
 *
 * The tracks start afresh only where the stream restarts: a flush (a flushing seek), a new stream
 * (STREAM-START) and a change of resolution; track ids keep counting up, so an id is never given
 * to two people. Dropped buffers, DISCONT flags, gaps in the timestamps and new non-flushing
 * segments (concat, splitmuxsrc) are gaps in time that the tracks live through: every time-based
 * setting (lost-time, smoothing) runs on the running time of the buffers' PTS. Buffers without a
 * PTS, or with one not after the previous buffer's, are taken one frame duration after it (said
 * once in the log).
 *
 * With inference-interval=N the networks run on every Nth frame; on the frames in between every
 * track is moved on by its motion model (GstJointFlowMeta.predicted is TRUE), so the poses
 * neither stand still nor flicker. When downstream reports lateness through QoS events (a live
 * pipeline whose sink syncs to the clock) and skip-late-frames is TRUE, frames that are already
 * late are predicted the same way instead of inferred, so the element catches up and latency
 * does not grow. To bound latency at a live source in any case, put a leaky queue in front:
 * `queue leaky=downstream max-size-buffers=1`.
 *
 * The networks run on OpenCV's dnn module by default, or with backend=openvino on OpenVINO's
 * runtime (about three times faster on a CPU; docs/benchmarks.md). OpenVINO runs asynchronously:
 * the element then holds one frame, so that the network of frame N runs while frame N-1 is
 * associated and pushed and upstream brings frame N+1; that adds one frame of latency (reported
 * in the latency query). async-inference=false gives that frame back: each frame then leaves
 * with its own poses, at a lower frame rate. Elements with the same model-instance-id share one
 * compiled model of each network (one copy of the weights), each with its own infer requests.
 *
 * With stats-interval=N the element posts a "jointflowtrack-stats" element message every N seconds
 * of stream time and at EOS: frames in, inferred and predicted, tracks active, lost and created,
 * histograms of the inference time, the time in the element and (live) each frame's lag from its
 * capture, and the version and model files (track_stats.hpp; docs/gstreamer.md).
 *
 * Properties that configure the models and the tracker are read when the element starts (goes
 * from READY to PAUSED). A model that is missing or not what was expected makes that state change
 * fail with an error message naming the file.
 *
 * ## Example launch line
 * |[
 * gst-launch-1.0 filesrc location=vtest.avi ! decodebin ! videoconvert !
 *     jointflowtrack similarity=oks ! jointflowoverlay ! videoconvert ! autovideosink
 * gst-launch-1.0 filesrc location=vtest.avi ! decodebin ! videoconvert !
 *     jointflowtrack backend=openvino model-instance-id=shared ! fakesink
 * ]|
 */
#include "gstjointflowtrack.h"

#include <gst/video/gstvideometa.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "frame_converter.hpp"
#include "frame_lag.hpp"
#include "jointflow/error.hpp"
#include "jointflow/frame_clock.hpp"
#include "jointflow/pose_associator.hpp"
#include "jointflow/tracker.hpp"
#include "jointflowmeta.h"
#include "person_box.hpp"
#include "setting_enum_types.h"
#include "setting_properties.hpp"
#include "track_properties.hpp"
#include "track_stats.hpp"
#include "video_formats.hpp"

GST_DEBUG_CATEGORY_STATIC(gst_jointflow_track_debug);
#define GST_CAT_DEFAULT gst_jointflow_track_debug

namespace {

// What the streaming thread owns: the tracker and the buffers reused from frame to frame.
struct StreamState {
  std::unique_ptr<jointflow::Tracker> tracker;
  jointflow::gst::FrameConverter converter;
  std::int64_t frame = 0;           ///< frames since the last reset
  std::int64_t last_inferred = -1;  ///< frame of the last inference since the reset, -1 = none
  /// With an asynchronous engine: the inferred frame whose network runs while the next frame
  /// comes in (pushed once that one is submitted, or drained before an event or a predicted
  /// frame).
  GstBuffer* held = nullptr;
  std::int64_t held_arrival_us = 0;  ///< when the held frame came in (g_get_monotonic_time)
  double held_submit_s = 0;          ///< the held frame's submit(), s
  bool async_inference = true;       ///< the property, read at start
  /// The statistics since start (track_stats.hpp) and the stream time of the next message.
  jointflow::gst::TrackStats stats;
  double next_stats = std::numeric_limits<double>::quiet_NaN();
  bool live_known = false;  ///< upstream has answered the latency query (stats.live)
  /// Each buffer's stream time (the core's one policy), its frame duration from the caps.
  jointflow::FrameClock clock;
  bool warned_time = false;
  int width = 0, height = 0;  ///< the resolution the tracks' coordinates refer to

  /// Drops the held frame unpushed (a flush, a stop); drain() pushes it.
  void dropHeld() {
    if (held) gst_buffer_unref(held);
    held = nullptr;
  }

  void reset() {
    dropHeld();
    if (tracker) tracker->reset();
    frame = 0;
    last_inferred = -1;
    clock.reset();
    next_stats = std::numeric_limits<double>::quiet_NaN();
  }

  // The buffer's time in seconds (FrameClock): the running time of its PTS, which runs on
  // through gaps, DISCONTs and new non-flushing segments; else one frame after the previous buffer.
  double timeOf(GstObject* element, const GstSegment& segment, GstBuffer* buffer) {
    const GstClockTime running =
        gst_segment_to_running_time(&segment, GST_FORMAT_TIME, GST_BUFFER_PTS(buffer));
    const int fallbacks = clock.fallbacks();
    const double t =
        clock.next(GST_CLOCK_TIME_IS_VALID(running) ? static_cast<double>(running) / GST_SECOND
                                                    : std::numeric_limits<double>::quiet_NaN());
    if (clock.fallbacks() > fallbacks && !warned_time) {
      GST_WARNING_OBJECT(element,
                         "a buffer without a PTS, or with one not after the previous buffer's: "
                         "taking it one frame duration (%.4f s) later; the tracker counts frames "
                         "where the stream has no usable time",
                         clock.frameDuration());
      warned_time = true;
    }
    return t;
  }
};

}  // namespace

struct _GstJointFlowTrack {
  GstVideoFilter parent;

  // Properties (track_properties.hpp), guarded by the object lock.
  jointflow::gst::TrackElementSettings* settings;
  GstClockTime earliest_time;  ///< from QoS events: frames running before this are late

  StreamState* stream;  ///< streaming thread only (and start/stop)
};

G_DEFINE_TYPE(GstJointFlowTrack, gst_jointflow_track, GST_TYPE_VIDEO_FILTER);
GST_ELEMENT_REGISTER_DEFINE(jointflowtrack, "jointflowtrack", GST_RANK_NONE,
                            GST_TYPE_JOINTFLOW_TRACK);

static void gst_jointflow_track_set_property(GObject* object, guint prop_id, const GValue* value,
                                             GParamSpec* pspec) {
  jointflow::gst::setSettingProperty(object, *GST_JOINTFLOW_TRACK(object)->settings,
                                     jointflow::gst::trackProperties(), prop_id, value, pspec);
}

static void gst_jointflow_track_get_property(GObject* object, guint prop_id, GValue* value,
                                             GParamSpec* pspec) {
  jointflow::gst::getSettingProperty(object, *GST_JOINTFLOW_TRACK(object)->settings,
                                     jointflow::gst::trackProperties(), prop_id, value, pspec);
}

static gboolean gst_jointflow_track_start(GstBaseTransform* trans) {
  auto* self = GST_JOINTFLOW_TRACK(trans);
  GST_OBJECT_LOCK(self);
  const jointflow::TrackerSettings settings = self->settings->tracker;
  self->stream->async_inference = self->settings->async_inference;
  self->earliest_time = GST_CLOCK_TIME_NONE;
  GST_OBJECT_UNLOCK(self);
  // Each property is range-checked when set; what only the values together can break (the TFF
  // mix's weights summing over 1, tiles with several scales) is checked here, and said as a
  // setting, not a model, at fault.
  try {
    jointflow::validateTrackerSettings(settings);
    jointflow::validateSpatialOptions(settings.spatial);
  } catch (const std::exception& e) {
    GST_ELEMENT_ERROR(self, LIBRARY, SETTINGS, ("Invalid jointflowtrack settings: %s", e.what()),
                      (nullptr));
    return FALSE;
  }
  try {
    self->stream->tracker = std::make_unique<jointflow::Tracker>(settings);
  } catch (const std::exception& e) {
    // jointflow::Error names the file at fault; OpenCV's own exceptions say what it choked on.
    GST_ELEMENT_ERROR(self, RESOURCE, OPEN_READ,
                      ("Could not load the JointFlow models: %s", e.what()),
                      ("spatial-model=\"%s\" model-type=%s tff-model=\"%s\" similarity=%s",
                       settings.spatial.model_path.c_str(), toString(settings.model_type),
                       settings.tff_model.c_str(), toString(settings.similarity)));
    return FALSE;
  }
  self->stream->reset();
  self->stream->stats = jointflow::gst::TrackStats{};
  self->stream->live_known = false;
  {
    const jointflow::Tracker& t = *self->stream->tracker;
    const auto base = [](const std::string& path) {
      return path.substr(path.find_last_of('/') + 1);
    };
    self->stream->stats.model = {toString(t.spatialModel().type()),
                                 base(t.spatialModel().options().model_path),
                                 base(t.tffModelPath()), t.engine(), toString(settings.similarity)};
  }
  // The file says which models folder was used (core/include/jointflow/model_files.hpp).
  GST_INFO_OBJECT(self, "models loaded (%s from %s on %s, similarity %s)",
                  toString(self->stream->tracker->spatialModel().type()),
                  self->stream->tracker->spatialModel().options().model_path.c_str(),
                  self->stream->tracker->engine().c_str(), toString(settings.similarity));
  if (settings.similarity == jointflow::SimilarityType::kAuto && !self->stream->tracker->hasTff())
    GST_INFO_OBJECT(self,
                    "similarity auto: no TFF network fits the %s spatial model (set tff-model "
                    "to one); every frame is matched with oks",
                    toString(self->stream->tracker->spatialModel().type()));
  return TRUE;
}

static gboolean gst_jointflow_track_stop(GstBaseTransform* trans) {
  auto* self = GST_JOINTFLOW_TRACK(trans);
  self->stream->reset();
  self->stream->tracker.reset();
  return TRUE;
}

static gboolean gst_jointflow_track_set_info(GstVideoFilter* filter, GstCaps*, GstVideoInfo* in,
                                             GstCaps*, GstVideoInfo*) {
  auto* self = GST_JOINTFLOW_TRACK(filter);
  StreamState& st = *self->stream;
  GST_DEBUG_OBJECT(self, "format %s %dx%d", gst_video_format_to_string(GST_VIDEO_INFO_FORMAT(in)),
                   GST_VIDEO_INFO_WIDTH(in), GST_VIDEO_INFO_HEIGHT(in));
  if (GST_VIDEO_INFO_FPS_N(in) > 0 && GST_VIDEO_INFO_FPS_D(in) > 0)
    st.clock.setFrameDuration(static_cast<double>(GST_VIDEO_INFO_FPS_D(in)) /
                              GST_VIDEO_INFO_FPS_N(in));
  // Poses and the tracker's maps are in pixels of one resolution: a new one starts afresh. A new
  // format or frame rate at the same size changes nothing the tracks depend on.
  if (st.width != GST_VIDEO_INFO_WIDTH(in) || st.height != GST_VIDEO_INFO_HEIGHT(in)) {
    if (st.width != 0) GST_DEBUG_OBJECT(self, "new resolution: tracks reset");
    st.reset();
    st.width = GST_VIDEO_INFO_WIDTH(in);
    st.height = GST_VIDEO_INFO_HEIGHT(in);
  }
  return TRUE;
}

namespace {
GstFlowReturn drainHeld(GstJointFlowTrack* self);
void postStats(GstJointFlowTrack* self);
}  // namespace

static gboolean gst_jointflow_track_sink_event(GstBaseTransform* trans, GstEvent* event) {
  auto* self = GST_JOINTFLOW_TRACK(trans);
  // A held frame (asynchronous engine) leaves before any serialized event that followed it; a
  // flush drops it.
  if (GST_EVENT_TYPE(event) == GST_EVENT_FLUSH_STOP) {
    self->stream->dropHeld();
  } else if (GST_EVENT_IS_SERIALIZED(event) && self->stream->held) {
    const GstFlowReturn ret = drainHeld(self);
    if (ret != GST_FLOW_OK && ret != GST_FLOW_FLUSHING && ret != GST_FLOW_EOS)
      GST_DEBUG_OBJECT(self, "held frame not pushed: %s", gst_flow_get_name(ret));
  }
  if (GST_EVENT_TYPE(event) == GST_EVENT_EOS) {
    GST_OBJECT_LOCK(self);
    const bool stats = self->settings->stats_interval > 0;
    GST_OBJECT_UNLOCK(self);
    if (stats && self->stream->tracker) postStats(self);  // the stream's totals
  }
  switch (GST_EVENT_TYPE(event)) {
    case GST_EVENT_FLUSH_STOP:
      GST_OBJECT_LOCK(self);
      self->earliest_time = GST_CLOCK_TIME_NONE;
      GST_OBJECT_UNLOCK(self);
      [[fallthrough]];
    case GST_EVENT_STREAM_START:
      // A flushing seek or a new stream: the previous frame is not this one's predecessor. A new
      // segment without a flush (concat, splitmuxsrc) continues the stream and keeps the tracks.
      GST_DEBUG_OBJECT(self, "%s: tracks reset", GST_EVENT_TYPE_NAME(event));
      self->stream->reset();
      break;
    default:
      break;
  }
  return GST_BASE_TRANSFORM_CLASS(gst_jointflow_track_parent_class)->sink_event(trans, event);
}

static gboolean gst_jointflow_track_src_event(GstBaseTransform* trans, GstEvent* event) {
  auto* self = GST_JOINTFLOW_TRACK(trans);
  if (GST_EVENT_TYPE(event) == GST_EVENT_QOS) {
    gdouble proportion;
    GstClockTimeDiff diff;
    GstClockTime timestamp;
    gst_event_parse_qos(event, nullptr, &proportion, &diff, &timestamp);
    GST_OBJECT_LOCK(self);
    // As GstBaseTransform does: a frame is late when it would run before timestamp + diff, and
    // when we are late we leave extra room for catching up.
    if (diff > 0)
      self->earliest_time = timestamp + 2 * diff;
    else
      self->earliest_time =
          static_cast<GstClockTimeDiff>(timestamp) + diff > 0 ? timestamp + diff : 0;
    GST_OBJECT_UNLOCK(self);
  }
  return GST_BASE_TRANSFORM_CLASS(gst_jointflow_track_parent_class)->src_event(trans, event);
}

namespace {

JointFlowPerson toPerson(const jointflow::TrackedPose& tp) {
  JointFlowPerson p{};
  p.track_id = tp.track_id;
  p.tentative = tp.tentative;
  p.age = tp.age;
  p.age_seconds = static_cast<float>(tp.age_seconds);
  p.previous_track_id = tp.previous_track_id;
  p.score = tp.pose.score;
  p.x = tp.pose.box.x;
  p.y = tp.pose.box.y;
  p.width = tp.pose.box.w;
  p.height = tp.pose.box.h;
  for (int j = 0; j < JOINTFLOW_N_KEYPOINTS; ++j)
    p.keypoints[j] = {tp.pose.keypoints[j].x, tp.pose.keypoints[j].y, tp.pose.keypoints[j].score};
  return p;
}

// One ROI per person as DL Streamer attaches them, so that tools reading ROI metas see the people.
void addRegion(GstBuffer* buffer, const JointFlowPerson& p, int width, int height) {
  const auto [x0, y0, x1, y1] = jointflow::gst::boxInFrame(p, width, height);
  GstVideoRegionOfInterestMeta* roi = gst_buffer_add_video_region_of_interest_meta(
      buffer, "person", static_cast<guint>(x0), static_cast<guint>(y0),
      static_cast<guint>(x1 - x0 + 0.5f), static_cast<guint>(y1 - y0 + 0.5f));
  roi->id = static_cast<gint>(p.track_id);
  gst_video_region_of_interest_meta_add_param(
      roi,
      gst_structure_new("detection", "x_min", G_TYPE_DOUBLE, x0 / width, "y_min", G_TYPE_DOUBLE,
                        y0 / height, "x_max", G_TYPE_DOUBLE, x1 / width, "y_max", G_TYPE_DOUBLE,
                        y1 / height, "confidence", G_TYPE_DOUBLE, static_cast<double>(p.score),
                        "label_id", G_TYPE_INT, 0, "label", G_TYPE_STRING, "person", nullptr));
  gst_video_region_of_interest_meta_add_param(
      roi,
      gst_structure_new("object_id", "id", G_TYPE_INT, static_cast<gint>(p.track_id), nullptr));
}

}  // namespace

namespace {

// Whether the networks run on this frame: every inference-interval-th frame, unless it is
// already late (QoS) and skip-late-frames is on.
bool shouldInfer(GstJointFlowTrack* self, GstBaseTransform* trans, GstBuffer* buffer) {
  StreamState& st = *self->stream;
  GST_OBJECT_LOCK(self);
  const std::int64_t interval = self->settings->inference_interval;
  const bool skip_late = self->settings->skip_late_frames;
  const GstClockTime earliest = self->earliest_time;
  GST_OBJECT_UNLOCK(self);

  bool infer = st.last_inferred < 0 || st.frame - st.last_inferred >= interval;
  if (infer && st.last_inferred >= 0 && skip_late && GST_CLOCK_TIME_IS_VALID(earliest)) {
    const GstClockTime running =
        gst_segment_to_running_time(&trans->segment, GST_FORMAT_TIME, GST_BUFFER_PTS(buffer));
    if (GST_CLOCK_TIME_IS_VALID(running) && running <= earliest) {
      GST_LOG_OBJECT(self, "frame late by %" GST_STIME_FORMAT ": poses predicted",
                     GST_STIME_ARGS(GST_CLOCK_DIFF(running, earliest)));
      infer = false;
    }
  }
  return infer;
}

// Maps the frame and hands it to the tracker: submit() (the network starts; on an asynchronous
// engine it runs on after this returns). The pixels are mapped for reading only: the video is
// not modified, and a buffer whose memory is shared is not copied.
bool submitFrame(GstJointFlowTrack* self, GstBuffer* buffer, double time) {
  auto* filter = GST_VIDEO_FILTER(self);
  StreamState& st = *self->stream;
  GstVideoFrame frame;
  if (!gst_video_frame_map(&frame, &filter->in_info, buffer, GST_MAP_READ)) {
    GST_ELEMENT_ERROR(self, STREAM, FAILED, ("Could not map the video frame for reading"),
                      (nullptr));
    return false;
  }
  try {
    jointflow::PixelOrder order = jointflow::PixelOrder::kBGR;
    const cv::Mat image = st.converter.convert(frame, &order);
    st.tracker->submit(image, order, time);
  } catch (const std::exception& e) {
    gst_video_frame_unmap(&frame);
    GST_ELEMENT_ERROR(self, STREAM, FAILED, ("Pose tracking failed: %s", e.what()), (nullptr));
    return false;
  }
  gst_video_frame_unmap(&frame);
  st.last_inferred = st.frame;
  return true;
}

// The tracked poses of the oldest submitted frame (its TFF and association run here).
bool collectPoses(GstJointFlowTrack* self, std::vector<jointflow::TrackedPose>* poses) {
  StreamState& st = *self->stream;
  try {
    *poses = st.tracker->collect();
  } catch (const std::exception& e) {
    GST_ELEMENT_ERROR(self, STREAM, FAILED, ("Pose tracking failed: %s", e.what()), (nullptr));
    return false;
  }
  return true;
}

void attachPoses(GstJointFlowTrack* self, GstBuffer* buffer,
                 const std::vector<jointflow::TrackedPose>& poses, bool predicted) {
  auto* filter = GST_VIDEO_FILTER(self);
  const int width = GST_VIDEO_INFO_WIDTH(&filter->in_info);
  const int height = GST_VIDEO_INFO_HEIGHT(&filter->in_info);
  GstJointFlowMeta* meta = gst_buffer_add_jointflow_meta(buffer, width, height);
  meta->predicted = predicted;
  for (const auto& tp : poses) {
    const JointFlowPerson person = toPerson(tp);
    gst_jointflow_meta_add_person(meta, &person);
    addRegion(buffer, person, width, height);
  }
}

double secondsSince(std::int64_t monotonic_us) {
  return static_cast<double>(g_get_monotonic_time() - monotonic_us) / G_USEC_PER_SEC;
}

// Whether upstream is live, asked once per start: the lag is measured only there, where a
// buffer's running time is when its source captured it, on the pipeline clock.
void checkLive(GstJointFlowTrack* self) {
  StreamState& st = *self->stream;
  if (st.live_known) return;
  st.live_known = true;
  GstQuery* query = gst_query_new_latency();
  if (gst_pad_peer_query(GST_BASE_TRANSFORM_SINK_PAD(self), query)) {
    gboolean live = FALSE;
    gst_query_parse_latency(query, &live, nullptr, nullptr);
    st.stats.live = live;
  }
  gst_query_unref(query);
}

// A frame leaves with its poses: the time it spent in the element and, live, its lag
// (frame_lag.hpp).
void recordExit(GstJointFlowTrack* self, GstBuffer* buffer, std::int64_t arrival_us) {
  StreamState& st = *self->stream;
  st.stats.element.observe(secondsSince(arrival_us));
  if (const auto capture_lag = jointflow::gst::captureLagSeconds(buffer))
    st.stats.capture_lag.observe(*capture_lag);
  if (!st.stats.live) return;
  if (const auto lag = jointflow::gst::frameLagSeconds(GST_ELEMENT(self),
                                                       GST_BASE_TRANSFORM(self)->segment, buffer))
    st.stats.lag.observe(*lag);
}

void postStats(GstJointFlowTrack* self) {
  gst_element_post_message(GST_ELEMENT(self),
                           gst_message_new_element(GST_OBJECT(self), jointflow::gst::statsStructure(
                                                                         self->stream->stats)));
}

// A frame went in: the counts, and the statistics message once stats-interval of stream time has
// passed since the last one (the first one interval after the first frame).
void countFrame(GstJointFlowTrack* self, double time, bool inferred) {
  StreamState& st = *self->stream;
  st.stats.frames++;
  (inferred ? st.stats.inferred : st.stats.predicted)++;
  st.stats.stream_time = time;
  st.stats.tracks = st.tracker->trackCounts();
  GST_OBJECT_LOCK(self);
  const double interval = self->settings->stats_interval;
  GST_OBJECT_UNLOCK(self);
  if (!(interval > 0)) {
    st.next_stats = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  if (std::isnan(st.next_stats)) {
    st.next_stats = time + interval;
  } else if (time >= st.next_stats) {
    postStats(self);
    st.next_stats += interval;
    if (st.next_stats <= time) st.next_stats = time + interval;  // after a gap
  }
}

// Pushes the held frame (asynchronous engine) with its poses; nothing to do when none is held.
GstFlowReturn drainHeld(GstJointFlowTrack* self) {
  StreamState& st = *self->stream;
  if (!st.held) return GST_FLOW_OK;
  GstBuffer* buffer = st.held;
  st.held = nullptr;
  std::vector<jointflow::TrackedPose> poses;
  const std::int64_t collect_start = g_get_monotonic_time();
  if (!collectPoses(self, &poses)) {
    gst_buffer_unref(buffer);
    return GST_FLOW_ERROR;
  }
  st.stats.inference.observe(st.held_submit_s + secondsSince(collect_start));
  buffer = gst_buffer_make_writable(buffer);
  attachPoses(self, buffer, poses, false);
  recordExit(self, buffer, st.held_arrival_us);
  return gst_pad_push(GST_BASE_TRANSFORM_SRC_PAD(self), buffer);
}

bool pipelined(GstJointFlowTrack* self) {
  return self->stream->async_inference && self->stream->tracker &&
         self->stream->tracker->asynchronous();
}

}  // namespace

// cv::dnn (and OpenVINO with async-inference=false): one frame in, the same frame out with its
// poses.
static GstFlowReturn gst_jointflow_track_transform_ip(GstBaseTransform* trans, GstBuffer* buffer) {
  auto* self = GST_JOINTFLOW_TRACK(trans);
  auto* filter = GST_VIDEO_FILTER(trans);
  StreamState& st = *self->stream;
  if (!filter->negotiated || !st.tracker) {
    GST_ELEMENT_ERROR(self, CORE, NEGOTIATION, (nullptr), ("no format negotiated before data"));
    return GST_FLOW_NOT_NEGOTIATED;
  }
  // A DISCONT (a buffer dropped upstream: a leaky queue, packet loss) is a gap in time that the
  // tracks live through, not a new stream.
  const std::int64_t arrival = g_get_monotonic_time();
  checkLive(self);
  const double time = st.timeOf(GST_OBJECT(self), trans->segment, buffer);
  const bool infer = shouldInfer(self, trans, buffer);
  std::vector<jointflow::TrackedPose> poses;
  if (infer) {
    if (!submitFrame(self, buffer, time) || !collectPoses(self, &poses)) return GST_FLOW_ERROR;
    st.stats.inference.observe(secondsSince(arrival));
  } else {
    poses = st.tracker->predict(time);
  }
  st.frame++;
  attachPoses(self, buffer, poses, !infer);
  recordExit(self, buffer, arrival);  // GstBaseTransform pushes it as this returns
  countFrame(self, time, infer);
  return GST_FLOW_OK;
}

// An asynchronous engine (OpenVINO): frame N is submitted (its run queued behind N-1's), then
// frame N-1 (held) is collected and pushed while N's spatial network runs, and N is held in turn.
// So N's network overlaps the reading and decoding of N-1's outputs, N-1's TFF and association,
// and whatever upstream does to bring frame N+1 (decoding, conversion) in this thread. The price is
// one frame of latency, which the latency query reports. Predicted frames and serialized events
// drain the held frame first, so buffers and events leave in the order they came.
static GstFlowReturn gst_jointflow_track_generate_output(GstBaseTransform* trans,
                                                         GstBuffer** outbuf) {
  auto* self = GST_JOINTFLOW_TRACK(trans);
  if (!pipelined(self))
    return GST_BASE_TRANSFORM_CLASS(gst_jointflow_track_parent_class)
        ->generate_output(trans, outbuf);
  *outbuf = nullptr;
  GstBuffer* buffer = trans->queued_buf;
  trans->queued_buf = nullptr;
  if (!buffer) return GST_FLOW_OK;
  StreamState& st = *self->stream;
  if (!GST_VIDEO_FILTER(trans)->negotiated) {
    gst_buffer_unref(buffer);
    GST_ELEMENT_ERROR(self, CORE, NEGOTIATION, (nullptr), ("no format negotiated before data"));
    return GST_FLOW_NOT_NEGOTIATED;
  }
  // As in transform_ip, a DISCONT is a gap in time, not a new stream.
  const std::int64_t arrival = g_get_monotonic_time();
  checkLive(self);
  const double time = st.timeOf(GST_OBJECT(self), trans->segment, buffer);
  if (!shouldInfer(self, trans, buffer)) {
    const GstFlowReturn ret = drainHeld(self);
    if (ret != GST_FLOW_OK) {
      gst_buffer_unref(buffer);
      return ret;
    }
    st.frame++;
    const auto poses = st.tracker->predict(time);
    buffer = gst_buffer_make_writable(buffer);
    attachPoses(self, buffer, poses, true);
    recordExit(self, buffer, arrival);
    countFrame(self, time, false);
    *outbuf = buffer;
    return GST_FLOW_OK;
  }
  if (!submitFrame(self, buffer, time)) {
    gst_buffer_unref(buffer);
    return GST_FLOW_ERROR;
  }
  const double submit_s = secondsSince(arrival);
  GstBuffer* previous = st.held;
  const std::int64_t previous_arrival = st.held_arrival_us;
  const double previous_submit_s = st.held_submit_s;
  st.held = buffer;
  st.held_arrival_us = arrival;
  st.held_submit_s = submit_s;
  st.frame++;
  countFrame(self, time, true);
  if (!previous) return GST_FLOW_OK;
  std::vector<jointflow::TrackedPose> poses;
  const std::int64_t collect_start = g_get_monotonic_time();
  if (!collectPoses(self, &poses)) {
    gst_buffer_unref(previous);
    return GST_FLOW_ERROR;
  }
  st.stats.inference.observe(previous_submit_s + secondsSince(collect_start));
  previous = gst_buffer_make_writable(previous);
  attachPoses(self, previous, poses, false);
  recordExit(self, previous, previous_arrival);
  *outbuf = previous;
  return GST_FLOW_OK;
}

// One frame more of latency where a frame is held (asynchronous engine).
static gboolean gst_jointflow_track_query(GstBaseTransform* trans, GstPadDirection direction,
                                          GstQuery* query) {
  auto* self = GST_JOINTFLOW_TRACK(trans);
  const gboolean ok =
      GST_BASE_TRANSFORM_CLASS(gst_jointflow_track_parent_class)->query(trans, direction, query);
  if (ok && direction == GST_PAD_SRC && GST_QUERY_TYPE(query) == GST_QUERY_LATENCY &&
      pipelined(self)) {
    const GstVideoInfo* info = &GST_VIDEO_FILTER(trans)->in_info;
    if (GST_VIDEO_INFO_FPS_N(info) > 0) {
      gboolean live;
      GstClockTime min, max;
      gst_query_parse_latency(query, &live, &min, &max);
      const GstClockTime frame = gst_util_uint64_scale_int(GST_SECOND, GST_VIDEO_INFO_FPS_D(info),
                                                           GST_VIDEO_INFO_FPS_N(info));
      gst_query_set_latency(query, live, min + frame,
                            GST_CLOCK_TIME_IS_VALID(max) ? max + frame : max);
    }
  }
  return ok;
}

static void gst_jointflow_track_finalize(GObject* object) {
  auto* self = GST_JOINTFLOW_TRACK(object);
  delete self->stream;
  delete self->settings;
  G_OBJECT_CLASS(gst_jointflow_track_parent_class)->finalize(object);
}

static void gst_jointflow_track_class_init(GstJointFlowTrackClass* klass) {
  auto* gobject_class = G_OBJECT_CLASS(klass);
  auto* element_class = GST_ELEMENT_CLASS(klass);
  auto* trans_class = GST_BASE_TRANSFORM_CLASS(klass);
  auto* filter_class = GST_VIDEO_FILTER_CLASS(klass);

  GST_DEBUG_CATEGORY_INIT(gst_jointflow_track_debug, "jointflowtrack", 0,
                          "JointFlow multi-person pose tracking");

  gobject_class->set_property = gst_jointflow_track_set_property;
  gobject_class->get_property = gst_jointflow_track_get_property;
  gobject_class->finalize = gst_jointflow_track_finalize;

  // One property per row of the table; tracker settings are read at start (READY -> PAUSED),
  // the element's own rows apply at once.
  jointflow::gst::installSettingProperties(gobject_class, jointflow::gst::trackProperties());

  gst_element_class_set_static_metadata(
      element_class, "JointFlow pose tracker", "Analyzer/Video",
      "Estimates and tracks the 2D poses of every person (JointFlow, BMVC 2018); attaches "
      "GstJointFlowMeta and person GstVideoRegionOfInterestMeta",
      "JointFlow developers");
  jointflow::gst::addVideoPadTemplates(element_class);

  for (GType t : {gst_jointflow_model_type_get_type(), gst_jointflow_similarity_get_type(),
                  gst_jointflow_matcher_get_type(), gst_jointflow_appearance_get_type(),
                  gst_jointflow_backend_get_type(), gst_jointflow_target_get_type()})
    gst_type_mark_as_plugin_api(t, static_cast<GstPluginAPIFlags>(0));

  trans_class->start = gst_jointflow_track_start;
  trans_class->stop = gst_jointflow_track_stop;
  trans_class->sink_event = gst_jointflow_track_sink_event;
  trans_class->src_event = gst_jointflow_track_src_event;
  trans_class->transform_ip = gst_jointflow_track_transform_ip;
  trans_class->generate_output = gst_jointflow_track_generate_output;
  trans_class->query = gst_jointflow_track_query;
  filter_class->set_info = gst_jointflow_track_set_info;
}

static void gst_jointflow_track_init(GstJointFlowTrack* self) {
  self->settings = new jointflow::gst::TrackElementSettings();
  self->earliest_time = GST_CLOCK_TIME_NONE;
  self->stream = new StreamState();
  // GstVideoFilter turns QoS on, which would drop late frames before they reach us; our own
  // policy (skip-late-frames) passes them on with predicted poses. qos=true still drops them.
  gst_base_transform_set_qos_enabled(GST_BASE_TRANSFORM(self), FALSE);
}
