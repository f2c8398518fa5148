// jointflowjsonwriter: one JSON object per frame with the documented fields (the schema outside
// tools rely on), the video passed through untouched, and a clear error for a bad location.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gst_test_util.hpp"
#include "jointflow/types.hpp"

using namespace jointflow::test;

namespace {

std::vector<nlohmann::json> readLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<nlohmann::json> lines;
  std::string line;
  while (std::getline(in, line)) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

}  // namespace

TEST_CASE("JSON Lines records hold frame, timestamp, resolution and named keypoints",
          "[plugin][json]") {
  initGst();
  const std::string path =
      (std::filesystem::temp_directory_path() / "jointflow-test-writer.jsonl").string();
  GstHarness* h = gst_harness_new_parse(("jointflowjsonwriter location=" + path).c_str());
  gst_harness_set_src_caps_str(h, capsFor("RGB", 64, 48).c_str());

  GstBuffer* first = blackFrame("RGB", 64, 48, 0);
  GstJointFlowMeta* meta = gst_buffer_add_jointflow_meta(first, 64, 48);
  JointFlowPerson p = person(12, 8, 4, 32, 40);
  p.tentative = TRUE;
  p.keypoints[JOINTFLOW_KEYPOINT_RIGHT_KNEE] = {20.f, 30.f, 0.5f};
  gst_jointflow_meta_add_person(meta, &p);
  // A person reaching past the left and bottom borders: the box is cut at the frame, as the ROI
  // meta cuts it (person_box.hpp); x, y, w, h stay the tracker's.
  JointFlowPerson border = person(13, -10, 20, 30, 40);
  border.previous_track_id = 7;  // recognised late: shown as 7 until this frame
  gst_jointflow_meta_add_person(meta, &border);
  GstBuffer* second = blackFrame("RGB", 64, 48, GST_SECOND / 30);  // no meta: no objects
  GstBuffer* third = blackFrame("RGB", 64, 48, GST_CLOCK_TIME_NONE);
  gst_buffer_add_jointflow_meta(third, 64, 48);

  for (GstBuffer* b : {first, second, third}) {
    GstBuffer* expected = b;
    REQUIRE(gst_harness_push(h, b) == GST_FLOW_OK);
    GstBuffer* out = gst_harness_pull(h);
    CHECK(out == expected);  // passed through, not copied
    gst_buffer_unref(out);
  }
  gst_harness_teardown(h);

  const auto lines = readLines(path);
  REQUIRE(lines.size() == 3);
  for (size_t i = 0; i < lines.size(); ++i) {
    CHECK(lines[i].at("frame") == i);
    CHECK(lines[i].at("resolution").at("width") == 64);
    CHECK(lines[i].at("resolution").at("height") == 48);
    CHECK(lines[i].at("objects").is_array());
  }
  CHECK(lines[0].at("timestamp") == 0);
  CHECK(lines[1].at("timestamp") == GST_SECOND / 30);
  CHECK(lines[2].at("timestamp").is_null());
  CHECK(lines[1].at("objects").empty());
  CHECK(lines[2].at("objects").empty());

  REQUIRE(lines[0].at("objects").size() == 2);
  const auto& cut = lines[0].at("objects")[1].at("detection").at("bounding_box");
  CHECK(cut.at("x_min").get<double>() == 0.0);
  CHECK(cut.at("x_max").get<double>() == Approx(20.0 / 64));
  CHECK(cut.at("y_min").get<double>() == Approx(20.0 / 48));
  CHECK(cut.at("y_max").get<double>() == 1.0);
  CHECK(lines[0].at("objects")[1].at("x") == -10);
  CHECK(lines[0].at("objects")[1].at("previous_id") == 7);
  CHECK_FALSE(lines[0].at("objects")[0].contains("previous_id"));  // only a person recognised late
  const auto& o = lines[0].at("objects")[0];
  CHECK(o.at("id") == 12);
  CHECK(o.at("tentative") == true);
  CHECK(o.at("confidence").get<float>() == Approx(0.9f));
  CHECK(o.at("x") == 8);
  CHECK(o.at("y") == 4);
  CHECK(o.at("w") == 32);
  CHECK(o.at("h") == 40);
  const auto& bbox = o.at("detection").at("bounding_box");
  CHECK(bbox.at("x_min").get<double>() == Approx(8.0 / 64));
  CHECK(bbox.at("y_max").get<double>() == Approx(44.0 / 48));
  CHECK(o.at("detection").at("label") == "person");
  const auto& kps = o.at("keypoints");
  REQUIRE(kps.size() == jointflow::kNumJoints);
  for (const auto name : jointflow::kJointNames) {
    INFO("keypoint " << name);
    const auto& k = kps.at(std::string(name));
    CHECK(k.contains("x"));
    CHECK(k.contains("y"));
    CHECK(k.contains("score"));
  }
  CHECK(kps.at("right_knee").at("x") == 20);
  CHECK(kps.at("right_knee").at("score") == 0.5);
  CHECK(kps.at("nose").at("score") == 0);
  std::filesystem::remove(path);
}

TEST_CASE("a location that cannot be written fails the state change with a message",
          "[plugin][json]") {
  initGst();
  GstElement* pipeline = gst_parse_launch(
      "videotestsrc num-buffers=1 ! jointflowjsonwriter location=/nonexistent-dir/x.jsonl ! "
      "fakesink",
      nullptr);
  REQUIRE(pipeline != nullptr);
  CHECK(gst_element_set_state(pipeline, GST_STATE_PAUSED) == GST_STATE_CHANGE_FAILURE);
  CHECK(busError(pipeline).find("/nonexistent-dir/x.jsonl") != std::string::npos);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(pipeline);
}
