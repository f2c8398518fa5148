// COCO-17 -> PoseTrack joints (derived neck and head top) and PoseTrack track ids.
#include <cmath>
#include <set>

#include <catch2/catch.hpp>

#include "../test_env.hpp"
#include "jointflow/error.hpp"
#include "jointflow/posetrack.hpp"
#include "jointflow/posetrack_joints.hpp"

using namespace jointflow;
using namespace jointflow::posetrack;

namespace {

Pose uprightPose() {
  Pose pose;
  for (int j = 0; j < kNumJoints; ++j) pose.keypoints[j] = {float(j), float(200 + j), 0.9f};
  pose.keypoints[kLeftShoulder] = {20.f, 100.f, 0.8f};
  pose.keypoints[kRightShoulder] = {0.f, 100.f, 0.6f};
  pose.keypoints[kNose] = {10.f, 60.f, 0.7f};
  pose.keypoints[kLeftEye] = {14.f, 56.f, 0.9f};
  pose.keypoints[kRightEye] = {6.f, 56.f, 0.9f};
  return pose;
}

}  // namespace

TEST_CASE("COCO joints map onto PoseTrack ids; neck and head top are derived", "[eval][joints]") {
  const PoseTrackJoints pt = toPoseTrackJoints(uprightPose(), 0.1f);
  REQUIRE(pt[kPtRightAnkle]);
  CHECK(pt[kPtRightAnkle]->x == Approx(kRightAnkle));
  CHECK(pt[kPtLeftWrist]->y == Approx(200 + kLeftWrist));
  // Shoulder midpoint (10, 100), nose (10, 60): v = (0, -40); shoulder width 20, normal up.
  REQUIRE(pt[kPtNeck]);
  CHECK(pt[kPtNeck]->x == Approx(10.0));
  CHECK(pt[kPtNeck]->y == Approx(100.0 - kNeckAlongFace * 40.0));
  CHECK(*pt[kPtNeck]->score == Approx(0.6));  // the weaker shoulder (the nose scores 0.7)
  REQUIRE(pt[kPtHeadTop]);
  CHECK(pt[kPtHeadTop]->x == Approx(10.0));
  const double from_face = 60.0 - kHeadTopExtension * 40.0;
  const double from_shoulders = 100.0 - kHeadTopAboveShoulders * 20.0;
  CHECK(pt[kPtHeadTop]->y == Approx(0.5 * (from_face + from_shoulders)));
  CHECK(*pt[kPtHeadTop]->score == Approx(0.6));
}

TEST_CASE("the head top falls back to the eyes; joints below the threshold are not written",
          "[eval][joints]") {
  Pose pose = uprightPose();
  pose.keypoints[kNose].score = 0.f;
  pose.keypoints[kLeftKnee].score = 0.05f;
  PoseTrackJoints pt = toPoseTrackJoints(pose, 0.1f);
  CHECK_FALSE(pt[kPtNose]);
  CHECK_FALSE(pt[kPtLeftKnee]);
  REQUIRE(pt[kPtHeadTop]);  // the eyes' midpoint (10, 56) is the face point: v = (0, -44)
  CHECK(pt[kPtHeadTop]->y ==
        Approx(0.5 * (56.0 - kHeadTopExtension * 44.0 + 100.0 - kHeadTopAboveShoulders * 20.0)));
  CHECK(pt[kPtNeck]->y == Approx(100.0 - kNeckAlongFace * 44.0));
  for (int j : {kLeftEye, kRightEye, kLeftEar, kRightEar}) pose.keypoints[j].score = 0.f;
  pt = toPoseTrackJoints(pose, 0.1f);  // no face point: the neck is the shoulder midpoint
  REQUIRE(pt[kPtNeck]);
  CHECK(pt[kPtNeck]->y == Approx(100.0));
  CHECK_FALSE(pt[kPtHeadTop]);
  pose = uprightPose();
  pose.keypoints[kRightShoulder].score = 0.f;  // no neck, so no head top either
  pt = toPoseTrackJoints(pose, 0.1f);
  CHECK_FALSE(pt[kPtNeck]);
  CHECK_FALSE(pt[kPtHeadTop]);
  pose.keypoints[kLeftShoulder].score = 0.95f;
  pose.keypoints[kRightShoulder].score = 0.5f;
  CHECK_FALSE(toPoseTrackJoints(pose, 0.6f)[kPtNeck]);  // the derived score is thresholded too
}

TEST_CASE("PoseTrack names map onto ids; the ears are not scored", "[eval][joints]") {
  CHECK(poseTrackJointFromName("head_bottom") == kPtNeck);
  CHECK(poseTrackJointFromName("head_top") == kPtHeadTop);
  CHECK(poseTrackJointFromName("right_ankle") == kPtRightAnkle);
  CHECK_FALSE(poseTrackJointFromName("left_ear"));
  CHECK_FALSE(poseTrackJointFromName("neck"));  // not a 2018 keypoint name
}

TEST_CASE("track ids map into 0..999, unique per frame and stable per track", "[eval][joints]") {
  TrackIdMap map;
  CHECK(map.assign({17, 18, 5}) == std::vector<int>{0, 1, 2});
  CHECK(map.assign({5, 17}) == std::vector<int>{2, 0});
  CHECK(map.assign({18, 40}) == std::vector<int>{1, 3});  // 18 kept its number while missing
  // 3000 more tracks, 7 at a time: always in range and unique within the frame.
  std::int64_t next = 100;
  for (int f = 0; f < 3000 / 7; ++f) {
    std::vector<std::int64_t> ids{5};
    for (int k = 0; k < 6; ++k) ids.push_back(next++);
    const std::vector<int> numbers = map.assign(ids);
    CHECK(numbers[0] == 2);  // a track present throughout never changes number
    const std::set<int> unique(numbers.begin(), numbers.end());
    CHECK(unique.size() == numbers.size());
    CHECK(*unique.begin() >= 0);
    CHECK(*unique.rbegin() <= 999);
  }
  CHECK_THROWS_AS(map.assign({1, 1}), Error);
  CHECK_THROWS_AS(map.assign(std::vector<std::int64_t>(1001, 0)), Error);
}

TEST_CASE("without a face point the shoulder midpoint is within PCKh@0.5 of most necks",
          "[eval][joints][data]") {
  const std::string path =
      test::dataDir() + "/bonn-posetrack/annotations/test/060470979_bonn_test.json";
  JF_REQUIRE_PATH_OR_SKIP(path);
  int total = 0, within = 0;
  for (const auto& frame : readSequence(path).frames) {
    for (const auto& person : frame.people) {
      const auto& l = person.joints[kPtLeftShoulder];
      const auto& r = person.joints[kPtRightShoulder];
      const auto& neck = person.joints[kPtNeck];
      if (!l || !r || !neck || !person.head_box) continue;
      Pose pose;
      pose.keypoints[kLeftShoulder] = {float(l->x), float(l->y), 1.f};
      pose.keypoints[kRightShoulder] = {float(r->x), float(r->y), 1.f};
      const auto derived = toPoseTrackJoints(pose, 0.1f)[kPtNeck];
      const auto& b = *person.head_box;
      const double head = 0.6 * std::hypot(b.x2 - b.x1, b.y2 - b.y1);
      ++total;
      within += std::hypot(derived->x - neck->x, derived->y - neck->y) <= 0.5 * head ? 1 : 0;
    }
  }
  REQUIRE(total == 164);
  INFO(within << " of " << total);
  CHECK(within >= 0.6 * total);
}

TEST_CASE("the fitted rule puts neck and head top where PoseTrack 2018 annotates them",
          "[eval][joints][data]") {
  // The 13 people of the PoseTrack 2018 fixtures with nose, head_bottom, head_top and both
  // shoulders, the rule applied to their annotated nose and shoulders (training/
  // fit_head_joints.py fitted it partly on them: this checks the C++ against the fit). The
  // previous rule (neck = shoulder midpoint, head top from the nose alone) had 11 of 13 necks
  // and 7 of 13 head tops within PCKh@0.5.
  const std::string path = test::dataDir() + "/posetrack18-fixtures/annotations/val";
  JF_REQUIRE_PATH_OR_SKIP(path);
  int total = 0, necks = 0, tops = 0;
  for (const std::string& file : listSequenceFiles(path)) {
    for (const auto& frame : readSequence(file).frames) {
      for (const auto& person : frame.people) {
        const auto& j = person.joints;
        if (!j[kPtLeftShoulder] || !j[kPtRightShoulder] || !j[kPtNose] || !j[kPtNeck] ||
            !j[kPtHeadTop] || !person.head_box)
          continue;
        Pose pose;
        for (auto [coco, pt] : {std::pair{kLeftShoulder, kPtLeftShoulder},
                                {kRightShoulder, kPtRightShoulder},
                                {kNose, kPtNose}})
          pose.keypoints[coco] = {float(j[pt]->x), float(j[pt]->y), 1.f};
        const PoseTrackJoints derived = toPoseTrackJoints(pose, 0.1f);
        const auto& b = *person.head_box;
        const double radius = 0.5 * 0.6 * std::hypot(b.x2 - b.x1, b.y2 - b.y1);
        auto near = [&](int k) {
          return std::hypot(derived[k]->x - j[k]->x, derived[k]->y - j[k]->y) <= radius;
        };
        ++total;
        necks += near(kPtNeck) ? 1 : 0;
        tops += near(kPtHeadTop) ? 1 : 0;
      }
    }
  }
  REQUIRE(total == 13);
  INFO(necks << " necks and " << tops << " head tops of " << total << " within PCKh@0.5");
  CHECK(necks == 13);
  CHECK(tops >= 10);
}
