#include "pose_json.hpp"

#include <algorithm>
#include <utility>

#include "person_box.hpp"

namespace jointflow::gst {
namespace {

nlohmann::json personObject(const JointFlowPerson& p, guint width, guint height) {
  nlohmann::json keypoints = nlohmann::json::object();
  for (guint k = 0; k < JOINTFLOW_N_KEYPOINTS; ++k) {
    const JointFlowKeypoint& kp = p.keypoints[k];
    keypoints[jointflow_keypoint_name(k)] = {{"x", kp.x}, {"y", kp.y}, {"score", kp.score}};
  }
  // DL Streamer's "detection": the box in the frame (as the ROI meta has it) normalised to [0, 1].
  const FrameBox box = boxInFrame(p, width, height);
  auto norm = [](float v, guint size) { return size > 0 ? v / static_cast<float>(size) : 0.f; };
  const nlohmann::json detection = {{"bounding_box",
                                     {{"x_min", norm(box.x0, width)},
                                      {"y_min", norm(box.y0, height)},
                                      {"x_max", norm(box.x1, width)},
                                      {"y_max", norm(box.y1, height)}}},
                                    {"confidence", p.score},
                                    {"label", "person"},
                                    {"label_id", 0}};
  nlohmann::json object = {{"id", p.track_id},
                           {"tentative", static_cast<bool>(p.tentative)},
                           {"age", p.age},
                           {"age_s", p.age_seconds},
                           {"confidence", p.score},
                           {"x", p.x},
                           {"y", p.y},
                           {"w", p.width},
                           {"h", p.height},
                           {"detection", detection},
                           {"keypoints", keypoints}};
  // Only on the frame the id changed (late re-entry): a consumer joins the two ids' histories.
  if (p.previous_track_id > 0) object["previous_id"] = p.previous_track_id;
  return object;
}

}  // namespace

nlohmann::json frameRecord(const GstJointFlowMeta* meta, guint64 frame, GstClockTime timestamp,
                           guint width, guint height, const std::string& source_id) {
  if (meta) {
    width = meta->width;
    height = meta->height;
  }
  nlohmann::json objects = nlohmann::json::array();
  for (guint i = 0; meta && i < gst_jointflow_meta_get_n_persons(meta); ++i)
    objects.push_back(personObject(*gst_jointflow_meta_get_person(meta, i), width, height));
  nlohmann::json record = {{"frame", frame},
                           {"timestamp", nullptr},
                           {"resolution", {{"width", width}, {"height", height}}},
                           {"predicted", meta ? static_cast<bool>(meta->predicted) : false},
                           {"objects", objects}};
  if (GST_CLOCK_TIME_IS_VALID(timestamp)) record["timestamp"] = timestamp;
  if (!source_id.empty()) record["source_id"] = source_id;
  return record;
}

void FrameRecorder::reset(std::string source_id) {
  source_id_ = std::move(source_id);
  frame_ = 0;
  have_info_ = false;
}

void FrameRecorder::setCaps(const GstCaps* caps) {
  have_info_ = gst_video_info_from_caps(&info_, caps);
}

std::string FrameRecorder::next(GstBuffer* buffer) {
  const guint width = have_info_ ? GST_VIDEO_INFO_WIDTH(&info_) : 0;
  const guint height = have_info_ ? GST_VIDEO_INFO_HEIGHT(&info_) : 0;
  // Invalid UTF-8 in a source id is replaced rather than thrown on: a camera name must not stop
  // the stream.
  return frameRecord(gst_buffer_get_jointflow_meta(buffer), frame_++, GST_BUFFER_PTS(buffer), width,
                     height, source_id_)
      .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace jointflow::gst
