// PosePredictor: poses between inferences move on with each track's own velocity, joints that
// were not seen do not move, and extrapolation stops at the horizon.
#include <catch2/catch.hpp>

#include "pose_predictor.hpp"

using jointflow::TrackedPose;
using jointflow::gst::PosePredictor;

namespace {

TrackedPose at(std::int64_t id, float x, float y) {
  TrackedPose t;
  t.track_id = id;
  t.tentative = false;
  for (auto& k : t.pose.keypoints) k = {x, y, 0.8f};
  t.pose.keypoints[jointflow::kNose].score = 0.f;  // not detected
  t.pose.box = {x - 10, y - 20, 20, 40};
  t.pose.score = 0.7f;
  return t;
}

}  // namespace

TEST_CASE("predicted poses move with the track's velocity", "[plugin][predict]") {
  PosePredictor predictor(10);
  predictor.observe({at(1, 100, 50), at(2, 10, 10)}, 0);
  // Track 1 moves 6 px right and 3 px down over 3 frames; track 2 stands still; 3 is new.
  predictor.observe({at(1, 106, 53), at(2, 10, 10), at(3, 300, 300)}, 3);

  const auto p = predictor.predict(5);
  REQUIRE(p.size() == 3);
  CHECK(p[0].track_id == 1);
  CHECK(p[0].pose.keypoints[jointflow::kLeftHip].x == Approx(110.f));
  CHECK(p[0].pose.keypoints[jointflow::kLeftHip].y == Approx(55.f));
  CHECK(p[0].pose.keypoints[jointflow::kNose].x == Approx(106.f));  // unseen joint stays
  CHECK(p[0].pose.box.x == Approx(100.f));
  CHECK(p[0].pose.score == Approx(0.7f));
  CHECK_FALSE(p[0].tentative);
  CHECK(p[1].pose.keypoints[jointflow::kLeftHip].x == Approx(10.f));
  CHECK(p[2].track_id == 3);  // no velocity yet: holds
  CHECK(p[2].pose.keypoints[jointflow::kLeftHip].x == Approx(300.f));

  // Beyond the horizon (10 frames) the pose holds where it got to.
  CHECK(predictor.predict(13).at(0).pose.keypoints[jointflow::kLeftHip].x == Approx(126.f));
  CHECK(predictor.predict(40).at(0).pose.keypoints[jointflow::kLeftHip].x == Approx(126.f));
}

TEST_CASE("tracks gone from the last inference are not predicted; reset forgets all",
          "[plugin][predict]") {
  PosePredictor predictor;
  predictor.observe({at(1, 0, 0), at(2, 5, 5)}, 0);
  predictor.observe({at(2, 6, 5)}, 1);
  const auto p = predictor.predict(2);
  REQUIRE(p.size() == 1);
  CHECK(p[0].track_id == 2);
  CHECK(p[0].pose.keypoints[jointflow::kLeftHip].x == Approx(7.f));
  predictor.reset();
  CHECK(predictor.predict(3).empty());
}
