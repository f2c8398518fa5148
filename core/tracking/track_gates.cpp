// Where a track's person may be: the position gate, the path, the view (track_book.hpp).
#include <algorithm>
#include <cmath>

#include "track_book.hpp"

namespace jointflow::track_book {
namespace {

// The point of the segment a-b nearest to p, and its distance from p: how far a pose lies from the
// path a lost track's person took if they went on at their speed for any part of the time they were
// hidden, and then stopped or turned back. A constant-velocity prediction alone assumes they kept
// walking: on the identity benchmark's occluder a person walked behind the bar, the play turned
// back, and they came out where they had gone in, 355 px from the prediction (gate 253 px).
cv::Point2f nearestOnPath(cv::Point2f p, cv::Point2f a, cv::Point2f b) {
  const cv::Point2f ab = b - a;
  const float length2 = ab.dot(ab);
  const float t = length2 > 0.f ? std::clamp((p - a).dot(ab) / length2, 0.f, 1.f) : 0.f;
  return a + t * ab;
}

float distanceToPath(cv::Point2f p, cv::Point2f a, cv::Point2f b) {
  return static_cast<float>(cv::norm(p - nearestOnPath(p, a, b)));
}

}  // namespace

// The person walked out of the view: the track's predicted centre lies outside the frame (of
// this size; empty = not known, nobody counts as gone).
bool leftView(const Track& t, cv::Size frame) {
  const cv::Point2f c = t.motion.centre();
  return !frame.empty() && (c.x < 0.f || c.y < 0.f || c.x >= frame.width || c.y >= frame.height);
}

// How far from the path they were on a hidden person can have strayed, in their heights per
// second hidden (a walker covers about 0.8 of their height a second).
constexpr float kStrayHeightsPerSecond = 1.f;

// A track's position gate, px: 3 standard deviations of its predicted centre plus half the
// person's height, but no more than half the height plus kStrayHeightsPerSecond for each second
// since the track was last seen (`hidden`). The motion model's uncertainty grows with the
// square of the time, and after seconds it spans most of the frame: on vtest.avi a track lost
// for 3 s mid-view had a gate of 574 px (6.7 heights) and took a man in a striped sweater who
// came in 358 px from its path (appearance 0.88).
float positionGate(const Track& t, double hidden) {
  const float h = t.motion.height();
  return std::min(3.f * t.motion.positionSigma(),
                  kStrayHeightsPerSecond * h * static_cast<float>(hidden)) +
         0.5f * h;
}

// How far a pose's centre lies from the track's path (distanceToPath), px.
float pathDistance(const Track& t, const Pose& pose) {
  return distanceToPath(poseCentre(pose), t.motion.lastSeenCentre(), t.motion.centre());
}

// The track's predicted pose moved along its path to where it best fits the pose: the point of
// the path nearest to the prediction moved by the mean offset of the joints both show. Why the
// joints and not the centres: a person coming out from behind someone shows their head and
// shoulders first, whose keypoint box centre lies 0.4 heights above the whole body's.
Pose poseOnPath(const Track& t, const Pose& pose) {
  const cv::Matx23f none(1, 0, 0, 0, 1, 0);
  const Pose predicted = t.motion.pose();
  const cv::Point2f centre = t.motion.centre();
  // With no joint in common the offset is 0 and the prediction stays where it is (the path's end).
  const cv::Point2f at =
      nearestOnPath(centre + meanMotion(predicted, pose, none), t.motion.lastSeenCentre(), centre);
  return movePose(predicted, none, at - centre);
}

}  // namespace jointflow::track_book
