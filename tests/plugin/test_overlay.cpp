// jointflowoverlay on synthetic meta: the skeleton is drawn in the track's colour where the limbs
// are, nothing elsewhere, in every format the element takes.
#include <catch2/catch.hpp>

#include <cstdlib>

#include "frame_painter.hpp"
#include "gst_test_util.hpp"

using namespace jointflow::test;

namespace {

constexpr int kW = 96, kH = 64;
constexpr gint64 kId = 4;

// One person whose only visible limb is the left upper arm, horizontal from (20,30) to (70,30).
GstBuffer* frameWithArm(const std::string& format) {
  GstBuffer* buffer = blackFrame(format, kW, kH, 0);
  GstJointFlowMeta* meta = gst_buffer_add_jointflow_meta(buffer, kW, kH);
  JointFlowPerson p = person(kId, 10, 20, 70, 30);
  p.keypoints[JOINTFLOW_KEYPOINT_LEFT_SHOULDER] = {20.f, 30.f, 0.9f};
  p.keypoints[JOINTFLOW_KEYPOINT_LEFT_ELBOW] = {70.f, 30.f, 0.9f};
  gst_jointflow_meta_add_person(meta, &p);
  return buffer;
}

GstBuffer* drawn(const std::string& format, GstBuffer* in, const char* props = "") {
  GstHarness* h = gst_harness_new_parse((std::string("jointflowoverlay ") + props).c_str());
  gst_harness_set_src_caps_str(h, capsFor(format, kW, kH).c_str());
  REQUIRE(gst_harness_push(h, in) == GST_FLOW_OK);
  GstBuffer* out = gst_harness_pull(h);
  gst_harness_teardown(h);
  REQUIRE(out != nullptr);
  return out;
}

struct Pixel {
  int c[4] = {0, 0, 0, 0};
};

// The values of the pixel (x, y) on each component (R, G, B or Y, U, V).
Pixel pixelAt(const std::string& format, GstBuffer* buffer, int x, int y) {
  GstVideoInfo info;
  gst_video_info_set_format(&info, gst_video_format_from_string(format.c_str()), kW, kH);
  GstVideoFrame frame;
  REQUIRE(gst_video_frame_map(&frame, &info, buffer, GST_MAP_READ));
  Pixel px;
  for (guint c = 0; c < 3; ++c) {
    const int cx = GST_VIDEO_FORMAT_INFO_SCALE_WIDTH(info.finfo, c, x);
    const int cy = GST_VIDEO_FORMAT_INFO_SCALE_HEIGHT(info.finfo, c, y);
    const auto* row = static_cast<const guint8*>(GST_VIDEO_FRAME_COMP_DATA(&frame, c)) +
                      cy * GST_VIDEO_FRAME_COMP_STRIDE(&frame, c);
    px.c[c] = row[cx * GST_VIDEO_FRAME_COMP_PSTRIDE(&frame, c)];  // COMP_DATA has the offset
  }
  gst_video_frame_unmap(&frame);
  return px;
}

bool near(int a, double b, int tolerance) {
  return std::abs(a - b) <= tolerance;
}

}  // namespace

TEST_CASE("overlay draws the limb in the track colour and leaves the rest", "[plugin][overlay]") {
  initGst();
  const jointflow::gst::Rgb colour = jointflow::gst::colourForId(kId);
  const auto format = GENERATE(as<std::string>{}, "RGB", "BGR", "RGBx", "BGRx", "xRGB", "xBGR",
                               "RGBA", "BGRA", "I420", "NV12");
  INFO("format " << format);
  GstBuffer* out = drawn(format, frameWithArm(format), "draw-ids=false trail-length=0");
  const Pixel on = pixelAt(format, out, 45, 30);
  const Pixel off = pixelAt(format, out, 45, 55);
  if (format == "I420" || format == "NV12") {
    const double y = 16 + 0.257 * colour.r + 0.504 * colour.g + 0.098 * colour.b;
    const double u = 128 - 0.148 * colour.r - 0.291 * colour.g + 0.439 * colour.b;
    const double v = 128 + 0.439 * colour.r - 0.368 * colour.g - 0.071 * colour.b;
    CHECK(near(on.c[0], y, 2));
    CHECK(near(on.c[1], u, 2));
    CHECK(near(on.c[2], v, 2));
    CHECK(off.c[0] == 16);
    CHECK(off.c[1] == 128);
    CHECK(off.c[2] == 128);
  } else {
    CHECK(on.c[0] == colour.r);
    CHECK(on.c[1] == colour.g);
    CHECK(on.c[2] == colour.b);
    CHECK(off.c[0] + off.c[1] + off.c[2] == 0);
  }
  gst_buffer_unref(out);
}

TEST_CASE("overlay draws boxes when asked, and different ids in different colours",
          "[plugin][overlay]") {
  initGst();
  CHECK_FALSE((jointflow::gst::colourForId(1).r == jointflow::gst::colourForId(2).r &&
               jointflow::gst::colourForId(1).g == jointflow::gst::colourForId(2).g &&
               jointflow::gst::colourForId(1).b == jointflow::gst::colourForId(2).b));
  GstBuffer* plain = drawn("RGB", frameWithArm("RGB"), "draw-ids=false");
  GstBuffer* boxed = drawn("RGB", frameWithArm("RGB"), "draw-ids=false draw-boxes=true");
  // The box's bottom edge runs along y = 50, well away from the arm.
  CHECK(pixelAt("RGB", plain, 40, 50).c[0] + pixelAt("RGB", plain, 40, 50).c[1] == 0);
  CHECK(pixelAt("RGB", boxed, 40, 50).c[0] == jointflow::gst::colourForId(kId).r);
  gst_buffer_unref(plain);
  gst_buffer_unref(boxed);
}

TEST_CASE("overlay draws a motion trail behind a moving track, and forgets it after a flush",
          "[plugin][overlay]") {
  initGst();
  GstHarness* h = gst_harness_new_parse("jointflowoverlay draw-ids=false trail-length=10");
  gst_harness_set_src_caps_str(h, capsFor("RGB", kW, kH).c_str());
  // A box whose bottom centre (the trail's anchor) moves from (20,50) to (70,50), no keypoints.
  GstBuffer* out = nullptr;
  for (int i = 0; i < 2; ++i) {
    GstBuffer* in = blackFrame("RGB", kW, kH, i * GST_SECOND / 30);
    JointFlowPerson p = person(kId, 10.f + 50.f * i, 10, 20, 40);
    gst_jointflow_meta_add_person(gst_buffer_add_jointflow_meta(in, kW, kH), &p);
    REQUIRE(gst_harness_push(h, in) == GST_FLOW_OK);
    if (out) gst_buffer_unref(out);
    out = gst_harness_pull(h);
  }
  const jointflow::gst::Rgb colour = jointflow::gst::colourForId(kId);
  // On the trail between the two anchors: a 1-pixel anti-aliased line, so nearly the colour.
  CHECK(pixelAt("RGB", out, 45, 50).c[1] > colour.g * 3 / 4);
  gst_buffer_unref(out);

  // After a flush the old position is forgotten: no trail from a single point.
  REQUIRE(gst_harness_push_event(h, gst_event_new_flush_start()));
  REQUIRE(gst_harness_push_event(h, gst_event_new_flush_stop(TRUE)));
  GstSegment segment;
  gst_segment_init(&segment, GST_FORMAT_TIME);
  REQUIRE(gst_harness_push_event(h, gst_event_new_segment(&segment)));
  GstBuffer* in = blackFrame("RGB", kW, kH, 0);
  JointFlowPerson p = person(kId, 60, 10, 20, 40);
  gst_jointflow_meta_add_person(gst_buffer_add_jointflow_meta(in, kW, kH), &p);
  REQUIRE(gst_harness_push(h, in) == GST_FLOW_OK);
  out = gst_harness_pull(h);
  CHECK(pixelAt("RGB", out, 45, 50).c[1] == 0);
  gst_buffer_unref(out);
  gst_harness_teardown(h);
}

TEST_CASE("overlay falls back to region-of-interest meta", "[plugin][overlay]") {
  initGst();
  GstBuffer* in = blackFrame("RGB", kW, kH, 0);
  GstVideoRegionOfInterestMeta* roi =
      gst_buffer_add_video_region_of_interest_meta(in, "person", 10, 10, 40, 40);
  gst_video_region_of_interest_meta_add_param(
      roi, gst_structure_new("object_id", "id", G_TYPE_INT, 9, nullptr));
  GstBuffer* out = drawn("RGB", in, "draw-ids=false");
  const jointflow::gst::Rgb colour = jointflow::gst::colourForId(9);
  const Pixel edge = pixelAt("RGB", out, 10, 30);  // left edge of the box
  CHECK(edge.c[0] == colour.r);
  CHECK(edge.c[1] == colour.g);
  CHECK(edge.c[2] == colour.b);
  CHECK(pixelAt("RGB", out, 30, 30).c[0] == 0);  // inside the box
  gst_buffer_unref(out);
}
