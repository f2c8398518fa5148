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
 * The tracks start afresh after a flush (seek), a discontinuity, a new segment or stream, and a
 * change of resolution; track ids keep counting up, so an id is never given to two people.
 *
 * With inference-interval=N the networks run on every Nth frame; on the frames in between every
 * track is moved on with its own velocity (GstJointFlowMeta.predicted is TRUE), so the poses
 * neither stand still nor flicker. When downstream reports lateness through QoS events (a live
 * pipeline whose sink syncs to the clock) and skip-late-frames is TRUE, frames that are already
 * late are predicted the same way instead of inferred, so the element catches up and latency
 * does not grow. To bound latency at a live source in any case, put a leaky queue in front:
 * `queue leaky=downstream max-size-buffers=1`.
 *
 * Properties that configure the models and the tracker are read when the element starts (goes
 * from READY to PAUSED). A model that is missing or not what was expected makes that state change
 * fail with an error message naming the file.
 *
 * ## Example launch line
 * |[
 * gst-launch-1.0 filesrc location=vtest.avi ! decodebin ! videoconvert !
 *     jointflowtrack similarity=oks ! jointflowoverlay ! videoconvert ! autovideosink
 * ]|
 */
#include "gstjointflowtrack.h"

#include <gst/video/gstvideometa.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "frame_converter.hpp"
#include "jointflow/error.hpp"
#include "jointflow/tracker.hpp"
#include "jointflowmeta.h"
#include "pose_predictor.hpp"
#include "video_formats.hpp"

GST_DEBUG_CATEGORY_STATIC(gst_jointflow_track_debug);
#define GST_CAT_DEFAULT gst_jointflow_track_debug

namespace {

enum {
  PROP_0,
  PROP_SPATIAL_MODEL,
  PROP_MODEL_TYPE,
  PROP_TFF_MODEL,
  PROP_SIMILARITY,
  PROP_MATCHER,
  PROP_INPUT_SIZE,
  PROP_SCALES,
  PROP_MAX_PERSONS,
  PROP_PERSON_THRESHOLD,
  PROP_KEYPOINT_THRESHOLD,
  PROP_NMS_THRESHOLD,
  PROP_TAU_DELTA,
  PROP_MIN_TRACK_LENGTH,
  PROP_COAST_FRAMES,
  PROP_SMOOTHING,
  PROP_INFERENCE_INTERVAL,
  PROP_SKIP_LATE_FRAMES,
  PROP_BACKEND,
  PROP_TARGET,
  PROP_NUM_THREADS,
};

// The tracker's own defaults (core/include/jointflow/tracker.hpp) are the element's defaults.
const jointflow::TrackerSettings kDefaults{};
constexpr guint DEFAULT_INFERENCE_INTERVAL = 1;
constexpr gboolean DEFAULT_SKIP_LATE_FRAMES = TRUE;

// The enumerations of the string settings, with the core's spellings as nicks.
GType registerEnum(const char* name, const GEnumValue* values) {
  GType type = g_type_from_name(name);
  return type ? type : g_enum_register_static(name, values);
}

#define JOINTFLOW_ENUM_TYPE(fn, name, ...)                                     \
  GType fn() {                                                                 \
    static gsize type = 0;                                                     \
    if (g_once_init_enter(&type)) {                                            \
      static const GEnumValue values[] = {__VA_ARGS__, {0, nullptr, nullptr}}; \
      g_once_init_leave(&type, registerEnum(name, values));                    \
    }                                                                          \
    return static_cast<GType>(type);                                           \
  }

JOINTFLOW_ENUM_TYPE(modelTypeEnum, "GstJointFlowModelType",
                    {0, "Chosen from the ONNX file's output names", "auto"},
                    {1, "MoveNet MultiPose", "movenet"}, {2, "PoseNet MobileNetV1", "posenet"},
                    {3, "Belief maps + Part Affinity Fields (OpenPose)", "openpose"})
JOINTFLOW_ENUM_TYPE(similarityEnum, "GstJointFlowSimilarity",
                    {0, "Temporal Flow Fields (the paper's method; needs tff-model)", "tff"},
                    {1, "Object keypoint similarity to the track's last pose", "oks"},
                    {2, "Box intersection over union", "iou"},
                    {3, "PCKh of the track's last pose", "pckh"},
                    {4, "Keypoints moved by optical flow (Farneback)", "flow"})
JOINTFLOW_ENUM_TYPE(matcherEnum, "GstJointFlowMatcher",
                    {0, "Greedy, highest potential first (the paper)", "greedy"},
                    {1, "Optimal bipartite matching (Hungarian)", "optimal"})
JOINTFLOW_ENUM_TYPE(backendEnum, "GstJointFlowBackend", {0, "OpenCV's default", "default"},
                    {1, "OpenCV's own", "opencv"}, {2, "CUDA (OpenCV built with CUDA)", "cuda"},
                    {3, "OpenVINO inference engine", "openvino"})
JOINTFLOW_ENUM_TYPE(targetEnum, "GstJointFlowTarget", {0, "CPU", "cpu"}, {1, "OpenCL", "opencl"},
                    {2, "OpenCL, half precision", "opencl_fp16"}, {3, "CUDA", "cuda"},
                    {4, "CUDA, half precision", "cuda_fp16"})

int enumValue(GType type, const std::string& nick) {
  auto* klass = static_cast<GEnumClass*>(g_type_class_ref(type));
  const GEnumValue* v = g_enum_get_value_by_nick(klass, nick.c_str());
  const int value = v ? v->value : 0;
  g_type_class_unref(klass);
  return value;
}

std::string enumNick(GType type, int value) {
  auto* klass = static_cast<GEnumClass*>(g_type_class_ref(type));
  const GEnumValue* v = g_enum_get_value(klass, value);
  std::string nick = v ? v->value_nick : "";
  g_type_class_unref(klass);
  return nick;
}

std::string scalesToString(const std::vector<float>& scales) {
  std::ostringstream out;
  for (size_t i = 0; i < scales.size(); ++i) out << (i ? "," : "") << scales[i];
  return out.str();
}

// "0.5,1,1.5": each scale in (0, 4]. Throws jointflow::Error naming what is wrong.
std::vector<float> parseScales(const std::string& text) {
  std::vector<float> scales;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    size_t used = 0;
    float s = 0.f;
    try {
      s = std::stof(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || item.find_first_not_of(" \t", used) != std::string::npos || !(s > 0.f) ||
        s > 4.f)
      throw jointflow::Error("scales: \"" + item + "\" in \"" + text +
                             "\" is not a scale in (0, 4]; expected e.g. \"1\" or \"0.5,1,1.5\"");
    scales.push_back(s);
  }
  if (scales.empty())
    throw jointflow::Error("scales: empty; expected a comma-separated list such as \"1\"");
  return scales;
}

// What the streaming thread owns: the tracker and the buffers reused from frame to frame.
struct StreamState {
  std::unique_ptr<jointflow::Tracker> tracker;
  jointflow::gst::FrameConverter converter;
  jointflow::gst::PosePredictor predictor;
  std::int64_t frame = 0;           ///< frames since the last reset
  std::int64_t last_inferred = -1;  ///< frame of the last inference since the reset, -1 = none

  void reset() {
    if (tracker) tracker->reset();
    predictor.reset();
    frame = 0;
    last_inferred = -1;
  }
};

}  // namespace

struct _GstJointFlowTrack {
  GstVideoFilter parent;

  // Properties, guarded by the object lock.
  jointflow::TrackerSettings* settings;
  guint inference_interval;
  gboolean skip_late_frames;
  GstClockTime earliest_time;  ///< from QoS events: frames running before this are late

  StreamState* stream;  ///< streaming thread only (and start/stop)
};

G_DEFINE_TYPE(GstJointFlowTrack, gst_jointflow_track, GST_TYPE_VIDEO_FILTER);
GST_ELEMENT_REGISTER_DEFINE(jointflowtrack, "jointflowtrack", GST_RANK_NONE,
                            GST_TYPE_JOINTFLOW_TRACK);

static void warnRefused(GstJointFlowTrack* self, const char* property, const std::string& why) {
  GST_WARNING_OBJECT(self, "%s refused: %s", property, why.c_str());
  g_warning("jointflowtrack: %s refused, keeping the previous value: %s", property, why.c_str());
}

static void gst_jointflow_track_set_property(GObject* object, guint prop_id, const GValue* value,
                                             GParamSpec* pspec) {
  auto* self = GST_JOINTFLOW_TRACK(object);
  // Parse outside the lock: the parsers may throw.
  jointflow::InputSize input_size;
  std::vector<float> scales;
  try {
    if (prop_id == PROP_INPUT_SIZE) {
      const char* text = g_value_get_string(value);
      input_size = jointflow::InputSize::parse(text ? text : "");
    } else if (prop_id == PROP_SCALES) {
      const char* text = g_value_get_string(value);
      scales = parseScales(text ? text : "");
    }
  } catch (const jointflow::Error& e) {
    warnRefused(self, pspec->name, e.what());
    return;
  }

  GST_OBJECT_LOCK(self);
  jointflow::TrackerSettings& s = *self->settings;
  auto string = [&] {
    const char* v = g_value_get_string(value);
    return std::string(v ? v : "");
  };
  switch (prop_id) {
    case PROP_SPATIAL_MODEL:
      s.spatial.model_path = string();
      break;
    case PROP_MODEL_TYPE:
      s.model_type = enumNick(modelTypeEnum(), g_value_get_enum(value));
      break;
    case PROP_TFF_MODEL:
      s.tff_model = string();
      break;
    case PROP_SIMILARITY:
      s.similarity = enumNick(similarityEnum(), g_value_get_enum(value));
      break;
    case PROP_MATCHER:
      s.matcher = enumNick(matcherEnum(), g_value_get_enum(value));
      break;
    case PROP_INPUT_SIZE:
      s.spatial.input_size = input_size;
      break;
    case PROP_SCALES:
      s.spatial.scales = scales;
      break;
    case PROP_MAX_PERSONS:
      s.max_persons = s.spatial.max_persons = g_value_get_int(value);
      break;
    case PROP_PERSON_THRESHOLD:
      s.spatial.person_threshold = g_value_get_float(value);
      break;
    case PROP_KEYPOINT_THRESHOLD:
      s.spatial.keypoint_threshold = g_value_get_float(value);
      break;
    case PROP_NMS_THRESHOLD:
      s.spatial.nms_threshold = g_value_get_float(value);
      break;
    case PROP_TAU_DELTA:
      s.tau_delta = g_value_get_float(value);
      break;
    case PROP_MIN_TRACK_LENGTH:
      s.min_track_length = g_value_get_int(value);
      break;
    case PROP_COAST_FRAMES:
      s.coast_frames = g_value_get_int(value);
      break;
    case PROP_SMOOTHING:
      s.smoothing = g_value_get_boolean(value);
      break;
    case PROP_INFERENCE_INTERVAL:
      self->inference_interval = g_value_get_uint(value);
      break;
    case PROP_SKIP_LATE_FRAMES:
      self->skip_late_frames = g_value_get_boolean(value);
      break;
    case PROP_BACKEND:
      s.spatial.dnn.backend = enumNick(backendEnum(), g_value_get_enum(value));
      break;
    case PROP_TARGET:
      s.spatial.dnn.target = enumNick(targetEnum(), g_value_get_enum(value));
      break;
    case PROP_NUM_THREADS:
      s.spatial.dnn.num_threads = g_value_get_int(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, prop_id, pspec);
      break;
  }
  GST_OBJECT_UNLOCK(self);
}

static void gst_jointflow_track_get_property(GObject* object, guint prop_id, GValue* value,
                                             GParamSpec* pspec) {
  auto* self = GST_JOINTFLOW_TRACK(object);
  GST_OBJECT_LOCK(self);
  const jointflow::TrackerSettings& s = *self->settings;
  switch (prop_id) {
    case PROP_SPATIAL_MODEL:
      g_value_set_string(value, s.spatial.model_path.c_str());
      break;
    case PROP_MODEL_TYPE:
      g_value_set_enum(value, enumValue(modelTypeEnum(), s.model_type));
      break;
    case PROP_TFF_MODEL:
      g_value_set_string(value, s.tff_model.c_str());
      break;
    case PROP_SIMILARITY:
      g_value_set_enum(value, enumValue(similarityEnum(), s.similarity));
      break;
    case PROP_MATCHER:
      g_value_set_enum(value, enumValue(matcherEnum(), s.matcher));
      break;
    case PROP_INPUT_SIZE:
      g_value_set_string(value, s.spatial.input_size.toString().c_str());
      break;
    case PROP_SCALES:
      g_value_set_string(value, scalesToString(s.spatial.scales).c_str());
      break;
    case PROP_MAX_PERSONS:
      g_value_set_int(value, s.max_persons);
      break;
    case PROP_PERSON_THRESHOLD:
      g_value_set_float(value, s.spatial.person_threshold);
      break;
    case PROP_KEYPOINT_THRESHOLD:
      g_value_set_float(value, s.spatial.keypoint_threshold);
      break;
    case PROP_NMS_THRESHOLD:
      g_value_set_float(value, s.spatial.nms_threshold);
      break;
    case PROP_TAU_DELTA:
      g_value_set_float(value, s.tau_delta);
      break;
    case PROP_MIN_TRACK_LENGTH:
      g_value_set_int(value, s.min_track_length);
      break;
    case PROP_COAST_FRAMES:
      g_value_set_int(value, s.coast_frames);
      break;
    case PROP_SMOOTHING:
      g_value_set_boolean(value, s.smoothing);
      break;
    case PROP_INFERENCE_INTERVAL:
      g_value_set_uint(value, self->inference_interval);
      break;
    case PROP_SKIP_LATE_FRAMES:
      g_value_set_boolean(value, self->skip_late_frames);
      break;
    case PROP_BACKEND:
      g_value_set_enum(value, enumValue(backendEnum(), s.spatial.dnn.backend));
      break;
    case PROP_TARGET:
      g_value_set_enum(value, enumValue(targetEnum(), s.spatial.dnn.target));
      break;
    case PROP_NUM_THREADS:
      g_value_set_int(value, s.spatial.dnn.num_threads);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, prop_id, pspec);
      break;
  }
  GST_OBJECT_UNLOCK(self);
}

static gboolean gst_jointflow_track_start(GstBaseTransform* trans) {
  auto* self = GST_JOINTFLOW_TRACK(trans);
  GST_OBJECT_LOCK(self);
  const jointflow::TrackerSettings settings = *self->settings;
  self->earliest_time = GST_CLOCK_TIME_NONE;
  GST_OBJECT_UNLOCK(self);
  try {
    self->stream->tracker = std::make_unique<jointflow::Tracker>(settings);
  } catch (const std::exception& e) {
    // jointflow::Error names the file at fault; OpenCV's own exceptions say what it choked on.
    GST_ELEMENT_ERROR(self, RESOURCE, OPEN_READ,
                      ("Could not load the JointFlow models: %s", e.what()),
                      ("spatial-model=\"%s\" model-type=%s tff-model=\"%s\" similarity=%s",
                       settings.spatial.model_path.c_str(), settings.model_type.c_str(),
                       settings.tff_model.c_str(), settings.similarity.c_str()));
    return FALSE;
  }
  self->stream->reset();
  GST_INFO_OBJECT(self, "models loaded (%s, similarity %s)", settings.model_type.c_str(),
                  settings.similarity.c_str());
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
  // One-Euro smoothing filters in time: it needs the rate at which the tracker sees frames, the
  // stream's frame rate (which only the caps tell) divided by the inference interval. The
  // tracker is rebuilt for it (once per stream, and only with smoothing on).
  GST_OBJECT_LOCK(self);
  const double interval = self->inference_interval;
  GST_OBJECT_UNLOCK(self);
  const double fps = GST_VIDEO_INFO_FPS_D(in) > 0 ? static_cast<double>(GST_VIDEO_INFO_FPS_N(in)) /
                                                        GST_VIDEO_INFO_FPS_D(in) / interval
                                                  : 0.0;
  if (st.tracker && st.tracker->settings().smoothing && fps > 0 &&
      std::abs(fps - st.tracker->settings().frame_rate) > 1e-3) {
    jointflow::TrackerSettings settings = st.tracker->settings();
    settings.frame_rate = static_cast<float>(fps);
    try {
      st.tracker = std::make_unique<jointflow::Tracker>(settings);
    } catch (const std::exception& e) {
      GST_ELEMENT_ERROR(self, RESOURCE, OPEN_READ,
                        ("Could not load the JointFlow models: %s", e.what()), (nullptr));
      return FALSE;
    }
  }
  // Poses and the tracker's maps are in pixels of one resolution: a new one starts afresh.
  st.reset();
  return TRUE;
}

static gboolean gst_jointflow_track_sink_event(GstBaseTransform* trans, GstEvent* event) {
  auto* self = GST_JOINTFLOW_TRACK(trans);
  switch (GST_EVENT_TYPE(event)) {
    case GST_EVENT_FLUSH_STOP:
      GST_OBJECT_LOCK(self);
      self->earliest_time = GST_CLOCK_TIME_NONE;
      GST_OBJECT_UNLOCK(self);
      [[fallthrough]];
    case GST_EVENT_SEGMENT:
    case GST_EVENT_STREAM_START:
      // A seek, a new segment or a new stream: the previous frame is not this one's predecessor.
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
  const float x0 = std::clamp(p.x, 0.f, static_cast<float>(width));
  const float y0 = std::clamp(p.y, 0.f, static_cast<float>(height));
  const float x1 = std::clamp(p.x + p.width, 0.f, static_cast<float>(width));
  const float y1 = std::clamp(p.y + p.height, 0.f, static_cast<float>(height));
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

// Works on the buffer rather than a mapped frame so that the pixels are mapped for reading only:
// the video is not modified, and a buffer whose memory is shared is not copied.
static GstFlowReturn gst_jointflow_track_transform_ip(GstBaseTransform* trans, GstBuffer* buffer) {
  auto* self = GST_JOINTFLOW_TRACK(trans);
  auto* filter = GST_VIDEO_FILTER(trans);
  StreamState& st = *self->stream;
  if (!filter->negotiated || !st.tracker) {
    GST_ELEMENT_ERROR(self, CORE, NEGOTIATION, (nullptr), ("no format negotiated before data"));
    return GST_FLOW_NOT_NEGOTIATED;
  }
  if (GST_BUFFER_FLAG_IS_SET(buffer, GST_BUFFER_FLAG_DISCONT) && st.frame > 0) {
    GST_DEBUG_OBJECT(self, "discontinuity: tracks reset");
    st.reset();
  }

  GST_OBJECT_LOCK(self);
  const std::int64_t interval = self->inference_interval;
  const gboolean skip_late = self->skip_late_frames;
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

  std::vector<jointflow::TrackedPose> poses;
  if (infer) {
    GstVideoFrame frame;
    if (!gst_video_frame_map(&frame, &filter->in_info, buffer, GST_MAP_READ)) {
      GST_ELEMENT_ERROR(self, STREAM, FAILED, ("Could not map the video frame for reading"),
                        (nullptr));
      return GST_FLOW_ERROR;
    }
    try {
      jointflow::PixelOrder order = jointflow::PixelOrder::kBGR;
      const cv::Mat image = st.converter.convert(frame, &order);
      poses = st.tracker->process(image, order);
    } catch (const std::exception& e) {
      gst_video_frame_unmap(&frame);
      GST_ELEMENT_ERROR(self, STREAM, FAILED, ("Pose tracking failed: %s", e.what()), (nullptr));
      return GST_FLOW_ERROR;
    }
    gst_video_frame_unmap(&frame);
    st.predictor.observe(poses, st.frame);
    st.last_inferred = st.frame;
  } else {
    poses = st.predictor.predict(st.frame);
  }
  st.frame++;

  const int width = GST_VIDEO_INFO_WIDTH(&filter->in_info);
  const int height = GST_VIDEO_INFO_HEIGHT(&filter->in_info);
  GstJointFlowMeta* meta = gst_buffer_add_jointflow_meta(buffer, width, height);
  meta->predicted = !infer;
  for (const auto& tp : poses) {
    const JointFlowPerson person = toPerson(tp);
    gst_jointflow_meta_add_person(meta, &person);
    addRegion(buffer, person, width, height);
  }
  return GST_FLOW_OK;
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

  // Read at start (READY -> PAUSED); changes while running take effect at the next start.
  const auto at_start = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
                                                 GST_PARAM_MUTABLE_READY);
  const auto live = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
                                             GST_PARAM_MUTABLE_PLAYING);
  const jointflow::TrackerSettings& d = kDefaults;
  auto install = [&](guint id, GParamSpec* spec) {
    g_object_class_install_property(gobject_class, id, spec);
  };
  install(PROP_SPATIAL_MODEL,
          g_param_spec_string("spatial-model", "Spatial model",
                              "ONNX file of the pose estimation network; empty = the shipped "
                              "model of model-type (MoveNet MultiPose for auto) in the models "
                              "folder ($JOINTFLOW_MODELS_DIR overrides it)",
                              "", at_start));
  install(PROP_MODEL_TYPE,
          g_param_spec_enum("model-type", "Model type", "Decoder of the spatial model",
                            modelTypeEnum(), enumValue(modelTypeEnum(), d.model_type), at_start));
  install(PROP_TFF_MODEL,
          g_param_spec_string("tff-model", "TFF model",
                              "ONNX file of the Temporal Flow Field network (similarity=tff); "
                              "empty = the shipped one",
                              "", at_start));
  install(PROP_SIMILARITY,
          g_param_spec_enum("similarity", "Similarity",
                            "How a new pose is compared with a track's last pose", similarityEnum(),
                            enumValue(similarityEnum(), d.similarity), at_start));
  install(PROP_MATCHER,
          g_param_spec_enum("matcher", "Matcher", "How poses are assigned to tracks", matcherEnum(),
                            enumValue(matcherEnum(), d.matcher), at_start));
  install(PROP_INPUT_SIZE,
          g_param_spec_string("input-size", "Input size",
                              "Size the frame is brought to for the spatial network: \"native\", "
                              "\"WxH\" (letterboxed) or \"max:N\" (longer side N pixels)",
                              d.spatial.input_size.toString().c_str(), at_start));
  install(PROP_SCALES,
          g_param_spec_string("scales", "Scales",
                              "Comma-separated scales of multi-scale inference, each in (0, 4] "
                              "(the paper uses 0.5,1,1.5,2; each scale costs one network run)",
                              scalesToString(d.spatial.scales).c_str(), at_start));
  install(PROP_MAX_PERSONS,
          g_param_spec_int("max-persons", "Max persons", "Most persons tracked per frame", 1, 256,
                           d.max_persons, at_start));
  install(PROP_PERSON_THRESHOLD,
          g_param_spec_float("person-threshold", "Person threshold",
                             "Poses with a lower person score are dropped", 0.f, 1.f,
                             d.spatial.person_threshold, at_start));
  install(PROP_KEYPOINT_THRESHOLD,
          g_param_spec_float("keypoint-threshold", "Keypoint threshold",
                             "Keypoints with a lower score are reported with score 0", 0.f, 1.f,
                             d.spatial.keypoint_threshold, at_start));
  install(PROP_NMS_THRESHOLD,
          g_param_spec_float("nms-threshold", "NMS threshold",
                             "Lowest belief-map peak kept by non-maximum suppression (OpenPose "
                             "decoder, the paper's tau_NMS)",
                             0.f, 1.f, d.spatial.nms_threshold, at_start));
  install(PROP_TAU_DELTA,
          g_param_spec_float("tau-delta", "Tau delta",
                             "Pixels: a joint that moved less than this between frames counts as "
                             "still (the paper's tau_Delta)",
                             0.f, 1000.f, d.tau_delta, at_start));
  install(PROP_MIN_TRACK_LENGTH,
          g_param_spec_int("min-track-length", "Min track length",
                           "Tracks are tentative until they are this many frames long", 1, 100000,
                           d.min_track_length, at_start));
  install(PROP_COAST_FRAMES,
          g_param_spec_int("coast-frames", "Coast frames",
                           "Frames a track that was not matched can still be continued", 0, 100000,
                           d.coast_frames, at_start));
  install(PROP_SMOOTHING, g_param_spec_boolean("smoothing", "Smoothing",
                                               "One-Euro smoothing of the keypoints of each track",
                                               d.smoothing, at_start));
  install(PROP_INFERENCE_INTERVAL,
          g_param_spec_uint("inference-interval", "Inference interval",
                            "Run the networks on every Nth frame; the poses of the frames in "
                            "between are moved on with each track's velocity",
                            1, 1000, DEFAULT_INFERENCE_INTERVAL, live));
  install(PROP_SKIP_LATE_FRAMES,
          g_param_spec_boolean("skip-late-frames", "Skip late frames",
                               "When downstream reports lateness (QoS), predict the poses of "
                               "frames that are already late instead of running the networks",
                               DEFAULT_SKIP_LATE_FRAMES, live));
  install(
      PROP_BACKEND,
      g_param_spec_enum("backend", "Backend", "OpenCV dnn backend the networks run on",
                        backendEnum(), enumValue(backendEnum(), d.spatial.dnn.backend), at_start));
  install(PROP_TARGET,
          g_param_spec_enum("target", "Target", "OpenCV dnn target device", targetEnum(),
                            enumValue(targetEnum(), d.spatial.dnn.target), at_start));
  install(PROP_NUM_THREADS,
          g_param_spec_int("num-threads", "Threads",
                           "Threads OpenCV uses for inference (0 = OpenCV's default; the "
                           "setting is process-wide in OpenCV)",
                           0, 1024, d.spatial.dnn.num_threads, at_start));

  gst_element_class_set_static_metadata(
      element_class, "JointFlow pose tracker", "Analyzer/Video",
      "Estimates and tracks the 2D poses of every person (JointFlow, BMVC 2018); attaches "
      "GstJointFlowMeta and person GstVideoRegionOfInterestMeta",
      "JointFlow developers");
  jointflow::gst::addVideoPadTemplates(element_class);

  for (GType t : {modelTypeEnum(), similarityEnum(), matcherEnum(), backendEnum(), targetEnum()})
    gst_type_mark_as_plugin_api(t, static_cast<GstPluginAPIFlags>(0));

  trans_class->start = gst_jointflow_track_start;
  trans_class->stop = gst_jointflow_track_stop;
  trans_class->sink_event = gst_jointflow_track_sink_event;
  trans_class->src_event = gst_jointflow_track_src_event;
  trans_class->transform_ip = gst_jointflow_track_transform_ip;
  filter_class->set_info = gst_jointflow_track_set_info;
}

static void gst_jointflow_track_init(GstJointFlowTrack* self) {
  self->settings = new jointflow::TrackerSettings(kDefaults);
  self->inference_interval = DEFAULT_INFERENCE_INTERVAL;
  self->skip_late_frames = DEFAULT_SKIP_LATE_FRAMES;
  self->earliest_time = GST_CLOCK_TIME_NONE;
  self->stream = new StreamState();
  // GstVideoFilter turns QoS on, which would drop late frames before they reach us; our own
  // policy (skip-late-frames) passes them on with predicted poses. qos=true still drops them.
  gst_base_transform_set_qos_enabled(GST_BASE_TRANSFORM(self), FALSE);
}
