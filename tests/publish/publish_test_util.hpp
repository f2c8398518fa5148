// Helpers of the publish tests: synthetic frames with poses that change from frame to frame
// (exact checks), the real pipeline on vtest.avi with the real models, and jointflowmetapublish
// in a GstHarness.
#pragma once

#include <gst/check/gstharness.h>
#include <gst/gst.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "gst_test_util.hpp"
#include "test_env.hpp"

namespace jointflow::test {

constexpr int kSynthW = 64;
constexpr int kSynthH = 48;

/// Frame @i: two people whose boxes and a keypoint move with @i; PTS i/30 s.
inline GstBuffer* syntheticFrame(int i) {
  GstBuffer* b =
      blackFrame("RGB", kSynthW, kSynthH, static_cast<GstClockTime>(i) * GST_SECOND / 30);
  GstJointFlowMeta* meta = gst_buffer_add_jointflow_meta(b, kSynthW, kSynthH);
  for (int k = 0; k < 2; ++k) {
    JointFlowPerson p = person(1 + k, 2.f + (i % 20) + 10 * k, 3.f + k, 20, 30);
    p.keypoints[JOINTFLOW_KEYPOINT_NOSE] = {5.f + i, 6.f + k, 0.75f};
    gst_jointflow_meta_add_person(meta, &p);
  }
  return b;
}

/// Frame @i of a camera where track 1 stays and track 2 leaves after frame 9 (what
/// examples/consumer.py reports: 2 present, then 1, then track 2 ended).
inline GstBuffer* leavingFrame(int i) {
  GstBuffer* b =
      blackFrame("RGB", kSynthW, kSynthH, static_cast<GstClockTime>(i) * GST_SECOND / 30);
  GstJointFlowMeta* meta = gst_buffer_add_jointflow_meta(b, kSynthW, kSynthH);
  JointFlowPerson stays = person(1, 5, 5, 20, 30);
  gst_jointflow_meta_add_person(meta, &stays);
  if (i <= 9) {
    JointFlowPerson leaves = person(2, 30, 5, 20, 30);
    gst_jointflow_meta_add_person(meta, &leaves);
  }
  return b;
}

/// What examples/consumer.py prints for cameras door and hall of 20 leavingFrame()s each.
inline void checkConsumerOutput(const std::string& out) {
  INFO(out);
  for (const std::string camera : {"door", "hall"}) {
    CHECK_THAT(out, Catch::Contains(camera + " frame 0: 2 present [1, 2]"));
    CHECK_THAT(out, Catch::Contains(camera + " frame 10: 1 present [1]"));
    CHECK_THAT(out, Catch::Contains(camera + " frame 15: track 2 ended (frames 0-9)"));
    CHECK_THAT(out, Catch::Contains(camera + " end: track 1 ended (frames 0-19)"));
  }
}

inline std::vector<std::string> readLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

inline long frameOf(const std::string& message) {
  return nlohmann::json::parse(message).at("frame").get<long>();
}

/// The frame numbers of JSON records, "0 1 2 ...", for a failure message.
inline std::string framesOf(const std::vector<std::string>& records) {
  std::string out;
  for (const auto& r : records) out += std::to_string(frameOf(r)) + " ";
  return out;
}

/// jointflowmetapublish (with @properties) in a harness, taking 64x48 RGB.
class PublishHarness {
 public:
  explicit PublishHarness(const std::string& properties) {
    initGst();
    // The element itself (gst_harness_new_parse would wrap it in a bin without its properties).
    GstElement* element = gst_parse_launch(("jointflowmetapublish " + properties).c_str(), nullptr);
    h_ = gst_harness_new_with_element(element, "sink", "src");
    gst_object_unref(element);
    // A bus of its own, so that the element's warnings and errors can be read.
    bus_ = gst_bus_new();
    gst_element_set_bus(h_->element, bus_);
    gst_harness_set_src_caps_str(h_, capsFor("RGB", kSynthW, kSynthH).c_str());
  }
  ~PublishHarness() {
    // A message left on the bus holds the element, which holds the bus: flushing drops them
    // (and the state changes of the teardown), so that both are freed.
    gst_bus_set_flushing(bus_, TRUE);
    gst_harness_teardown(h_);
    gst_object_unref(bus_);
  }
  PublishHarness(const PublishHarness&) = delete;
  PublishHarness& operator=(const PublishHarness&) = delete;

  /// Pushes synthetic frames [from, to) and pulls each back out (the video passes through).
  GstFlowReturn push(int from, int to) {
    for (int i = from; i < to; ++i) {
      const GstFlowReturn r = gst_harness_push(h_, syntheticFrame(i));
      if (r != GST_FLOW_OK) return r;
      gst_buffer_unref(gst_harness_pull(h_));
    }
    return GST_FLOW_OK;
  }
  /// EOS through the element (it flushes, within flush-timeout); returns how long it took.
  std::chrono::milliseconds eos() {
    const auto t0 = std::chrono::steady_clock::now();
    gst_harness_push_event(h_, gst_event_new_eos());
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() -
                                                                 t0);
  }
  guint64 counter(const char* name) {
    guint64 v = 0;
    g_object_get(element(), name, &v, nullptr);
    return v;
  }
  GstElement* element() { return h_->element; }
  GstHarness* harness() { return h_; }

 private:
  GstHarness* h_ = nullptr;
  GstBus* bus_ = nullptr;
};

/// Pushes a frame every 5 ms until the element fails a push or @timeout passes; returns the
/// frames pushed and the last result (what a camera would see while no broker is there).
inline std::pair<int, GstFlowReturn> pushUntilError(PublishHarness& h,
                                                    std::chrono::milliseconds timeout) {
  const auto t0 = std::chrono::steady_clock::now();
  GstFlowReturn r = GST_FLOW_OK;
  int pushed = 0;
  while (r == GST_FLOW_OK && std::chrono::steady_clock::now() - t0 < timeout) {
    r = h.push(pushed, pushed + 1);
    pushed++;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return {pushed, r};
}

/// Messages of a type the element posted on a harness's bus (warnings, errors).
inline std::vector<std::string> busMessages(GstElement* element, GstMessageType type) {
  std::vector<std::string> out;
  GstBus* bus = gst_element_get_bus(element);
  if (!bus) return out;
  while (GstMessage* msg = gst_bus_pop_filtered(bus, type)) {
    GError* err = nullptr;
    if (type == GST_MESSAGE_WARNING)
      gst_message_parse_warning(msg, &err, nullptr);
    else
      gst_message_parse_error(msg, &err, nullptr);
    out.push_back(err ? err->message : "");
    if (err) g_error_free(err);
    gst_message_unref(msg);
  }
  gst_object_unref(bus);
  return out;
}

/// Runs @launch (a gst-launch description) to EOS, at most @timeout; returns "" or the error.
inline std::string runToEos(const std::string& launch, std::chrono::seconds timeout) {
  initGst();
  GError* err = nullptr;
  GstElement* pipeline = gst_parse_launch(launch.c_str(), &err);
  if (!pipeline) {
    std::string text = err ? err->message : "parse failed";
    if (err) g_error_free(err);
    return text;
  }
  std::string result;
  if (gst_element_set_state(pipeline, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
    result = "could not start: " + busError(pipeline);
  if (result.empty()) {
    GstBus* bus = gst_element_get_bus(pipeline);
    GstMessage* msg = gst_bus_timed_pop_filtered(
        bus, static_cast<GstClockTime>(timeout.count()) * GST_SECOND,
        static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
    if (!msg) {
      result = "no EOS within the time limit";
    } else {
      result = errorText(msg);
      gst_message_unref(msg);
    }
    gst_object_unref(bus);
  }
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(pipeline);
  return result;
}

/// The real pipeline: at least @frames frames of vtest.avi through jointflowtrack (the shipped
/// models), jointflowjsonwriter (to @json_path) and jointflowmetapublish (with @publish).
/// identity eos-after=N turns the Nth buffer into EOS, and the decoder's thread may still push a
/// later frame after that (examples/probe.py): so N = @frames + 1, and the tests compare what
/// was published with what was written, however many that is.
inline std::string vtestLaunch(int frames, const std::string& json_path,
                               const std::string& source_id, const std::string& publish) {
  return "filesrc location=" + vtestPath() +
         " ! decodebin ! videoconvert ! identity eos-after=" + std::to_string(frames + 1) +
         " ! jointflowtrack ! jointflowjsonwriter location=" + json_path +
         " source-id=" + source_id + " ! jointflowmetapublish source-id=" + source_id + " " +
         publish + " ! fakesink";
}

}  // namespace jointflow::test
