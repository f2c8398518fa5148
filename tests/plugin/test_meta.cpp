// GstJointFlowMeta: the public API, and that the poses survive copies and scaling (videoscale)
// with coordinates that still fit the frame.
#include <catch2/catch.hpp>

#include <cstring>

#include "gst_test_util.hpp"
#include "jointflow/types.hpp"

using namespace jointflow::test;

TEST_CASE("the meta API stores and returns every pose of a frame", "[plugin][meta]") {
  initGst();
  GstBuffer* buffer = gst_buffer_new();
  REQUIRE(gst_buffer_get_jointflow_meta(buffer) == nullptr);
  GstJointFlowMeta* meta = gst_buffer_add_jointflow_meta(buffer, 640, 480);
  REQUIRE(meta != nullptr);
  CHECK(gst_jointflow_meta_get_n_persons(meta) == 0);

  JointFlowPerson a = person(3, 10, 20, 30, 40);
  a.keypoints[JOINTFLOW_KEYPOINT_LEFT_WRIST] = {12.5f, 33.f, 0.75f};
  gst_jointflow_meta_add_person(meta, &a);
  JointFlowPerson b = person(7, 100, 120, 50, 90);
  b.tentative = TRUE;
  gst_jointflow_meta_add_person(meta, &b);

  GstJointFlowMeta* read = gst_buffer_get_jointflow_meta(buffer);
  REQUIRE(read == meta);
  CHECK(read->width == 640);
  CHECK(read->height == 480);
  REQUIRE(gst_jointflow_meta_get_n_persons(read) == 2);
  const JointFlowPerson* p0 = gst_jointflow_meta_get_person(read, 0);
  CHECK(p0->track_id == 3);
  CHECK_FALSE(p0->tentative);
  CHECK(p0->keypoints[JOINTFLOW_KEYPOINT_LEFT_WRIST].x == 12.5f);
  CHECK(p0->keypoints[JOINTFLOW_KEYPOINT_LEFT_WRIST].score == 0.75f);
  CHECK(gst_jointflow_meta_get_person(read, 1)->tentative);
  CHECK(gst_jointflow_meta_get_person(read, 2) == nullptr);
  gst_buffer_unref(buffer);
}

TEST_CASE("keypoint names and the skeleton are the COCO ones", "[plugin][meta]") {
  REQUIRE(JOINTFLOW_N_KEYPOINTS == jointflow::kNumJoints);
  CHECK(std::strcmp(jointflow_keypoint_name(JOINTFLOW_KEYPOINT_NOSE), "nose") == 0);
  CHECK(std::strcmp(jointflow_keypoint_name(JOINTFLOW_KEYPOINT_RIGHT_ANKLE), "right_ankle") == 0);
  CHECK(jointflow_keypoint_name(JOINTFLOW_N_KEYPOINTS) == nullptr);
  CHECK(jointflow_keypoint_from_name("left_hip") == JOINTFLOW_KEYPOINT_LEFT_HIP);
  CHECK(jointflow_keypoint_from_name("tail") == -1);
  REQUIRE(jointflow_skeleton_get_n_limbs() == jointflow::kCocoSkeleton.size());
  guint a = 99, b = 99;
  REQUIRE(jointflow_skeleton_get_limb(0, &a, &b));
  CHECK(a < JOINTFLOW_N_KEYPOINTS);
  CHECK(b < JOINTFLOW_N_KEYPOINTS);
  CHECK_FALSE(jointflow_skeleton_get_limb(jointflow_skeleton_get_n_limbs(), &a, &b));
}

TEST_CASE("copying a buffer copies the poses", "[plugin][meta]") {
  initGst();
  GstBuffer* buffer = gst_buffer_new_allocate(nullptr, 16, nullptr);
  GstJointFlowMeta* meta = gst_buffer_add_jointflow_meta(buffer, 64, 48);
  meta->predicted = TRUE;
  JointFlowPerson p = person(5, 1, 2, 3, 4);
  gst_jointflow_meta_add_person(meta, &p);
  GstBuffer* copy = gst_buffer_copy(buffer);
  gst_buffer_unref(buffer);  // the copy must not share the persons array
  GstJointFlowMeta* m = gst_buffer_get_jointflow_meta(copy);
  REQUIRE(m != nullptr);
  CHECK(m->predicted);
  REQUIRE(gst_jointflow_meta_get_n_persons(m) == 1);
  CHECK(gst_jointflow_meta_get_person(m, 0)->track_id == 5);
  CHECK(gst_jointflow_meta_get_person(m, 0)->height == 4.f);
  gst_buffer_unref(copy);
}

TEST_CASE("videoscale scales the poses, videoconvert keeps them", "[plugin][meta]") {
  initGst();
  GstHarness* h = gst_harness_new_parse(
      "videoconvert ! videoscale ! capsfilter caps=video/x-raw,format=I420,width=160,height=60");
  gst_harness_set_src_caps_str(h, capsFor("RGB", 320, 240).c_str());
  GstBuffer* in = blackFrame("RGB", 320, 240, 0);
  GstJointFlowMeta* meta = gst_buffer_add_jointflow_meta(in, 320, 240);
  JointFlowPerson p = person(2, 100, 40, 60, 120);
  p.keypoints[JOINTFLOW_KEYPOINT_NOSE] = {130.f, 48.f, 0.9f};
  gst_jointflow_meta_add_person(meta, &p);
  REQUIRE(gst_harness_push(h, in) == GST_FLOW_OK);
  GstBuffer* out = gst_harness_pull(h);
  REQUIRE(out != nullptr);
  const GstJointFlowMeta* m = gst_buffer_get_jointflow_meta(out);
  REQUIRE(m != nullptr);
  CHECK(m->width == 160);
  CHECK(m->height == 60);
  REQUIRE(gst_jointflow_meta_get_n_persons(m) == 1);
  const JointFlowPerson* q = gst_jointflow_meta_get_person(m, 0);
  CHECK(q->track_id == 2);
  CHECK(q->x == Approx(50.f));
  CHECK(q->y == Approx(10.f));
  CHECK(q->width == Approx(30.f));
  CHECK(q->height == Approx(30.f));
  CHECK(q->keypoints[JOINTFLOW_KEYPOINT_NOSE].x == Approx(65.f));
  CHECK(q->keypoints[JOINTFLOW_KEYPOINT_NOSE].y == Approx(12.f));
  CHECK(q->keypoints[JOINTFLOW_KEYPOINT_NOSE].score == Approx(0.9f));
  gst_buffer_unref(out);
  gst_harness_teardown(h);
}
