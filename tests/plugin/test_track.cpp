// jointflowtrack with the real models on a few frames of vtest.avi: meta on every buffer, stable
// ids, untouched buffers, every format, resets (flush, resolution) and what does not reset
// (DISCONT, PTS gaps, segments, formats), inference interval, state cycles, model errors, refused
// property values, separate instances.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "gst_test_util.hpp"
#include "test_env.hpp"

using namespace jointflow::test;

namespace {

constexpr int kW = 768, kH = 576;

// Frames 100.. of vtest.avi (several people walking), BGR; read once.
const std::vector<cv::Mat>& vtestFrames() {
  static const std::vector<cv::Mat> frames = [] {
    std::vector<cv::Mat> out;
    cv::VideoCapture capture(vtestPath());
    capture.set(cv::CAP_PROP_POS_FRAMES, 100);
    cv::Mat frame;
    for (int i = 0; i < 6 && capture.read(frame); ++i) out.push_back(frame.clone());
    return out;
  }();
  return frames;
}

GstBuffer* bufferOf(const cv::Mat& bgr, int index) {
  const size_t bytes = bgr.total() * bgr.elemSize();
  GstBuffer* buffer = gst_buffer_new_allocate(nullptr, bytes, nullptr);
  gst_buffer_fill(buffer, 0, bgr.data, bytes);
  GST_BUFFER_PTS(buffer) = index * GST_SECOND / 10;
  GST_BUFFER_DTS(buffer) = index * GST_SECOND / 10;
  GST_BUFFER_DURATION(buffer) = GST_SECOND / 10;
  GST_BUFFER_OFFSET(buffer) = index;
  return buffer;
}

struct Result {
  std::vector<gint64> ids;
  std::vector<cv::Point2f> centres;
  bool predicted = false;
  guint width = 0, height = 0;
};

Result resultOf(GstBuffer* buffer) {
  const GstJointFlowMeta* meta = gst_buffer_get_jointflow_meta(buffer);
  REQUIRE(meta != nullptr);
  Result r;
  r.predicted = meta->predicted;
  r.width = meta->width;
  r.height = meta->height;
  for (guint i = 0; i < gst_jointflow_meta_get_n_persons(meta); ++i) {
    const JointFlowPerson* p = gst_jointflow_meta_get_person(meta, i);
    r.ids.push_back(p->track_id);
    r.centres.emplace_back(p->x + p->width / 2, p->y + p->height / 2);
  }
  return r;
}

GstHarness* trackHarness(const std::string& props = "", const std::string& format = "BGR") {
  GstHarness* h = gst_harness_new_parse(("jointflowtrack " + props).c_str());
  gst_harness_set_src_caps_str(h, capsFor(format, kW, kH).c_str());
  return h;
}

Result pushPull(GstHarness* h, GstBuffer* in) {
  REQUIRE(gst_harness_push(h, in) == GST_FLOW_OK);
  GstBuffer* out = gst_harness_pull(h);
  REQUIRE(out != nullptr);
  Result r = resultOf(out);
  gst_buffer_unref(out);
  return r;
}

gint64 maxId(const std::vector<Result>& results) {
  gint64 m = 0;
  for (const auto& r : results)
    for (gint64 id : r.ids) m = std::max(m, id);
  return m;
}

bool haveFrames() {
  if (!pathOrSkip(vtestPath())) return false;
  REQUIRE(vtestFrames().size() == 6);
  return true;
}

}  // namespace

TEST_CASE("every buffer gets meta and ROIs; ids are stable; the buffer is untouched",
          "[plugin][track]") {
  initGst();
  if (!haveFrames()) return;
  GstHarness* h = trackHarness();
  std::vector<Result> results;
  for (int i = 0; i < 4; ++i) {
    GstBuffer* in = bufferOf(vtestFrames()[i], i);
    if (i == 2) GST_BUFFER_FLAG_SET(in, GST_BUFFER_FLAG_DELTA_UNIT);
    REQUIRE(gst_harness_push(h, in) == GST_FLOW_OK);
    GstBuffer* out = gst_harness_pull(h);
    REQUIRE(out != nullptr);
    CHECK(GST_BUFFER_PTS(out) == static_cast<GstClockTime>(i) * GST_SECOND / 10);
    CHECK(GST_BUFFER_DTS(out) == static_cast<GstClockTime>(i) * GST_SECOND / 10);
    CHECK(GST_BUFFER_DURATION(out) == GST_SECOND / 10);
    CHECK(GST_BUFFER_OFFSET(out) == static_cast<guint64>(i));
    CHECK(GST_BUFFER_FLAG_IS_SET(out, GST_BUFFER_FLAG_DELTA_UNIT) == (i == 2));
    CHECK(gst_buffer_memcmp(out, 0, vtestFrames()[i].data, kW * kH * 3) == 0);

    const Result r = resultOf(out);
    CHECK(r.width == kW);
    CHECK(r.height == kH);
    CHECK_FALSE(r.predicted);
    CHECK(r.ids.size() >= 2);  // vtest.avi shows several people at these frames
    CHECK(std::set<gint64>(r.ids.begin(), r.ids.end()).size() == r.ids.size());
    // One "person" ROI per pose, with DL Streamer's parameters.
    guint rois = 0;
    gpointer state = nullptr;
    GstMeta* m;
    while ((m = gst_buffer_iterate_meta_filtered(out, &state,
                                                 GST_VIDEO_REGION_OF_INTEREST_META_API_TYPE))) {
      auto* roi = reinterpret_cast<GstVideoRegionOfInterestMeta*>(m);
      CHECK(g_quark_to_string(roi->roi_type) == std::string("person"));
      GstStructure* det = gst_video_region_of_interest_meta_get_param(roi, "detection");
      GstStructure* obj = gst_video_region_of_interest_meta_get_param(roi, "object_id");
      REQUIRE(det != nullptr);
      REQUIRE(obj != nullptr);
      double x_min = -1, x_max = -1;
      gint id = -1;
      CHECK(gst_structure_get_double(det, "x_min", &x_min));
      CHECK(gst_structure_get_double(det, "x_max", &x_max));
      CHECK((0.0 <= x_min && x_min <= x_max && x_max <= 1.0));
      CHECK(gst_structure_get_int(obj, "id", &id));
      CHECK(std::count(r.ids.begin(), r.ids.end(), id) == 1);
      rois++;
    }
    CHECK(rois == r.ids.size());
    results.push_back(r);
    gst_buffer_unref(out);
  }
  // People walk slowly at 10 frames/s: most tracks of one frame continue in the next.
  for (size_t i = 1; i < results.size(); ++i) {
    const auto& a = results[i - 1].ids;
    const auto& b = results[i].ids;
    const auto kept = std::count_if(b.begin(), b.end(), [&](gint64 id) {
      return std::find(a.begin(), a.end(), id) != a.end();
    });
    CHECK(kept * 2 >= static_cast<long>(std::min(a.size(), b.size())));
  }
  gst_harness_teardown(h);
}

TEST_CASE("every listed format gives the poses of the BGR frame", "[plugin][track]") {
  initGst();
  if (!haveFrames()) return;
  GstHarness* ref = trackHarness();
  const Result expected = pushPull(ref, bufferOf(vtestFrames()[0], 0));
  gst_harness_teardown(ref);
  REQUIRE(!expected.ids.empty());

  const auto format = GENERATE(as<std::string>{}, "RGB", "RGBx", "BGRx", "xRGB", "xBGR", "RGBA",
                               "BGRA", "I420", "NV12");
  INFO("format " << format);
  GstHarness* h = gst_harness_new_parse(
      ("videoconvert ! capsfilter caps=video/x-raw,format=" + format + " ! jointflowtrack")
          .c_str());
  gst_harness_set_src_caps_str(h, capsFor("BGR", kW, kH).c_str());
  const Result r = pushPull(h, bufferOf(vtestFrames()[0], 0));
  gst_harness_teardown(h);
  const bool lossy = format == "I420" || format == "NV12";
  CHECK(std::abs(static_cast<int>(r.ids.size()) - static_cast<int>(expected.ids.size())) <=
        (lossy ? 1 : 0));
  // Each person of the BGR frame is found at the same place.
  int matched = 0;
  for (const auto& c : expected.centres)
    for (const auto& d : r.centres)
      if (cv::norm(c - d) < (lossy ? 8.f : 0.5f)) {
        matched++;
        break;
      }
  CHECK(matched >= static_cast<int>(expected.centres.size()) - (lossy ? 1 : 0));
}

// How many of the ids of `b` are ids of `a`.
long keptIds(const Result& a, const Result& b) {
  return std::count_if(b.ids.begin(), b.ids.end(), [&](gint64 id) {
    return std::find(a.ids.begin(), a.ids.end(), id) != a.ids.end();
  });
}

TEST_CASE("a flush and a new resolution start new tracks", "[plugin][track]") {
  initGst();
  if (!haveFrames()) return;
  GstHarness* h = trackHarness();
  std::vector<Result> before;
  for (int i = 0; i < 2; ++i) before.push_back(pushPull(h, bufferOf(vtestFrames()[i], i)));
  REQUIRE(maxId(before) > 0);

  REQUIRE(gst_harness_push_event(h, gst_event_new_flush_start()));
  REQUIRE(gst_harness_push_event(h, gst_event_new_flush_stop(TRUE)));
  GstSegment segment;
  gst_segment_init(&segment, GST_FORMAT_TIME);
  REQUIRE(gst_harness_push_event(h, gst_event_new_segment(&segment)));
  const Result after = pushPull(h, bufferOf(vtestFrames()[2], 2));
  REQUIRE(!after.ids.empty());
  for (gint64 id : after.ids) CHECK(id > maxId(before));  // ids are never given twice

  // A new resolution mid-stream: poses in the new frame's pixels, new tracks.
  cv::Mat half;
  cv::resize(vtestFrames()[3], half, cv::Size(kW / 2, kH / 2), 0, 0, cv::INTER_AREA);
  gst_harness_set_src_caps_str(h, capsFor("BGR", kW / 2, kH / 2).c_str());
  const Result small = pushPull(h, bufferOf(half, 3));
  CHECK(small.width == kW / 2);
  CHECK(small.height == kH / 2);
  for (gint64 id : small.ids) CHECK(id > maxId({before[0], before[1], after}));
  for (const auto& c : small.centres) CHECK((c.x < kW / 2 && c.y < kH / 2));
  gst_harness_teardown(h);
}

TEST_CASE("tracks live through DISCONT, PTS gaps, new segments and caps at the same size",
          "[plugin][track]") {
  // What a leaky queue, packet loss, concat or a renegotiation do to a live stream. The people of
  // vtest walk slowly: the tracks of frame 1 continue in frame 2 whatever came between.
  initGst();
  if (!haveFrames()) return;
  const std::string what =
      GENERATE(as<std::string>{}, "discont", "pts-gap", "segment", "format", "no-pts");
  INFO(what);
  GstHarness* h = trackHarness();
  std::vector<Result> before;
  for (int i = 0; i < 2; ++i) before.push_back(pushPull(h, bufferOf(vtestFrames()[i], i)));
  REQUIRE(before[1].ids.size() >= 3);
  // Frames 2, 3 and 4 are dropped for "pts-gap": frame 5 comes at its own time, flagged as a
  // discontinuity as a leaky queue or a decoder after packet loss flags it.
  const int index = what == "pts-gap" ? 5 : 2;
  GstBuffer* next = bufferOf(vtestFrames()[index], index);
  if (what == "discont" || what == "pts-gap") GST_BUFFER_FLAG_SET(next, GST_BUFFER_FLAG_DISCONT);
  if (what == "segment") {
    // A new segment without a flush, its running time going on (concat, splitmuxsrc).
    GstSegment segment;
    gst_segment_init(&segment, GST_FORMAT_TIME);
    segment.base = 0;
    REQUIRE(gst_harness_push_event(h, gst_event_new_segment(&segment)));
  }
  if (what == "format") {
    gst_buffer_unref(next);
    cv::Mat rgb;
    cv::cvtColor(vtestFrames()[index], rgb, cv::COLOR_BGR2RGB);
    gst_harness_set_src_caps_str(h, capsFor("RGB", kW, kH).c_str());
    next = bufferOf(rgb, index);
  }
  if (what == "no-pts") GST_BUFFER_PTS(next) = GST_CLOCK_TIME_NONE;
  const Result after = pushPull(h, next);
  INFO("before: " << before[1].ids.size() << " ids, after: " << after.ids.size());
  CHECK(keptIds(before[1], after) * 4 >= static_cast<long>(after.ids.size()) * 3);
  gst_harness_teardown(h);
}

TEST_CASE("inference-interval predicts the frames in between with the same tracks",
          "[plugin][track]") {
  initGst();
  if (!haveFrames()) return;
  GstHarness* h = trackHarness("inference-interval=3");
  std::vector<Result> r;
  for (int i = 0; i < 6; ++i) r.push_back(pushPull(h, bufferOf(vtestFrames()[i], i)));
  gst_harness_teardown(h);
  for (int i = 0; i < 6; ++i) {
    INFO("frame " << i);
    CHECK(r[i].predicted == (i % 3 != 0));
  }
  // Predicted frames carry the last inferred frame's tracks; from the second inference on they
  // move with the tracks' velocities.
  CHECK(r[1].ids == r[0].ids);
  CHECK(r[2].ids == r[0].ids);
  CHECK(r[4].ids == r[3].ids);
  CHECK(r[5].ids == r[3].ids);
  bool moved = false;
  for (size_t k = 0; k < r[3].ids.size(); ++k)
    moved |= cv::norm(r[4].centres[k] - r[3].centres[k]) > 0.1;
  CHECK(moved);
}

TEST_CASE("frames that downstream reports late are predicted, not inferred", "[plugin][track]") {
  initGst();
  if (!haveFrames()) return;
  GstHarness* h = trackHarness();
  const Result first = pushPull(h, bufferOf(vtestFrames()[0], 0));
  CHECK_FALSE(first.predicted);
  // The sink is one second late at running time 0: frames before 2 s (2 x the lateness, as
  // GstBaseTransform reckons) are late.
  REQUIRE(gst_harness_push_upstream_event(
      h, gst_event_new_qos(GST_QOS_TYPE_UNDERFLOW, 0.5, GST_SECOND, 0)));
  const Result late = pushPull(h, bufferOf(vtestFrames()[1], 1));
  CHECK(late.predicted);
  CHECK(late.ids == first.ids);
  // Back on time: inference again.
  REQUIRE(gst_harness_push_upstream_event(
      h, gst_event_new_qos(GST_QOS_TYPE_OVERFLOW, 1.0, -GST_SECOND / 10, GST_SECOND / 10)));
  CHECK_FALSE(pushPull(h, bufferOf(vtestFrames()[2], 2)).predicted);
  // skip-late-frames=false always infers.
  GstElement* track = gst_harness_find_element(h, "jointflowtrack");
  g_object_set(track, "skip-late-frames", FALSE, nullptr);
  gst_object_unref(track);
  REQUIRE(gst_harness_push_upstream_event(
      h, gst_event_new_qos(GST_QOS_TYPE_UNDERFLOW, 0.5, GST_SECOND, 0)));
  CHECK_FALSE(pushPull(h, bufferOf(vtestFrames()[3], 3)).predicted);
  gst_harness_teardown(h);
}

TEST_CASE("two instances in one process keep separate tracks", "[plugin][track]") {
  initGst();
  if (!haveFrames()) return;
  GstHarness* a = trackHarness();
  GstHarness* b = trackHarness();
  for (int i = 0; i < 3; ++i) {
    const Result ra = pushPull(a, bufferOf(vtestFrames()[i], i));
    const Result rb = pushPull(b, bufferOf(vtestFrames()[i], i));
    CHECK(ra.ids == rb.ids);  // each counts its own ids from 1
  }
  gst_harness_teardown(a);
  gst_harness_teardown(b);
}

TEST_CASE("repeated NULL-PLAYING-NULL cycles", "[plugin][track]") {
  initGst();
  GstElement* pipeline = gst_parse_launch(
      "videotestsrc num-buffers=2 pattern=ball ! video/x-raw,width=320,height=240 ! "
      "jointflowtrack ! fakesink",
      nullptr);
  REQUIRE(pipeline != nullptr);
  GstBus* bus = gst_element_get_bus(pipeline);
  for (int cycle = 0; cycle < 3; ++cycle) {
    INFO("cycle " << cycle);
    REQUIRE(gst_element_set_state(pipeline, GST_STATE_PLAYING) != GST_STATE_CHANGE_FAILURE);
    GstMessage* msg = gst_bus_timed_pop_filtered(
        bus, 60 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
    REQUIRE(msg != nullptr);
    CHECK(GST_MESSAGE_TYPE(msg) == GST_MESSAGE_EOS);
    gst_message_unref(msg);
    REQUIRE(gst_element_set_state(pipeline, GST_STATE_NULL) == GST_STATE_CHANGE_SUCCESS);
  }
  gst_object_unref(bus);
  gst_object_unref(pipeline);
}

TEST_CASE("a missing or corrupt model fails the state change with a message", "[plugin][track]") {
  initGst();
  const std::string corrupt =
      (std::filesystem::temp_directory_path() / "jointflow-corrupt-model.onnx").string();
  {
    std::ofstream out(corrupt, std::ios::binary);
    out << "this is not an ONNX model";
  }
  const std::string path = GENERATE_COPY(std::string("/nonexistent/pose-model.onnx"), corrupt);
  INFO("spatial-model " << path);
  GstElement* pipeline = gst_parse_launch(
      ("videotestsrc num-buffers=1 ! jointflowtrack spatial-model=" + path + " ! fakesink").c_str(),
      nullptr);
  REQUIRE(pipeline != nullptr);
  CHECK(gst_element_set_state(pipeline, GST_STATE_PAUSED) == GST_STATE_CHANGE_FAILURE);
  const std::string error = busError(pipeline);
  CHECK(error.find(path) != std::string::npos);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(pipeline);
}

namespace {

// The message of the LIBRARY/SETTINGS error with which `description` fails to start.
std::string settingsErrorAtStart(const char* description) {
  initGst();
  GstElement* pipeline = gst_parse_launch(description, nullptr);
  REQUIRE(pipeline != nullptr);
  CHECK(gst_element_set_state(pipeline, GST_STATE_PAUSED) == GST_STATE_CHANGE_FAILURE);
  GstBus* bus = gst_element_get_bus(pipeline);
  GstMessage* msg = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR);
  REQUIRE(msg != nullptr);
  GError* err = nullptr;
  gst_message_parse_error(msg, &err, nullptr);
  CHECK(g_error_matches(err, GST_LIBRARY_ERROR, GST_LIBRARY_ERROR_SETTINGS));
  const std::string text = err->message;
  g_error_free(err);
  gst_message_unref(msg);
  gst_object_unref(bus);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(pipeline);
  return text;
}

}  // namespace

TEST_CASE("values that only together are out of range fail the start with the setting named",
          "[plugin][track]") {
  // Each weight is within [0, 1], but with the default tff-flow-weight 0.25 the TFF's would be
  // negative: a settings error naming both, before any model is loaded.
  const std::string text = settingsErrorAtStart(
      "videotestsrc num-buffers=1 ! jointflowtrack tff-oks-weight=0.9 ! fakesink");
  CHECK(text.find("tff-flow-weight") != std::string::npos);
  CHECK(text.find("tff-oks-weight") != std::string::npos);
  // Tiles run each tile at one scale.
  const std::string tiles = settingsErrorAtStart(
      "videotestsrc num-buffers=1 ! jointflowtrack tiles=true scales=0.5,1 ! fakesink");
  CHECK(tiles.find("tiles") != std::string::npos);
  CHECK(tiles.find("scales") != std::string::npos);
}

TEST_CASE("tiles: auto by default; FALSE and TRUE, as when it was a boolean, are off and on",
          "[plugin][track]") {
  initGst();
  GstElement* track = gst_element_factory_make("jointflowtrack", nullptr);
  REQUIRE(track != nullptr);
  gst_object_ref_sink(track);
  GParamSpec* spec = g_object_class_find_property(G_OBJECT_GET_CLASS(track), "tiles");
  REQUIRE(G_IS_PARAM_SPEC_ENUM(spec));
  auto nick = [&] {
    gint value = -1;
    g_object_get(track, "tiles", &value, nullptr);
    const GEnumValue* v = g_enum_get_value(G_PARAM_SPEC_ENUM(spec)->enum_class, value);
    return std::string(v ? v->value_nick : "?");
  };
  CHECK(nick() == "auto");
  g_object_set(track, "tiles", FALSE, nullptr);  // an application written for the boolean
  CHECK(nick() == "false");
  g_object_set(track, "tiles", TRUE, nullptr);
  CHECK(nick() == "true");
  gst_object_unref(track);
}

TEST_CASE("nonsense property values are refused and the previous value kept", "[plugin][track]") {
  initGst();
  GstElement* track = gst_element_factory_make("jointflowtrack", nullptr);
  REQUIRE(track != nullptr);
  gst_object_ref_sink(track);
  // The defaults, read before the refused values are offered.
  gint max_persons = 0;
  gfloat threshold = 0;
  guint interval = 0;
  gchar* input_size = nullptr;
  gchar* scales = nullptr;
  g_object_get(track, "max-persons", &max_persons, "person-threshold", &threshold,
               "inference-interval", &interval, "input-size", &input_size, "scales", &scales,
               nullptr);
  const gint default_max_persons = max_persons;
  const gfloat default_threshold = threshold;
  const guint default_interval = interval;
  const std::string default_input_size = input_size, default_scales = scales;
  g_free(input_size);
  g_free(scales);

  WarningCounter warnings;
  g_object_set(track, "max-persons", 0, nullptr);
  g_object_set(track, "person-threshold", 1.5f, nullptr);
  g_object_set(track, "inference-interval", 0u, nullptr);
  g_object_set(track, "input-size", "banana", nullptr);
  g_object_set(track, "scales", "0,1", nullptr);
  g_object_set(track, "scales", "1,x", nullptr);
  CHECK(warnings.count == 6);
  CHECK(warnings.last.find("1,x") != std::string::npos);

  g_object_get(track, "max-persons", &max_persons, "person-threshold", &threshold,
               "inference-interval", &interval, "input-size", &input_size, "scales", &scales,
               nullptr);
  CHECK(max_persons == default_max_persons);
  CHECK(threshold == default_threshold);
  CHECK(interval == default_interval);
  CHECK(input_size == default_input_size);
  CHECK(scales == default_scales);
  g_free(input_size);
  g_free(scales);

  // Valid values are taken.
  g_object_set(track, "input-size", "320x240", "scales", "0.5,1", "max-persons", 4, nullptr);
  g_object_get(track, "input-size", &input_size, "scales", &scales, "max-persons", &max_persons,
               nullptr);
  CHECK(std::string(input_size) == "320x240");
  CHECK(std::string(scales) == "0.5,1");
  CHECK(max_persons == 4);
  CHECK(warnings.count == 6);
  g_free(input_size);
  g_free(scales);
  gst_object_unref(track);
}

namespace {

// The "jointflowtrack-stats" messages the element posted on @bus, oldest first.
std::vector<GstStructure*> statsMessages(GstBus* bus) {
  std::vector<GstStructure*> out;
  while (GstMessage* m = gst_bus_pop_filtered(bus, GST_MESSAGE_ELEMENT)) {
    const GstStructure* s = gst_message_get_structure(m);
    if (s && gst_structure_has_name(s, "jointflowtrack-stats"))
      out.push_back(gst_structure_copy(s));
    gst_message_unref(m);
  }
  return out;
}

guint64 u64(const GstStructure* s, const char* field) {
  guint64 v = 0;
  REQUIRE(gst_structure_get_uint64(s, field, &v));
  return v;
}

// A histogram field: its count, and its cumulative buckets as they must be (never decreasing,
// at most the count, bounds increasing).
guint64 histogramCount(const GstStructure* s, const char* field) {
  INFO(field);
  const GValue* v = gst_structure_get_value(s, field);
  REQUIRE(v != nullptr);
  REQUIRE(G_VALUE_TYPE(v) == GST_TYPE_STRUCTURE);
  const GstStructure* h = gst_value_get_structure(v);
  const guint64 count = u64(h, "count");
  const GValue* bounds = gst_structure_get_value(h, "bounds");
  const GValue* buckets = gst_structure_get_value(h, "buckets");
  REQUIRE(bounds != nullptr);
  REQUIRE(buckets != nullptr);
  REQUIRE(gst_value_array_get_size(bounds) == gst_value_array_get_size(buckets));
  REQUIRE(gst_value_array_get_size(bounds) > 0);
  guint64 previous = 0;
  double previous_bound = 0;
  for (guint i = 0; i < gst_value_array_get_size(buckets); ++i) {
    const guint64 b = g_value_get_uint64(gst_value_array_get_value(buckets, i));
    const double bound = g_value_get_double(gst_value_array_get_value(bounds, i));
    CHECK(b >= previous);
    CHECK(b <= count);
    CHECK(bound > previous_bound);
    previous = b;
    previous_bound = bound;
  }
  double sum = -1;
  REQUIRE(gst_structure_get_double(h, "sum", &sum));
  CHECK(sum >= 0);
  return count;
}

}  // namespace

TEST_CASE("stats-interval posts the figures every N seconds of stream time and at the end",
          "[plugin][track]") {
  initGst();
  if (!haveFrames()) return;
  // Frames 0.1 s apart (bufferOf). The first message is due 0.25 s after the first frame, so it
  // comes with frame 3 (0.3 s), the next with frame 5 (0.5 s); then one at EOS.
  GstHarness* h = trackHarness("stats-interval=0.25 inference-interval=2");
  GstBus* bus = gst_bus_new();
  gst_element_set_bus(h->element, bus);
  // Frames 4 and 5 carry the camera's capture time, 1 and 2 s before they are pushed on this
  // host's wall clock, as rtspsrc puts it (NTP, from 1900) and as a source on the host's own clock
  // would (Unix time). The wall time each push took is kept: the element reads the clock within
  // it, so the lag it reports lies between the offset and the offset plus that time, however
  // loaded the machine is.
  const auto wallNow = [] { return static_cast<double>(g_get_real_time()) / G_USEC_PER_SEC; };
  const struct {
    const char* reference;
    double epoch;  ///< the reference's zero, in Unix seconds
    double ago;
  } captured[] = {{"timestamp/x-ntp", -2208988800.0, 1.0}, {"timestamp/x-unix", 0.0, 2.0}};
  double push_seconds = 0;
  for (int i = 0; i < 6; ++i) {
    GstBuffer* buffer = bufferOf(vtestFrames()[i], i);
    const double before = wallNow();
    if (i >= 4) {
      const auto& c = captured[i - 4];
      GstCaps* reference = gst_caps_new_empty_simple(c.reference);
      gst_buffer_add_reference_timestamp_meta(
          buffer, reference, static_cast<GstClockTime>((before - c.ago - c.epoch) * GST_SECOND),
          GST_CLOCK_TIME_NONE);
      gst_caps_unref(reference);
    }
    pushPull(h, buffer);
    if (i >= 4) push_seconds += wallNow() - before;
  }
  std::vector<GstStructure*> during = statsMessages(bus);
  REQUIRE(gst_harness_push_event(h, gst_event_new_eos()));
  std::vector<GstStructure*> end = statsMessages(bus);
  gst_harness_teardown(h);
  gst_object_unref(bus);

  REQUIRE(during.size() == 2);
  REQUIRE(end.size() == 1);
  double t = 0;
  REQUIRE(gst_structure_get_double(during[0], "stream-time", &t));
  CHECK(t == Approx(0.3));
  REQUIRE(gst_structure_get_double(during[1], "stream-time", &t));
  CHECK(t == Approx(0.5));
  CHECK(u64(during[0], "frames") == 4);
  CHECK(u64(during[1], "frames") == 6);

  const GstStructure* s = end[0];
  // Every second frame inferred, the others predicted; every frame leaves once.
  CHECK(u64(s, "frames") == 6);
  CHECK(u64(s, "frames-inferred") == 3);
  CHECK(u64(s, "frames-predicted") == 3);
  CHECK(histogramCount(s, "inference-seconds") == 3);
  CHECK(histogramCount(s, "element-seconds") == 6);
  // vtest.avi's frames 100-105 have several people, each given an id.
  guint active = 0, lost = 99;
  REQUIRE(gst_structure_get_uint(s, "tracks-active", &active));
  REQUIRE(gst_structure_get_uint(s, "tracks-lost", &lost));
  CHECK(active >= 2);
  CHECK(u64(s, "tracks-created") >= active);
  // A harness answers the latency query as a live source: each frame's lag is measured.
  gboolean live = FALSE;
  REQUIRE(gst_structure_get_boolean(s, "live", &live));
  CHECK(live);
  CHECK(histogramCount(s, "lag-seconds") == 6);
  // The capture lag of the two frames that carried a capture time: 1 s and 2 s, plus at most the
  // time their pushes took (1 ms for the clock's and NTP's rounding). None before them.
  CHECK(!gst_structure_has_field(during[0], "capture-lag-seconds"));
  CHECK(histogramCount(s, "capture-lag-seconds") == 2);
  double capture_sum = 0;
  REQUIRE(gst_structure_get_double(
      gst_value_get_structure(gst_structure_get_value(s, "capture-lag-seconds")), "sum",
      &capture_sum));
  CHECK(capture_sum >= 3.0 - 1e-3);
  CHECK(capture_sum <= 3.0 + push_seconds + 1e-3);
  CHECK(std::string(gst_structure_get_string(s, "version")) == JOINTFLOW_VERSION);
  CHECK(std::string(gst_structure_get_string(s, "spatial-model")) == "movenet_multipose.onnx");
  CHECK(std::string(gst_structure_get_string(s, "model-type")) == "movenet");
  CHECK(std::string(gst_structure_get_string(s, "engine")).size() > 0);
  for (GstStructure* m : during) gst_structure_free(m);
  for (GstStructure* m : end) gst_structure_free(m);
}

TEST_CASE("stats-interval 0 posts nothing; a negative one is refused", "[plugin][track]") {
  initGst();
  if (!haveFrames()) return;
  GstHarness* h = trackHarness();
  GstElement* track = gst_harness_find_element(h, "jointflowtrack");
  REQUIRE(track != nullptr);
  WarningCounter warnings;
  g_object_set(track, "stats-interval", -1.0f, nullptr);
  CHECK(warnings.count == 1);
  gfloat interval = -2;
  g_object_get(track, "stats-interval", &interval, nullptr);
  CHECK(interval == 0.f);
  gst_object_unref(track);
  GstBus* bus = gst_bus_new();
  gst_element_set_bus(h->element, bus);
  for (int i = 0; i < 6; ++i) pushPull(h, bufferOf(vtestFrames()[i], i));
  REQUIRE(gst_harness_push_event(h, gst_event_new_eos()));
  CHECK(statsMessages(bus).empty());
  gst_harness_teardown(h);
  gst_object_unref(bus);
}
