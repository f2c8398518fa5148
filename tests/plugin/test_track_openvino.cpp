// jointflowtrack with backend=openvino on frames of vtest.avi: every frame leaves, in order, with
// the people cv::dnn finds, although the element holds one frame while its network runs; the
// latency it reports; elements in threads sharing one compiled model (model-instance-id); an
// unknown device.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/videoio.hpp>

#include "gst_test_util.hpp"
#include "test_env.hpp"

using namespace jointflow::test;

namespace {

constexpr int kW = 768, kH = 576, kFrames = 8;

// Frames 100.. of vtest.avi, BGR; read once.
const std::vector<cv::Mat>& frames() {
  static const std::vector<cv::Mat> out = [] {
    std::vector<cv::Mat> f;
    cv::VideoCapture capture(vtestPath());
    capture.set(cv::CAP_PROP_POS_FRAMES, 100);
    cv::Mat frame;
    for (int i = 0; i < kFrames && capture.read(frame); ++i) f.push_back(frame.clone());
    return f;
  }();
  return out;
}

GstBuffer* bufferOf(const cv::Mat& bgr, int index) {
  const size_t bytes = bgr.total() * bgr.elemSize();
  GstBuffer* buffer = gst_buffer_new_allocate(nullptr, bytes, nullptr);
  gst_buffer_fill(buffer, 0, bgr.data, bytes);
  GST_BUFFER_PTS(buffer) = index * GST_SECOND / 30;
  GST_BUFFER_DURATION(buffer) = GST_SECOND / 30;
  return buffer;
}

struct Out {
  GstClockTime pts;
  std::vector<gint64> ids;
  std::vector<float> x;  ///< box left edges
};

// A buffer's poses; false when it has no JointFlow meta.
bool outOf(GstBuffer* buffer, Out* o) {
  const GstJointFlowMeta* meta = gst_buffer_get_jointflow_meta(buffer);
  if (!meta) return false;
  *o = Out{GST_BUFFER_PTS(buffer), {}, {}};
  for (guint i = 0; i < gst_jointflow_meta_get_n_persons(meta); ++i) {
    o->ids.push_back(gst_jointflow_meta_get_person(meta, i)->track_id);
    o->x.push_back(gst_jointflow_meta_get_person(meta, i)->x);
  }
  return true;
}

// What one run brought out, and the first thing that went wrong (empty: nothing). No Catch
// assertions in here: the streams case runs it in threads, and Catch's assertions are not
// thread-safe (ThreadSanitizer reports them), so the calling thread checks `error`.
struct Run {
  std::vector<Out> out;
  std::string error;
};

// All frames through one element; outputs as they leave, EOS last.
Run runFrames(const std::string& props, bool expect_held) {
  GstHarness* h = gst_harness_new_parse(("jointflowtrack " + props).c_str());
  gst_harness_set_src_caps_str(h, capsFor("BGR", kW, kH).c_str());
  Run r;
  auto take = [&](GstBuffer* b) {
    Out o;
    if (!outOf(b, &o) && r.error.empty()) r.error = "a buffer without JointFlow meta";
    r.out.push_back(o);
    gst_buffer_unref(b);
  };
  for (int i = 0; i < kFrames && r.error.empty(); ++i) {
    if (gst_harness_push(h, bufferOf(frames()[i], i)) != GST_FLOW_OK) {
      r.error = "frame " + std::to_string(i) + " was refused";
      break;
    }
    if (i == 0 && expect_held) {
      // The first frame stays in the element until the second one is submitted.
      if (gst_harness_buffers_received(h) != 0) r.error = "the first frame was not held";
      continue;
    }
    GstBuffer* b = gst_harness_pull(h);
    if (!b) {
      r.error = "no buffer came out for frame " + std::to_string(i);
      break;
    }
    take(b);
  }
  if (!gst_harness_push_event(h, gst_event_new_eos()) && r.error.empty()) r.error = "EOS refused";
  // The held frame leaves before EOS does.
  while (GstBuffer* b = gst_harness_try_pull(h)) take(b);
  bool eos = false;
  while (GstEvent* e = gst_harness_try_pull_event(h)) {
    eos = eos || GST_EVENT_TYPE(e) == GST_EVENT_EOS;
    gst_event_unref(e);
  }
  if (!eos && r.error.empty()) r.error = "no EOS after the frames";
  gst_harness_teardown(h);
  return r;
}

std::vector<Out> run(const std::string& props, bool expect_held) {
  const Run r = runFrames(props, expect_held);
  INFO(props);
  CHECK(r.error == "");
  return r.out;
}

bool haveFrames() {
  if (!pathOrSkip(vtestPath())) return false;
  REQUIRE(frames().size() == kFrames);
  return true;
}

GstClockTime latencyOf(const std::string& props) {
  GstHarness* h = gst_harness_new_parse(("jointflowtrack " + props).c_str());
  gst_harness_set_src_caps_str(h, capsFor("BGR", kW, kH).c_str());
  gst_harness_push(h, bufferOf(frames()[0], 0));  // caps negotiated, models loaded
  GstQuery* q = gst_query_new_latency();
  REQUIRE(gst_pad_peer_query(h->sinkpad, q));
  GstClockTime min = 0;
  gst_query_parse_latency(q, nullptr, &min, nullptr);
  gst_query_unref(q);
  gst_harness_teardown(h);
  return min;
}

}  // namespace

TEST_CASE("backend=openvino: every frame leaves in order with the people cv::dnn finds",
          "[plugin][openvino]") {
  initGst();
  if (!haveFrames()) return;
  const std::vector<Out> dnn = run("", false);
  const std::vector<Out> ov = run("backend=openvino", true);
  REQUIRE(dnn.size() == kFrames);
  REQUIRE(ov.size() == kFrames);
  int people = 0;
  for (int i = 0; i < kFrames; ++i) {
    CHECK(ov[i].pts == static_cast<GstClockTime>(i) * GST_SECOND / 30);  // as bufferOf stamps it
    CHECK(std::abs(static_cast<int>(ov[i].ids.size()) - static_cast<int>(dnn[i].ids.size())) <= 1);
    people += static_cast<int>(ov[i].ids.size());
  }
  CHECK(people >= 3 * kFrames);
  // The tracks hold from frame to frame as on cv::dnn: as many distinct ids over the frames,
  // within one.
  auto distinct = [](const std::vector<Out>& run) {
    std::set<gint64> ids;
    for (const Out& o : run) ids.insert(o.ids.begin(), o.ids.end());
    return static_cast<int>(ids.size());
  };
  INFO("distinct ids: cv::dnn " << distinct(dnn) << ", OpenVINO " << distinct(ov));
  CHECK(std::abs(distinct(ov) - distinct(dnn)) <= 1);
  CHECK(distinct(ov) <= static_cast<int>(ov.front().ids.size()) + 3);
}

TEST_CASE("backend=openvino reports the frame it holds as latency", "[plugin][openvino]") {
  initGst();
  if (!haveFrames()) return;
  const GstClockTime dnn = latencyOf("");
  const GstClockTime ov = latencyOf("backend=openvino");
  CHECK(ov == dnn + GST_SECOND / 30);  // capsFor: 30 frames/s
}

TEST_CASE("backend=openvino async-inference=false: no frame held, the same poses",
          "[plugin][openvino]") {
  initGst();
  if (!haveFrames()) return;
  const std::vector<Out> held = run("backend=openvino", true);
  const std::vector<Out> direct = run("backend=openvino async-inference=false", false);
  REQUIRE(held.size() == kFrames);
  REQUIRE(direct.size() == kFrames);
  for (int i = 0; i < kFrames; ++i) {
    CHECK(direct[i].pts == held[i].pts);
    CHECK(direct[i].ids == held[i].ids);
    CHECK(direct[i].x == held[i].x);
  }
  CHECK(latencyOf("backend=openvino async-inference=false") == latencyOf(""));
}

TEST_CASE("elements in threads sharing one model-instance-id track alike",
          "[plugin][openvino][streams]") {
  initGst();
  if (!haveFrames()) return;
  constexpr int kStreams = 3;
  std::vector<Run> runs(kStreams);
  std::vector<std::thread> threads;
  for (int i = 0; i < kStreams; ++i)
    threads.emplace_back(
        [&, i] { runs[i] = runFrames("backend=openvino model-instance-id=plugin-test", true); });
  for (auto& t : threads) t.join();
  std::vector<std::vector<Out>> out;
  for (const Run& r : runs) {
    CHECK(r.error == "");
    out.push_back(r.out);
  }
  REQUIRE(out[0].size() == kFrames);
  for (int i = 1; i < kStreams; ++i) {
    REQUIRE(out[i].size() == out[0].size());
    for (size_t k = 0; k < out[0].size(); ++k) {
      CHECK(out[i][k].ids == out[0][k].ids);
      CHECK(out[i][k].x == out[0][k].x);  // one compiled model: the same numbers
    }
  }
}

TEST_CASE("backend=openvino with an unknown device fails the state change naming the devices",
          "[plugin][openvino]") {
  initGst();
  GstElement* pipeline = gst_parse_launch(
      "videotestsrc num-buffers=1 ! jointflowtrack backend=openvino device=TPU ! fakesink",
      nullptr);
  REQUIRE(pipeline != nullptr);
  CHECK(gst_element_set_state(pipeline, GST_STATE_PAUSED) == GST_STATE_CHANGE_FAILURE);
  const std::string error = busError(pipeline);
  CHECK(error.find("\"TPU\"") != std::string::npos);
  CHECK(error.find("CPU") != std::string::npos);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(pipeline);
}
