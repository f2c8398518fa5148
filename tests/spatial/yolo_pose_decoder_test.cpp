// The YOLO pose decoder on synthetic outputs whose answer is known exactly: threshold, overlap
// suppression, layout, coordinates, joint order, more people than MoveNet's decoders ever meet.
#include <catch2/catch.hpp>

#include "jointflow/error.hpp"
#include "yolo_pose_output.hpp"

using namespace jointflow;
using test::YoloAnchor;
using test::yoloPerson;

namespace {

// 70 people of 40x80 px in a 10 x 7 grid, 60 px apart sideways (no two overlap), each with a
// second anchor 2 px aside scoring a little less (IoU 0.905: a duplicate), one more person 16 px
// beside the first (IoU 0.43: a neighbour in a crowd), and anchors below the threshold.
struct Crowd {
  std::vector<YoloAnchor> people;   // the ones to find
  std::vector<YoloAnchor> anchors;  // what the network says
};

Crowd crowd() {
  Crowd c;
  for (int i = 0; i < 70; ++i) {
    const float cx = 40.f + 60.f * (i % 10), cy = 60.f + 100.f * (i / 10);
    const YoloAnchor p = yoloPerson(cx, cy, 40.f, 80.f, 0.3f + 0.005f * i);
    YoloAnchor dup = yoloPerson(cx + 2.f, cy, 40.f, 80.f, p.score - 0.001f);
    c.people.push_back(p);
    c.anchors.push_back(dup);  // before the person: the order of anchors must not matter
    c.anchors.push_back(p);
    c.anchors.push_back(yoloPerson(cx, cy + 30.f, 40.f, 80.f, 0.2f));  // below 0.25
  }
  const YoloAnchor neighbour = yoloPerson(40.f + 16.f, 60.f, 40.f, 80.f, 0.26f);
  c.people.push_back(neighbour);
  c.anchors.push_back(neighbour);
  return c;
}

void checkPose(const Pose& got, const YoloAnchor& want) {
  INFO("person at " << want.cx << ", " << want.cy);
  CHECK(got.score == want.score);
  // Ultralytics' pixel edges to JointFlow's pixel centres: -0.5 on every position.
  CHECK(got.box.x == want.cx - 0.5f * want.w - 0.5f);
  CHECK(got.box.y == want.cy - 0.5f * want.h - 0.5f);
  CHECK(got.box.w == want.w);
  CHECK(got.box.h == want.h);
  for (int j = 0; j < kNumJoints; ++j) {
    INFO("joint " << j);
    CHECK(got.keypoints[j].x == want.joints[j].x - 0.5f);
    CHECK(got.keypoints[j].y == want.joints[j].y - 0.5f);
    CHECK(got.keypoints[j].score == want.joints[j].score);
  }
}

// {1, N, 56}: the same values, anchor by anchor.
cv::Mat transposed(const cv::Mat& out) {
  const int n = out.size[2];
  cv::Mat t(std::vector<int>{1, n, kYoloPoseValues}, CV_32F);
  for (int v = 0; v < kYoloPoseValues; ++v)
    for (int a = 0; a < n; ++a) t.ptr<float>(0, a)[v] = out.ptr<float>(0, v)[a];
  return t;
}

}  // namespace

TEST_CASE("YOLO pose decoding keeps one pose per person of a crowd, best first, exactly") {
  const Crowd c = crowd();
  const cv::Mat out = test::yoloOutput(c.anchors, 1008);  // a 256x192 input's 1008 anchors
  YoloPoseDecodeOptions o;
  o.max_persons = 100;
  for (const bool transpose : {false, true}) {
    INFO((transpose ? "{1, N, 56}" : "{1, 56, N}"));
    const Poses poses = decodeYoloPose(transpose ? transposed(out) : out, o);
    REQUIRE(poses.size() == 71);
    // Highest score first: the grid's people from the last to the first, then the neighbour.
    for (int i = 0; i < 70; ++i) checkPose(poses[i], c.people[69 - i]);
    checkPose(poses[70], c.people[70]);
  }
}

TEST_CASE("YOLO pose decoding: candidates, ties, the cap and the threshold") {
  const Crowd c = crowd();
  const cv::Mat out = test::yoloOutput(c.anchors, 300);
  SECTION("candidates are every anchor at or above the threshold, in anchor order") {
    const Poses all = yoloPoseCandidates(out, 0.2f);
    CHECK(all.size() == c.anchors.size());
    CHECK(all[1].score == c.anchors[1].score);
    CHECK(yoloPoseCandidates(out, 0.25f).size() == 141);  // people, duplicates, neighbour
  }
  SECTION("max_persons keeps the best") {
    YoloPoseDecodeOptions o;
    o.max_persons = 10;
    const Poses poses = decodeYoloPose(out, o);
    REQUIRE(poses.size() == 10);
    for (int i = 0; i < 10; ++i) checkPose(poses[i], c.people[69 - i]);
  }
  SECTION("of two equal boxes with one score, the earlier anchor stays") {
    YoloAnchor a = yoloPerson(100.f, 100.f, 40.f, 80.f, 0.5f), b = a;
    b.joints[0].x += 3.f;
    const Poses poses = decodeYoloPose(test::yoloOutput({a, b}, 84), {});
    REQUIRE(poses.size() == 1);
    CHECK(poses[0].keypoints[0].x == a.joints[0].x - 0.5f);
  }
  SECTION("a lower IoU limit merges the neighbour into the first person") {
    YoloPoseDecodeOptions o;
    o.nms_iou = 0.4f;
    CHECK(decodeYoloPose(out, o).size() == 70);
  }
}

TEST_CASE("YOLO pose decoding refuses an output of another shape") {
  const cv::Mat detection(std::vector<int>{1, 84, 300}, CV_32F, cv::Scalar(0));  // boxes + 80
  CHECK_THROWS_WITH(decodeYoloPose(detection, {}),
                    Catch::Contains("{1, 56, N}") && Catch::Contains("1x84x300"));
  const cv::Mat maps(std::vector<int>{1, 56, 10, 10}, CV_32F, cv::Scalar(0));
  CHECK_THROWS_AS(decodeYoloPose(maps, {}), Error);
  CHECK_THROWS_AS(decodeYoloPose(cv::Mat(), {}), Error);
}
