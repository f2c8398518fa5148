// The identity benchmark's floor (bench/ground_truth_ids.hpp): poses re-labelled with the ground
// truth's ids make no id switch where the tracker's ids swapped, keep the switches a pose that
// holds joints of two people makes whatever its id, and a pose of nobody gets an id no person has.
#include <catch2/catch.hpp>

#include "ground_truth_ids.hpp"
#include "jointflow/evaluation.hpp"

using namespace jointflow;
using namespace jointflow::bench;
namespace pt = jointflow::posetrack;

namespace {

/// A person standing at x: every joint 10 px apart down a column, head box 20 px wide (a head
/// size of 0.6 x 28.3 = 17 px: joints within 8.5 px match).
pt::Person standing(double x, std::int64_t id, bool ground_truth) {
  pt::Person p;
  p.track_id = id;
  for (int j = 0; j < pt::kNumPoseTrackJoints; ++j) {
    pt::PoseTrackPoint q;
    q.x = x;
    q.y = 100.0 + 10.0 * j;
    if (!ground_truth) q.score = 0.9;
    p.joints[j] = q;
  }
  if (ground_truth) p.head_box = pt::HeadBox{x - 10, 80, x + 10, 100};
  return p;
}

/// Two people at x = 100 and 300 for `frames` frames (ground truth ids 1 and 2).
pt::Sequence twoPeople(int frames) {
  pt::Sequence s;
  s.name = "two";
  for (int f = 0; f < frames; ++f) {
    pt::Frame frame;
    frame.file_name = "images/" + std::to_string(f) + ".jpg";
    frame.image_id = frame.frame_id = f;
    frame.people = {standing(100, 1, true), standing(300, 2, true)};
    s.frames.push_back(frame);
  }
  return s;
}

std::int64_t switches(const pt::Sequence& gt, const pt::Sequence& pred) {
  return evaluatePoseTrack({gt}, {pred}).total.counts.switches;
}

}  // namespace

TEST_CASE("ground-truth ids undo a tracker's swap", "[ground-truth-ids]") {
  const pt::Sequence gt = twoPeople(6);
  pt::Sequence pred = gt;
  for (size_t f = 0; f < pred.frames.size(); ++f) {
    const bool swapped = f >= 3;  // the tracker swaps the two ids from frame 3 on
    pred.frames[f].people = {standing(100, swapped ? 8 : 7, false),
                             standing(300, swapped ? 7 : 8, false)};
  }
  REQUIRE(switches(gt, pred) == 2 * pt::kNumPoseTrackJoints);
  const pt::Sequence floor = withGroundTruthIds(gt, pred);
  CHECK(switches(gt, floor) == 0);
  CHECK(floor.frames[4].people[0].track_id == 1);
  CHECK(floor.frames[4].people[1].track_id == 2);
}

TEST_CASE("a pose holding joints of two people keeps its switches under ground-truth ids",
          "[ground-truth-ids]") {
  const pt::Sequence gt = twoPeople(6);
  pt::Sequence pred = gt;
  for (size_t f = 0; f < pred.frames.size(); ++f) {
    pt::Person a = standing(100, 7, false), b = standing(300, 8, false);
    if (f == 3) {
      // frame 3: person 1's pose takes person 2's last 4 joints, and person 2's pose loses them
      for (int j = pt::kNumPoseTrackJoints - 4; j < pt::kNumPoseTrackJoints; ++j) {
        a.joints[j] = b.joints[j];
        b.joints[j].reset();
      }
    }
    pred.frames[f].people = {a, b};
  }
  const pt::Sequence floor = withGroundTruthIds(gt, pred);
  // person 2's 4 joints are matched to pose 1 (id 1) in frame 3 and back to pose 2 after it
  CHECK(switches(gt, floor) == 2 * 4);
  CHECK(switches(gt, floor) == switches(gt, pred));
}

TEST_CASE("a pose of nobody gets an id no person has", "[ground-truth-ids]") {
  const pt::Sequence gt = twoPeople(3);
  pt::Sequence pred = gt;
  for (pt::Frame& f : pred.frames)
    f.people = {standing(100, 5, false), standing(300, 6, false), standing(600, 1, false)};
  const pt::Sequence floor = withGroundTruthIds(gt, pred);
  for (const pt::Frame& f : floor.frames) {
    REQUIRE(f.people.size() == 3);
    CHECK(f.people[0].track_id == 1);
    CHECK(f.people[1].track_id == 2);
    CHECK(*f.people[2].track_id > 2);
  }
  CHECK(floor.frames[0].people[2].track_id != floor.frames[1].people[2].track_id);
}

TEST_CASE("person id switches count a person under a new id once, not once per joint",
          "[ground-truth-ids]") {
  const pt::Sequence gt = twoPeople(8);
  pt::Sequence pred = gt;
  for (size_t f = 0; f < pred.frames.size(); ++f) {
    // Person 1 is shown under id 9 in frame 3 and under its own id 7 again after it; person 2
    // is not found in frames 5-6 and comes back under its id 8: a miss is not a switch.
    pred.frames[f].people = {standing(100, f == 3 ? 9 : 7, false)};
    if (f < 5 || f > 6) pred.frames[f].people.push_back(standing(300, 8, false));
  }
  CHECK(switches(gt, pred) == 2 * pt::kNumPoseTrackJoints);
  CHECK(personIdSwitches(gt, pred) == 2);
  CHECK(personIdSwitches(gt, withGroundTruthIds(gt, pred)) == 0);
  CHECK(personIdSwitches(gt, gt) == 0);
}
