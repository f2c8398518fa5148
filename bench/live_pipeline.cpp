#include "live_pipeline.hpp"

#include <gst/gst.h>

#include <chrono>
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/videoio.hpp>

#include "jointflow/error.hpp"

namespace jointflow::bench {
namespace {

using json = nlohmann::json;

/// A person object of the JSON writer (gst-plugin/pose_json.cpp) as a TrackedPose: keypoints by
/// their names, the box in frame pixels.
TrackedPose trackedPose(const json& o) {
  TrackedPose t;
  t.track_id = o.at("id").get<std::int64_t>();
  t.tentative = o.at("tentative").get<bool>();
  t.age = o.at("age").get<int>();
  t.age_seconds = o.at("age_s").get<double>();
  t.pose.score = o.at("confidence").get<float>();
  t.pose.box = {o.at("x").get<float>(), o.at("y").get<float>(), o.at("w").get<float>(),
                o.at("h").get<float>()};
  const json& keypoints = o.at("keypoints");
  for (int j = 0; j < kNumJoints; ++j) {
    const json& k = keypoints.at(std::string(kJointNames[j]));
    t.pose.keypoints[j] = {k.at("x").get<float>(), k.at("y").get<float>(),
                           k.at("score").get<float>()};
  }
  return t;
}

}  // namespace

PipelineRun runPipeline(const std::string& launch, const std::string& jsonl) {
  PipelineRun out;
  GError* error = nullptr;
  GstElement* pipeline = gst_parse_launch(launch.c_str(), &error);
  if (!pipeline || error) {
    out.note = std::string("cannot make the pipeline: ") + (error ? error->message : "?");
    if (error) g_error_free(error);
    if (pipeline) gst_object_unref(pipeline);
    return out;
  }
  const auto t0 = std::chrono::steady_clock::now();
  gst_element_set_state(pipeline, GST_STATE_PLAYING);
  GstBus* bus = gst_element_get_bus(pipeline);
  GstMessage* m = gst_bus_timed_pop_filtered(
      bus, GST_CLOCK_TIME_NONE, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  if (GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
    GError* e = nullptr;
    gchar* debug = nullptr;
    gst_message_parse_error(m, &e, &debug);
    out.note = std::string("pipeline error: ") + e->message +
               (debug ? std::string(" (") + debug + ")" : "");
    g_error_free(e);
    g_free(debug);
  }
  gst_message_unref(m);
  gst_object_unref(bus);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(pipeline);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!out.note.empty()) return out;

  std::ifstream in(jsonl);
  if (!in) throw Error(jsonl + ": the pipeline wrote no JSON Lines");
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    const json record = json::parse(line);
    const json& timestamp = record.at("timestamp");
    out.times.push_back(timestamp.is_null()
                            ? std::nan("")
                            : timestamp.get<double>() / static_cast<double>(GST_SECOND));
    out.frames.emplace_back();
    for (const json& o : record.at("objects")) out.frames.back().push_back(trackedPose(o));
  }
  out.ran = true;
  return out;
}

std::string trackPipeline(const std::string& source, bool live, const std::string& properties,
                          const std::string& jsonl) {
  // The queue holds one buffer and no limit of bytes or time: the newest frame waits, older ones
  // are dropped (docs/gstreamer.md, live sources).
  const std::string pacing =
      live ? " ! identity sync=true ! queue leaky=downstream max-size-buffers=1 max-size-bytes=0 "
             "max-size-time=0"
           : "";
  return source + pacing + " ! videoconvert ! jointflowtrack" +
         (properties.empty() ? "" : " " + properties) + " ! jointflowjsonwriter location=\"" +
         jsonl + "\" ! fakesink sync=false";
}

void writeClip(const std::vector<cv::Mat>& frames, double fps, const std::string& path) {
  if (frames.empty()) throw Error("writeClip: no frames for " + path);
  cv::VideoWriter out(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), fps,
                      frames.front().size());
  if (!out.isOpened()) throw Error(path + ": OpenCV cannot write an MJPEG AVI here");
  // OpenCV's default quality (95); the offline run of the same clip is the live run's reference,
  // so both see the same JPEG loss.
  for (const cv::Mat& f : frames) out.write(f);
}

}  // namespace jointflow::bench
