// jointflowtrack under the stream events deployments see (not covered in tests/plugin): EOS before
// any frame, format renegotiation mid-stream, frames too small for the models, flushing seeks
// while PLAYING, and property changes while PLAYING.
#include <catch2/catch.hpp>

#include <atomic>
#include <filesystem>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <gst/app/gstappsrc.h>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "gst_test_util.hpp"
#include "test_env.hpp"

using namespace jointflow::test;

namespace {

std::vector<gint64> idsOf(GstBuffer* buffer) {
  const GstJointFlowMeta* meta = gst_buffer_get_jointflow_meta(buffer);
  REQUIRE(meta != nullptr);
  std::vector<gint64> ids;
  for (guint i = 0; i < gst_jointflow_meta_get_n_persons(meta); ++i)
    ids.push_back(gst_jointflow_meta_get_person(meta, i)->track_id);
  return ids;
}

/// vtest.avi decoded and scaled to 384x288 BGR, tracked, into an appsink named "out".
std::string vtestPipeline(const std::string& track_props = "") {
  return "filesrc location=" + vtestPath() +
         " ! decodebin ! videoconvert ! videoscale ! video/x-raw,format=BGR,width=384,height=288"
         " ! jointflowtrack name=track input-size=384x288 " +
         track_props + " ! appsink name=out sync=false max-buffers=4";
}

GstElement* appsinkOf(GstElement* pipeline) {
  return gst_bin_get_by_name(GST_BIN(pipeline), "out");
}

/// Pulls one sample's ids; REQUIREs a sample within 60 s.
std::vector<gint64> pullIds(GstElement* appsink) {
  GstSample* sample = nullptr;
  g_signal_emit_by_name(appsink, "try-pull-sample", 60 * GST_SECOND, &sample);
  REQUIRE(sample != nullptr);
  const auto ids = idsOf(gst_sample_get_buffer(sample));
  gst_sample_unref(sample);
  return ids;
}

std::string last_error;  ///< the message of the last error waitEosNoError saw

/// Waits for EOS or an error; true for EOS.
bool waitEosNoError(GstElement* pipeline) {
  last_error.clear();
  GstBus* bus = gst_element_get_bus(pipeline);
  GstMessage* msg = gst_bus_timed_pop_filtered(
      bus, 120 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  gst_object_unref(bus);
  const bool eos = msg && GST_MESSAGE_TYPE(msg) == GST_MESSAGE_EOS;
  if (msg && !eos) {
    GError* err = nullptr;
    gst_message_parse_error(msg, &err, nullptr);
    last_error = err->message;
    UNSCOPED_INFO("error: " << last_error);
    g_error_free(err);
  }
  if (msg) gst_message_unref(msg);
  return eos;
}

}  // namespace

TEST_CASE("EOS before any frame: EOS goes through, no error, no buffer", "[hardening][plugin]") {
  initGst();
  SECTION("with a harness, caps set or not") {
    const bool with_caps = GENERATE(true, false);
    INFO("caps " << with_caps);
    GstHarness* h = gst_harness_new("jointflowtrack");
    if (with_caps) gst_harness_set_src_caps_str(h, capsFor("BGR", 320, 240).c_str());
    gst_harness_play(h);
    REQUIRE(gst_harness_push_event(h, gst_event_new_eos()));
    bool saw_eos = false;
    while (GstEvent* e = gst_harness_try_pull_event(h)) {
      saw_eos |= GST_EVENT_TYPE(e) == GST_EVENT_EOS;
      gst_event_unref(e);
    }
    CHECK(saw_eos);
    CHECK(gst_harness_buffers_received(h) == 0);
    gst_harness_teardown(h);
  }
  SECTION("in a pipeline whose source ends at once") {
    GstElement* pipeline = gst_parse_launch(
        "videotestsrc num-buffers=0 ! video/x-raw,width=320,height=240 ! jointflowtrack ! "
        "fakesink",
        nullptr);
    REQUIRE(pipeline != nullptr);
    REQUIRE(gst_element_set_state(pipeline, GST_STATE_PLAYING) != GST_STATE_CHANGE_FAILURE);
    CHECK(waitEosNoError(pipeline));
    gst_element_set_state(pipeline, GST_STATE_NULL);
    gst_object_unref(pipeline);
  }
}

TEST_CASE("format renegotiation mid-stream: every format keeps working", "[hardening][plugin]") {
  initGst();
  GstHarness* h = gst_harness_new("jointflowtrack");
  GstClockTime pts = 0;
  // Same size, new formats, then a new size and back: each buffer gets meta of its own size.
  const std::vector<std::tuple<std::string, int, int>> steps = {
      {"BGR", 320, 240},  {"I420", 320, 240}, {"RGBx", 320, 240},
      {"NV12", 322, 242}, {"BGR", 321, 241},  {"BGR", 320, 240}};
  for (const auto& [format, w, h_px] : steps) {
    INFO(format << " " << w << "x" << h_px);
    gst_harness_set_src_caps_str(h, capsFor(format, w, h_px).c_str());
    for (int i = 0; i < 2; ++i, pts += GST_SECOND / 30) {
      REQUIRE(gst_harness_push(h, blackFrame(format, w, h_px, pts)) == GST_FLOW_OK);
      GstBuffer* out = gst_harness_pull(h);
      REQUIRE(out != nullptr);
      const GstJointFlowMeta* meta = gst_buffer_get_jointflow_meta(out);
      REQUIRE(meta != nullptr);
      CHECK(meta->width == static_cast<guint>(w));
      CHECK(meta->height == static_cast<guint>(h_px));
      CHECK(gst_jointflow_meta_get_n_persons(meta) == 0);  // black frames
      gst_buffer_unref(out);
    }
  }
  gst_harness_teardown(h);
}

TEST_CASE("a frame too small for the models fails the stream with a message, not a crash",
          "[hardening][plugin]") {
  initGst();
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{8, 600}}) {
    INFO(w << "x" << h);
    GstElement* pipeline = gst_parse_launch(
        ("videotestsrc num-buffers=3 ! video/x-raw,format=BGR,width=" + std::to_string(w) +
         ",height=" + std::to_string(h) + " ! jointflowtrack ! fakesink")
            .c_str(),
        nullptr);
    REQUIRE(pipeline != nullptr);
    REQUIRE(gst_element_set_state(pipeline, GST_STATE_PLAYING) != GST_STATE_CHANGE_FAILURE);
    CHECK_FALSE(waitEosNoError(pipeline));
    CHECK_THAT(last_error, Catch::Contains("too small") &&
                               Catch::Contains(std::to_string(w) + "x" + std::to_string(h)));
    gst_element_set_state(pipeline, GST_STATE_NULL);
    gst_object_unref(pipeline);
  }
}

TEST_CASE("flushing seeks while PLAYING: tracks start afresh, the stream reaches EOS",
          "[hardening][plugin]") {
  initGst();
  JF_REQUIRE_PATH_OR_SKIP(vtestPath());
  GstElement* pipeline = gst_parse_launch(vtestPipeline().c_str(), nullptr);
  REQUIRE(pipeline != nullptr);
  GstElement* sink = appsinkOf(pipeline);
  REQUIRE(gst_element_set_state(pipeline, GST_STATE_PLAYING) != GST_STATE_CHANGE_FAILURE);
  gint64 max_id = 0;
  for (int round = 0; round < 3; ++round) {
    INFO("round " << round);
    for (int i = 0; i < 4; ++i)
      for (gint64 id : pullIds(sink)) max_id = std::max(max_id, id);
    REQUIRE(max_id > 0);
    // Back to 2 s, flushing, while the streaming thread is busy in the element.
    REQUIRE(gst_element_seek_simple(
        pipeline, GST_FORMAT_TIME,
        static_cast<GstSeekFlags>(GST_SEEK_FLAG_FLUSH | GST_SEEK_FLAG_ACCURATE), 2 * GST_SECOND));
    // The first frame after the seek has only new ids: nothing carried across the cut.
    for (gint64 id : pullIds(sink)) CHECK(id > max_id);
  }
  // And to the end: a seek near the end, then EOS.
  REQUIRE(gst_element_seek_simple(pipeline, GST_FORMAT_TIME, GST_SEEK_FLAG_FLUSH,
                                  (795 * GST_SECOND) / 10));
  GstSample* sample = nullptr;
  do {
    g_signal_emit_by_name(sink, "try-pull-sample", 60 * GST_SECOND, &sample);
    if (sample) gst_sample_unref(sample);
  } while (sample);
  gboolean eos = FALSE;
  g_object_get(sink, "eos", &eos, nullptr);
  CHECK(eos);
  CHECK(busError(pipeline).empty());
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(sink);
  gst_object_unref(pipeline);
}

TEST_CASE("property changes while PLAYING: live ones apply at once, the others at the next start",
          "[hardening][plugin]") {
  initGst();
  JF_REQUIRE_PATH_OR_SKIP(vtestPath());
  // appsrc rather than decodebin: the pipeline is restarted below, and gst_parse_launch links
  // decodebin's dynamic pad only once.
  std::vector<cv::Mat> frames;
  {
    cv::VideoCapture video(vtestPath());
    cv::Mat f, small;
    while (frames.size() < 20 && video.read(f)) {
      cv::resize(f, small, cv::Size(384, 288), 0, 0, cv::INTER_AREA);
      frames.push_back(small.clone());
    }
  }
  REQUIRE(frames.size() == 20);
  GstElement* pipeline = gst_parse_launch(
      "appsrc name=src format=time caps=video/x-raw,format=BGR,width=384,height=288,"
      "framerate=10/1 ! jointflowtrack name=track input-size=384x288 ! "
      "appsink name=out sync=false",
      nullptr);
  REQUIRE(pipeline != nullptr);
  GstElement* src = gst_bin_get_by_name(GST_BIN(pipeline), "src");
  GstElement* sink = appsinkOf(pipeline);
  GstElement* track = gst_bin_get_by_name(GST_BIN(pipeline), "track");
  int next = 0;
  auto feed = [&](int count) {
    for (int i = 0; i < count; ++i, ++next) {
      const cv::Mat& f = frames[next % frames.size()];
      GstBuffer* b = gst_buffer_new_allocate(nullptr, f.total() * 3, nullptr);
      gst_buffer_fill(b, 0, f.data, f.total() * 3);
      GST_BUFFER_PTS(b) = next * GST_SECOND / 10;
      REQUIRE(gst_app_src_push_buffer(GST_APP_SRC(src), b) == GST_FLOW_OK);
    }
  };
  REQUIRE(gst_element_set_state(pipeline, GST_STATE_PLAYING) != GST_STATE_CHANGE_FAILURE);
  feed(1);
  REQUIRE(pullIds(sink).size() >= 2);  // vtest.avi's first frames show several people

  // Settings read at start, changed from another thread while frames flow: stored (and read
  // back), the running tracker unchanged, no crash or race (the ASan build runs this too).
  std::atomic<bool> done{false};
  std::thread changer([&] {
    for (int i = 0; !done; ++i) {
      g_object_set(track, "max-persons", 1 + i % 2, "input-size", i % 2 ? "256x256" : "384x288",
                   "similarity", i % 2 ? 2 : 1, "smoothing", i % 2 == 1, nullptr);
      g_usleep(2000);
    }
  });
  feed(6);
  size_t most = 0;
  for (int i = 0; i < 6; ++i) most = std::max(most, pullIds(sink).size());
  done = true;
  changer.join();
  CHECK(most >= 2);  // max-persons=1 is not in effect while running
  g_object_set(track, "max-persons", 1, "input-size", "384x288", "smoothing", FALSE, nullptr);
  gint max_persons = 0;
  g_object_get(track, "max-persons", &max_persons, nullptr);
  CHECK(max_persons == 1);

  // inference-interval is live: from the next frame on, every 3rd frame is inferred.
  g_object_set(track, "inference-interval", 3u, nullptr);
  feed(7);
  int predicted = 0;
  for (int i = 0; i < 7; ++i) {
    GstSample* sample = nullptr;
    g_signal_emit_by_name(sink, "try-pull-sample", 60 * GST_SECOND, &sample);
    REQUIRE(sample != nullptr);
    predicted += gst_buffer_get_jointflow_meta(gst_sample_get_buffer(sample))->predicted ? 1 : 0;
    gst_sample_unref(sample);
  }
  CHECK(predicted == 5);  // frames 1, 2, 4, 5 and 7 after the change

  // At the next start the stored values are in effect.
  REQUIRE(gst_element_set_state(pipeline, GST_STATE_NULL) == GST_STATE_CHANGE_SUCCESS);
  g_object_set(track, "inference-interval", 1u, nullptr);
  REQUIRE(gst_element_set_state(pipeline, GST_STATE_PLAYING) != GST_STATE_CHANGE_FAILURE);
  feed(3);
  for (int i = 0; i < 3; ++i) CHECK(pullIds(sink).size() <= 1);
  CHECK(busError(pipeline).empty());
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(track);
  gst_object_unref(src);
  gst_object_unref(sink);
  gst_object_unref(pipeline);
}
