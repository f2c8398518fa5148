// PoseAssociator: the online track book. One function per step of pose_associator.hpp's list;
// update() calls them in order.
#include "jointflow/pose_associator.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>
#include <optional>
#include <string>

#include <opencv2/video/tracking.hpp>

#include "camera_motion.hpp"
#include "jointflow/appearance.hpp"
#include "jointflow/error.hpp"
#include "jointflow/matching.hpp"
#include "jointflow/similarity.hpp"
#include "motion_model.hpp"
#include "one_euro_filter.hpp"

namespace jointflow {
namespace {

enum class TrackState {
  kActive,  ///< matched on the previous inferred frame
  kLost,    ///< not matched since `last_time`; predicted, may be re-identified
};

/// A confirmed track that ended (lost for longer than lost_time): what a person coming back
/// later is recognised by (reentry_time).
struct Departed {
  std::int64_t output_id = -1;
  Descriptor appearance;
  double time = 0.0;  ///< when its track ended
};

struct Track {
  std::int64_t id = 0;          ///< internal, unique
  std::int64_t output_id = -1;  ///< assigned when first reported
  TrackState state = TrackState::kActive;
  MotionModel motion;  ///< the one motion model: prediction in current-frame pixels
  Pose last;           ///< the last detection, in the pixels of the frame it was made in
  Descriptor appearance;
  double start_time = 0.0;
  double last_time = 0.0;  ///< time of the last match
  int start_frame = 0;
  int hits = 0;                        ///< frames matched
  std::vector<OneEuroFilter> filters;  ///< x, y per joint (smoothing only)
  /// Where a track revived from the departed (re-entry) has its output id from: given back if the
  /// track ends before it is confirmed (a false detection must not use it up).
  std::optional<Departed> revived;
  /// The internal id of a confirmed track that was lost where this one was born (its position
  /// gate held the birth), or -1: this track is not shown while that one may still take it.
  std::int64_t contested_by = -1;

  Track(std::int64_t id_, const Pose& detection) : id(id_), motion(detection), last(detection) {}
};

// What one frame's matching steps decide: the track of each input pose, the tracks matched.
struct FrameMatches {
  std::vector<int> track_of;  ///< input pose -> track index, -1 = none
  std::vector<bool> matched;  ///< track index -> matched in this frame
};

JointThresholds thresholdsOf(const TrackerSettings& s) {
  JointThresholds t;
  t.fill(s.joint_threshold);
  if (!s.joint_thresholds.empty())
    std::copy(s.joint_thresholds.begin(), s.joint_thresholds.end(), t.begin());
  return t;
}

SimilarityOptions similarityOptionsOf(const TrackerSettings& s) {
  SimilarityOptions o;
  o.thresholds = thresholdsOf(s);
  o.tau_delta = s.tau_delta;
  o.line_samples = s.line_samples;
  o.sigma_flow = s.sigma_flow;
  return o;
}

void checkPoses(const Poses& poses) {
  for (size_t i = 0; i < poses.size(); ++i)
    for (int j = 0; j < kNumJoints; ++j) {
      const Keypoint& k = poses[i].keypoints[j];
      if (!std::isfinite(k.x) || !std::isfinite(k.y) || !std::isfinite(k.score))
        throw Error("association: pose " + std::to_string(i) + ", joint " +
                    std::string(kJointNames[j]) + " has a non-finite coordinate or score");
    }
}

// Sub-matrix of potentials for the chosen rows and columns.
Potentials select(const Potentials& p, const std::vector<int>& rows, const std::vector<int>& cols) {
  Potentials out{
      cv::Mat::zeros(static_cast<int>(rows.size()), static_cast<int>(cols.size()), CV_32F),
      cv::Mat::zeros(static_cast<int>(rows.size()), static_cast<int>(cols.size()), CV_32F)};
  for (size_t r = 0; r < rows.size(); ++r)
    for (size_t c = 0; c < cols.size(); ++c) {
      out.psi.at<float>(r, c) = p.psi.at<float>(rows[r], cols[c]);
      out.per_joint.at<float>(r, c) = p.per_joint.at<float>(rows[r], cols[c]);
    }
  return out;
}

// The person walked out of the view: the track's predicted centre lies outside the frame (of
// this size; empty = not known, nobody counts as gone).
bool leftView(const Track& t, cv::Size frame) {
  const cv::Point2f c = t.motion.centre();
  return !frame.empty() && (c.x < 0.f || c.y < 0.f || c.x >= frame.width || c.y >= frame.height);
}

cv::Point2f centreOf(const Pose& p) {
  const Box b = p.keypointBox(1e-12f);
  return {b.x + b.w / 2, b.y + b.h / 2};
}

// Re-identification accepts a pose up to this factor taller or shorter than the track: the
// keypoint box of a person partly seen (joints below their threshold, half out of view, coming
// out from behind something) is shorter than the person. At 1.5 a walker on vtest.avi who came
// back after 1.2 s with appearance 0.97, 84 px from the prediction, was refused at 0.667.
constexpr float kReidHeightRatio = 2.f;
// Updates over which the frame interval (for tentativeLostTime) is taken.
constexpr size_t kIntervals = 9;
// A pose that looks very like the track (appearance >= kReidStrongSimilarity) may lie half a
// height further from the prediction than the gate allows: a shaken camera's motion estimate errs
// by tens of pixels on some frames, and on the identity benchmark's shake a person who came back
// after one missed frame with appearance 0.94, 122 px from the prediction (gate 117 px), got a
// new id. Identity bench, oks: shake 18 -> 4 joint id switches, occluder 119 -> 116, vtest.avi
// unchanged (docs/identity.md).
constexpr float kReidStrongSimilarity = 0.9f;
constexpr float kReidStrongGateHeights = 0.5f;
// Added to a step-5 score where the position backs the pose (scores are at most 1).
constexpr float kPlacedRank = 1.f;

// Re-entry (step 6): the best departed person must lead the next one by this much, and at most
// this many departed people are kept (the oldest go first).
constexpr float kReentryMargin = 0.03f;
constexpr size_t kMaxDeparted = 64;

// Distance from p to the segment a-b: how far a pose lies from the path a lost track's person
// took if they went on at their speed for any part of the time they were hidden, and then stopped
// or turned back. A constant-velocity prediction alone assumes they kept walking: on the identity
// benchmark's occluder a person walked behind the bar, the play turned back, and they came out
// where they had gone in, 355 px from the prediction (gate 253 px).
float distanceToPath(cv::Point2f p, cv::Point2f a, cv::Point2f b) {
  const cv::Point2f ab = b - a;
  const float length2 = ab.dot(ab);
  const float t = length2 > 0.f ? std::clamp((p - a).dot(ab) / length2, 0.f, 1.f) : 0.f;
  return static_cast<float>(cv::norm(p - (a + t * ab)));
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
  return distanceToPath(centreOf(pose), t.motion.lastSeenCentre(), t.motion.centre());
}

// A free pose whose box lies almost wholly inside the box of a matched pose is a part of that
// person (MoveNet finds a second, partial person in the same body) or someone hidden behind them:
// its appearance is pooled over the person in front, so it cannot say whose it is. Identity bench,
// shake (oks): a free pose half as tall as a matched one, wholly inside its box, looked a little
// more like the track of someone lost beside it (gain 0.14), and the trade cost 28 joint id
// switches; the trades that were right covered at most half of the free pose (dropped 0.52,
// vtest.avi 0.41).
bool liesWithin(const Pose& inner, const Pose& outer) {
  constexpr float kWithin = 0.8f;
  return intersectionArea(inner.box, outer.box) > kWithin * inner.box.area();
}

}  // namespace

struct PoseAssociator::Impl {
  TrackerSettings settings;
  JointThresholds thresholds{};
  std::unique_ptr<Similarity> similarity;
  std::unique_ptr<Similarity> geometric;  ///< OKS: fallback, lost tracks, missing TFF/flow
  cv::Ptr<cv::DISOpticalFlow> optical_flow;
  std::vector<Track> tracks;
  std::vector<Departed> departed;      ///< ended confirmed tracks, oldest first (reentry_time)
  std::vector<std::int64_t> reported;  ///< internal ids reported by the last update, in order
  cv::Mat previous_grey;
  CameraMotionTracker camera_tracker;  ///< the previous frame's search image and points
  cv::Matx23f camera{1, 0, 0, 0, 1, 0};
  std::int64_t next_id = 1;
  std::int64_t next_output_id = 1;
  int frame = 0;
  double time = 0.0;  ///< of the last frame
  /// The stream time between the last updates, s, newest last (at most kIntervals).
  std::deque<double> intervals;
  int time_fallbacks = 0;

  double frameTime(double t);
  double tentativeLostTime() const;
  /// Re-entry is on: departed people are remembered and recognised (it needs an appearance).
  bool reentry() const {
    return settings.reentry_time > 0.f && settings.reid != AppearanceModel::kOff;
  }
  void depart(const Track& t);
  /// Matched on min_track_length frames: no longer tentative.
  bool confirmed(const Track& t) const { return t.hits >= settings.min_track_length; }
  /// The track's position gate now (positionGate for the time since it was last seen).
  float gate(const Track& t) const { return positionGate(t, time - t.last_time); }
  /// The pose lies within the track's gate of its path (where the track's person may be now).
  bool inGate(const Track& t, const Pose& pose) const { return pathDistance(t, pose) <= gate(t); }
  std::int64_t contestingTrack(const Pose& pose, cv::Size view, const FrameMatches& m) const;
  bool stillContested(const Track& t, const FrameMatches& m) const;
  std::vector<int> filterDetections(const Poses& poses) const;
  cv::Mat denseFlow(const AssociationFrame& in);
  void estimateCamera(const AssociationFrame& in, const cv::Mat& flow,
                      const std::vector<int>& dets);
  void predictTracks(double dt);
  cv::Mat temporalFlow(const AssociationFrame& in) const;
  void matchActive(const AssociationFrame& in, const cv::Mat& tff, const cv::Mat& flow,
                   const std::vector<int>& high, const std::vector<int>& low,
                   FrameMatches& m) const;
  void undoSwaps(const Poses& poses, const std::vector<Descriptor>& appearance, FrameMatches& m);
  float swapGain(const Track& a, const Descriptor& pose_a, const Track& b,
                 const Descriptor& pose_b) const;
  void restartAt(Track& t, const Pose& pose) const;
  void giveBackToUnmatched(const Poses& poses, const std::vector<int>& high,
                           const std::vector<Descriptor>& appearance, FrameMatches& m);
  float predictionOks(const Track& t, const Pose& pose) const;
  void matchLost(const Poses& poses, cv::Size frame, const std::vector<int>& high,
                 const std::vector<Descriptor>& appearance, FrameMatches& m) const;
  void birth(const Poses& poses, cv::Size view, const std::vector<int>& high,
             const std::vector<Descriptor>& appearance, FrameMatches& m);
  std::vector<TrackedPose> lifecycle(const Poses& poses, const std::vector<Descriptor>& appearance,
                                     const FrameMatches& m);
  TrackedPose report(Track& t, const Pose& pose, int detection);
  Pose smooth(Track& t, const Pose& pose, double dt) const;
};

// The frame's stream time; a missing time or one not after the previous frame's is taken one
// nominal frame later, so that time never stands still or runs back.
double PoseAssociator::Impl::frameTime(double t) {
  if (frame > 1 && !(std::isfinite(t) && t > time)) {
    ++time_fallbacks;
    return time + 1.0 / settings.frame_rate;
  }
  if (frame == 1 && !std::isfinite(t)) {
    ++time_fallbacks;
    return 0.0;
  }
  return t;
}

// Step 1: minimum size, duplicates, at most max_persons; returns indices of the kept poses.
std::vector<int> PoseAssociator::Impl::filterDetections(const Poses& poses) const {
  std::vector<int> order(poses.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return poses[a].score > poses[b].score; });
  std::vector<int> kept;
  for (int i : order) {
    const Pose& p = poses[i];
    Pose detected = p;
    for (int j = 0; j < kNumJoints; ++j)
      if (!isDetected(p.keypoints[j], thresholds[j])) detected.keypoints[j].score = 0.f;
    if (detected.countVisible(1e-12f) == 0) continue;  // nothing to associate
    const Box box = detected.keypointBox(0.f);
    if (std::max(box.w, box.h) < settings.min_person_size) continue;
    bool duplicate = false;
    if (settings.duplicate_oks > 0.f)
      for (int k : kept) duplicate |= oks(poses[k], p, thresholds) >= settings.duplicate_oks;
    if (duplicate) continue;
    kept.push_back(i);
    if (static_cast<int>(kept.size()) == settings.max_persons) break;
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

// Dense optical flow previous -> current, for the "flow" similarity.
cv::Mat PoseAssociator::Impl::denseFlow(const AssociationFrame& in) {
  cv::Mat flow;
  if (!similarity->needsFlow() || previous_grey.empty() || previous_grey.size() != in.grey.size())
    return flow;
  if (!optical_flow) optical_flow = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_MEDIUM);
  optical_flow->calc(previous_grey, in.grey, flow);
  return flow;
}

// Step 2: the camera motion, with the people's boxes left out of the fit.
void PoseAssociator::Impl::estimateCamera(const AssociationFrame& in, const cv::Mat& flow,
                                          const std::vector<int>& dets) {
  camera = cv::Matx23f(1, 0, 0, 0, 1, 0);
  if (!settings.camera_compensation) return;
  std::vector<Box> people;
  for (int d : dets) people.push_back(in.poses[d].box);
  for (const Track& t : tracks) people.push_back(t.motion.pose().box);
  if (!flow.empty()) {
    camera = cameraMotionFromFlow(flow, people);
    camera_tracker.reset();  // flow is missing only where the tracker has no previous frame
  } else {
    camera = camera_tracker.update(in.grey, people);  // an empty frame resets it
  }
}

// Step 3: every track follows the camera, then its own motion over dt seconds.
void PoseAssociator::Impl::predictTracks(double dt) {
  for (Track& t : tracks) {
    t.motion.applyCamera(camera);
    t.motion.predict(dt);
  }
}

// The TFF of this frame ("tff"): the one given, or the one computed on camera-compensated maps.
cv::Mat PoseAssociator::Impl::temporalFlow(const AssociationFrame& in) const {
  if (!similarity->needsTff() || !in.tff.empty() || !in.tff_after_camera) return in.tff;
  return in.tff_after_camera(camera);
}

// Step 4: the tracks matched on the previous inferred frame.
void PoseAssociator::Impl::matchActive(const AssociationFrame& in, const cv::Mat& tff,
                                       const cv::Mat& flow, const std::vector<int>& high,
                                       const std::vector<int>& low, FrameMatches& m) const {
  std::vector<int> active;
  for (size_t t = 0; t < tracks.size(); ++t)
    if (tracks[t].state == TrackState::kActive) active.push_back(static_cast<int>(t));
  std::vector<int> dets(high);
  dets.insert(dets.end(), low.begin(), low.end());
  if (active.empty() || dets.empty()) return;

  Poses current;
  for (int d : dets) current.push_back(in.poses[d]);
  // The TFF and the flow carry the apparent motion from where the joints were in the previous
  // frame (a TFF computed on camera-compensated maps: from there moved by the camera); the
  // geometric similarities compare with the prediction instead.
  const bool lacks =
      (similarity->needsTff() && tff.empty()) || (similarity->needsFlow() && flow.empty());
  const Similarity& primary = lacks ? *geometric : *similarity;
  const bool from_last = !lacks && (similarity->needsTff() || similarity->needsFlow());
  const bool compensated_tff = similarity->needsTff() && in.tff.empty();
  Poses previous;
  for (int t : active)
    previous.push_back(!from_last        ? tracks[t].motion.pose()
                       : compensated_tff ? movePose(tracks[t].last, camera, {0.f, 0.f})
                                         : tracks[t].last);
  // Without a TFF or flow between the two frames (the grid changed, a frame came without its
  // map) the geometric similarity stands in for this one frame.
  const Potentials all = primary.compute(previous, current, {tff, in.grid_to_frame, flow});

  const auto high_end = static_cast<int>(high.size());
  for (const bool high_pass : {true, false}) {
    std::vector<int> rows, cols;
    for (size_t r = 0; r < active.size(); ++r)
      if (!m.matched[active[r]]) rows.push_back(static_cast<int>(r));
    for (int c = high_pass ? 0 : high_end;
         c < (high_pass ? high_end : static_cast<int>(dets.size())); ++c)
      cols.push_back(c);
    if (rows.empty() || cols.empty()) continue;
    const Potentials p = select(all, rows, cols);
    for (const Match& mt :
         matchPoses(settings.matcher, p.psi, p.per_joint, settings.min_potential)) {
      m.matched[active[rows[mt.row]]] = true;
      m.track_of[dets[cols[mt.col]]] = active[rows[mt.row]];
    }
  }

  if (!settings.geometric_fallback) return;
  std::vector<int> rows, cols;
  for (int t : active)
    if (!m.matched[t]) rows.push_back(t);
  for (int d : high)
    if (m.track_of[d] < 0) cols.push_back(d);
  if (rows.empty() || cols.empty()) return;
  cv::Mat psi =
      cv::Mat::zeros(static_cast<int>(rows.size()), static_cast<int>(cols.size()), CV_32F);
  for (size_t r = 0; r < rows.size(); ++r)
    for (size_t c = 0; c < cols.size(); ++c)
      psi.at<float>(static_cast<int>(r), static_cast<int>(c)) =
          predictionOks(tracks[rows[r]], in.poses[cols[c]]);
  for (const Match& mt : matchPoses(settings.matcher, psi, psi, settings.coast_min_oks)) {
    m.matched[rows[mt.row]] = true;
    m.track_of[cols[mt.col]] = rows[mt.row];
  }
}

// Step 4, last: two confirmed tracks whose poses each look more like the other track (by more
// than swap_margin in all), and lie within its position gate, take each other's pose. Why: two
// people walking side by side or crossing are one box apart, and position, OKS, the TFF and the
// flow can all hand each track the other's pose for a frame; the tracks then go on with the
// wrong people. On vtest.avi (oks, `jointflow-track`) a man in a red and navy jacket and a
// blonde woman in a black coat walking side by side swapped ids at frame 148: his track's look
// against her pose 0.97, hers against his 0.97, each against its own 0.83 and 0.87 (gain 0.24).
// The swap is judged on the sum of both pairs, not pose by pose: a person half hidden behind the
// other shows the front one's coat, which raises both pairings of that pose alike.
void PoseAssociator::Impl::undoSwaps(const Poses& poses, const std::vector<Descriptor>& appearance,
                                     FrameMatches& m) {
  if (settings.swap_margin <= 0.f) return;
  std::vector<int> pose_of(tracks.size(), -1);
  for (size_t d = 0; d < m.track_of.size(); ++d)
    if (m.track_of[d] >= 0) pose_of[m.track_of[d]] = static_cast<int>(d);
  // A pose can be compared with a track when both have an appearance (swapGain).
  auto describable = [&](size_t t) {
    return pose_of[t] >= 0 && confirmed(tracks[t]) && !tracks[t].appearance.empty() &&
           !appearance[pose_of[t]].empty();
  };
  struct Swap {
    float gain;
    int a, b;
  };
  std::vector<Swap> swaps;
  for (size_t a = 0; a < tracks.size(); ++a)
    for (size_t b = a + 1; b < tracks.size(); ++b) {
      if (!describable(a) || !describable(b)) continue;
      const Track &ta = tracks[a], &tb = tracks[b];
      const Pose &pa = poses[pose_of[a]], &pb = poses[pose_of[b]];
      if (!inGate(ta, pb) || !inGate(tb, pa)) continue;
      const float gain = swapGain(ta, appearance[pose_of[a]], tb, appearance[pose_of[b]]);
      if (gain > settings.swap_margin)
        swaps.push_back({gain, static_cast<int>(a), static_cast<int>(b)});
    }
  // The surest first; a track takes part in one swap at most.
  std::sort(swaps.begin(), swaps.end(),
            [](const Swap& x, const Swap& y) { return x.gain > y.gain; });
  std::vector<bool> swapped(tracks.size(), false);
  for (const Swap& s : swaps) {
    if (swapped[s.a] || swapped[s.b]) continue;
    swapped[s.a] = swapped[s.b] = true;
    std::swap(m.track_of[pose_of[s.a]], m.track_of[pose_of[s.b]]);
    // Each motion model starts again at its new pose: whose path it followed is not known (the
    // position may have handed the poses over frames ago or in this one). Kept, a model jumps to
    // the other person's place; swapped with the poses, the same is wrong the other way round.
    // vtest.avi: a man in a black coat whose swap was undone, kept with his model, was hidden for
    // a frame and his track ran on that jump to a man entering at the border (identity bench,
    // oks: 20 ids against 19 with the restart).
    for (const int t : {s.a, s.b}) restartAt(tracks[t], poses[pose_of[t == s.a ? s.b : s.a]]);
  }
}

// How much more alike two tracks and two poses are paired the other way round: the appearance
// similarities of a with pose_b and b with pose_a, less those of a with pose_a and b with pose_b;
// 0 unless all four are positive (a part seen in both), or a pose with no colour seen would count
// as unlike anyone.
float PoseAssociator::Impl::swapGain(const Track& a, const Descriptor& pose_a, const Track& b,
                                     const Descriptor& pose_b) const {
  const float own_a = appearanceSimilarity(a.appearance, pose_a),
              own_b = appearanceSimilarity(b.appearance, pose_b),
              cross_a = appearanceSimilarity(a.appearance, pose_b),
              cross_b = appearanceSimilarity(b.appearance, pose_a);
  if (std::min({own_a, own_b, cross_a, cross_b}) <= 0.f) return 0.f;
  return cross_a + cross_b - own_a - own_b;
}

// A track that takes a pose another track followed starts its motion model again there.
void PoseAssociator::Impl::restartAt(Track& t, const Pose& pose) const {
  t.motion = MotionModel(pose);
  t.filters.clear();
}

// The last part of step 5: a confirmed track that took a pose in step 4 and a confirmed track
// left unmatched trade, when the first looks more like a pose still free and the second more like
// the first's pose (swapGain > swap_margin, each pose within the other track's gate): the first
// gets the free pose, the second its pose. Two people overlapping, one of them seen for a frame
// as one pose: the position gives it to the wrong track, whose own person, seen again, would
// start a new track. Bonn sequence with half the frames dropped (identity bench, oks): two
// people on the right crossing at a turn of the play, only one detected; the track of the one
// behind took the pose of the one in front, whose track was left lost, and the one behind came
// back as a new track (32 joint id switches, the new track hidden 5 frames by contested_time).
void PoseAssociator::Impl::giveBackToUnmatched(const Poses& poses, const std::vector<int>& high,
                                               const std::vector<Descriptor>& appearance,
                                               FrameMatches& m) {
  if (settings.swap_margin <= 0.f) return;
  std::vector<int> pose_of(tracks.size(), -1);
  for (size_t d = 0; d < m.track_of.size(); ++d)
    if (m.track_of[d] >= 0) pose_of[m.track_of[d]] = static_cast<int>(d);
  struct Trade {
    float gain;
    int taker, unmatched, free_pose;
  };
  std::vector<Trade> trades;
  for (int d : high) {
    if (m.track_of[d] >= 0 || appearance[d].empty()) continue;
    for (size_t a = 0; a < tracks.size(); ++a) {
      const Track& ta = tracks[a];
      if (pose_of[a] < 0 || !confirmed(ta) || ta.appearance.empty() ||
          appearance[pose_of[a]].empty() || !inGate(ta, poses[d]) ||
          liesWithin(poses[d], poses[pose_of[a]]))
        continue;
      for (size_t b = 0; b < tracks.size(); ++b) {
        const Track& tb = tracks[b];
        if (m.matched[b] || !confirmed(tb) || tb.appearance.empty() ||
            !inGate(tb, poses[pose_of[a]]))
          continue;
        const float gain = swapGain(ta, appearance[pose_of[a]], tb, appearance[d]);
        if (gain > settings.swap_margin)
          trades.push_back({gain, static_cast<int>(a), static_cast<int>(b), d});
      }
    }
  }
  std::sort(trades.begin(), trades.end(),
            [](const Trade& x, const Trade& y) { return x.gain > y.gain; });
  std::vector<bool> traded(tracks.size(), false);
  for (const Trade& t : trades) {
    if (traded[t.taker] || traded[t.unmatched] || m.track_of[t.free_pose] >= 0) continue;
    traded[t.taker] = traded[t.unmatched] = true;
    const int taken = pose_of[t.taker];
    m.track_of[taken] = t.unmatched;
    m.matched[t.unmatched] = true;
    m.track_of[t.free_pose] = t.taker;
    restartAt(tracks[t.taker], poses[t.free_pose]);
    restartAt(tracks[t.unmatched], poses[taken]);
  }
}

// OKS between a track's predicted pose and a pose, each joint's tolerance widened by how well the
// motion model knows where the person is now: after a gap in time (dropped frames, a slow frame
// rate, a track lost for a while) a person may have moved further than OKS alone allows.
float PoseAssociator::Impl::predictionOks(const Track& t, const Pose& pose) const {
  return oks(t.motion.pose(), pose, thresholds, t.motion.positionSigma());
}

// Step 5: lost tracks, and active tracks that step 4 left unmatched, against the poses still
// free. A pose is taken on OKS with the track's prediction (predictionOks >= coast_min_oks),
// or else on appearance (>= reid_min_similarity) when it lies within the position gate of the
// track's motion model (3 standard deviations of the predicted centre, at most one height per
// second hidden, plus half the person's height; one height for a pose that looks very like the
// track, ranked below the poses the position backs) of the path from where the person was last seen
// to the prediction (distanceToPath), and its height is within kReidHeightRatio of the track's. A
// confirmed track may also take a pose that a tentative track took in step 4: a person partly
// hidden for a frame or two (crossing behind someone) comes back in a view too poor for
// re-identification, starts a tentative track, and on the next frame, seen better, would stay
// with it (vtest.avi: a walker crossing behind another at frames 19-22 came back as a new track
// with appearance 0.80, 0.90 one frame later, and lost their id of 20 frames). The tentative
// track, unmatched, ends after tentative_lost_time.
// Active tracks take part because OKS alone loses small people for a frame: on vtest.avi (people
// 40-100 px tall) a walker whose pose changed kept OKS 0.39 at 3 px from its prediction with
// appearance 0.97, and got a new id (docs/identity.md: 14 -> 11 ids in the first 300 frames with
// this and the ratio below). Tentative ones too: a new track has the least motion history, so its
// prediction is the least sure, and frames apart (a stride, a slow machine) OKS lost them; on the
// Bonn sequence at strides 3 and 4, oks 28 and 30 joint id switches -> 2 and 2 (as tff and flow),
// and vtest.avi's walker entering at frame 117 kept their id (docs/tracking.md, step 5).
void PoseAssociator::Impl::matchLost(const Poses& poses, cv::Size frame,
                                     const std::vector<int>& high,
                                     const std::vector<Descriptor>& appearance,
                                     FrameMatches& m) const {
  const bool reidentify = settings.reid != AppearanceModel::kOff;
  std::vector<int> rows, cols;
  for (size_t t = 0; t < tracks.size(); ++t) {
    if (tracks[t].state == TrackState::kLost || (reidentify && !m.matched[t]))
      rows.push_back(static_cast<int>(t));
  }
  // The poses still free, and those a tentative track took in step 4: a confirmed track may take
  // those back (tentativeTaken).
  auto tentativeTaken = [&](int d) {
    return m.track_of[d] >= 0 && !confirmed(tracks[m.track_of[d]]);
  };
  for (int d : high)
    if (m.track_of[d] < 0 || tentativeTaken(d)) cols.push_back(d);
  if (rows.empty() || cols.empty()) return;
  cv::Mat psi =
      cv::Mat::zeros(static_cast<int>(rows.size()), static_cast<int>(cols.size()), CV_32F);
  for (size_t r = 0; r < rows.size(); ++r) {
    const Track& t = tracks[rows[r]];
    const float track_gate = gate(t);
    const bool gone = leftView(t, frame);
    for (size_t c = 0; c < cols.size(); ++c) {
      if (!confirmed(t) && tentativeTaken(cols[c])) continue;
      const Pose& p = poses[cols[c]];
      const float geometric_score = predictionOks(t, p);
      // An active track had its OKS chance in step 4 (the geometric fallback, where enabled).
      const bool lost = t.state == TrackState::kLost;
      float score = lost && geometric_score >= settings.coast_min_oks ? geometric_score : 0.f;
      // One who walked out of the view is not looked for inside it on appearance: whoever comes
      // in where they went out may be someone else, and position no longer tells (vtest.avi: a
      // man in a black coat entering 1.1 s after a man in a leather jacket walked out there took
      // his id, appearance 0.94). A person coming back is recognised by re-entry (reentry_time)
      // once the track has ended, with its stricter likeness. Position alone does not tell either:
      // the prediction's tolerance grows with the time lost, so after a few seconds anyone
      // entering there passes OKS. Taken back on position, they must also look like the track:
      // on vtest.avi a woman in a red top entering 2.7 s after a bald man walked out took his id
      // on OKS 0.82 (appearance 0.67), while a man coming back 2 s after he walked out there
      // (appearance 0.90) and the woman back 3 s after she left (0.89) were their own tracks.
      if (gone && reidentify && score > 0.f &&
          appearanceSimilarity(t.appearance, appearance[cols[c]]) < settings.reid_min_similarity)
        score = 0.f;
      bool placed = score > 0.f;  // where the track's prediction says the person is
      if (reidentify && !gone) {
        const float h = std::max(p.keypointBox(1e-12f).h, 1.f);
        const float ratio = h / t.motion.height();
        const float similar = appearanceSimilarity(t.appearance, appearance[cols[c]]);
        const float distance = pathDistance(t, p);
        const float allowed =
            track_gate +
            (similar >= kReidStrongSimilarity ? kReidStrongGateHeights * t.motion.height() : 0.f);
        if (distance <= allowed && ratio > 1.f / kReidHeightRatio && ratio < kReidHeightRatio &&
            similar >= settings.reid_min_similarity) {
          score = std::max(score, similar);
          placed = placed || distance <= track_gate;
        }
      }
      // A pose that only the strong likeness's wider gate lets in ranks below every pose the
      // position backs, however alike: the widening is for a camera estimate that erred, not a
      // reason to prefer someone further away. vtest.avi: a bald man hidden 0.4 s behind another
      // walker came back 6 px from his path (OKS 0.79, appearance 0.93), and a man in a leather
      // jacket who had just come in 111 px from it (appearance 0.94) took his id.
      if (placed) score += kPlacedRank;
      psi.at<float>(static_cast<int>(r), static_cast<int>(c)) = score;
    }
  }
  // Scores are in (0, 2]; 0 = not allowed. Greedy: the surest pair first.
  for (const Match& mt : matchGreedy(psi, psi, 1e-6f)) {
    const int d = cols[mt.col];
    if (m.track_of[d] >= 0) m.matched[m.track_of[d]] = false;  // the tentative track gives it up
    m.matched[rows[mt.row]] = true;
    m.track_of[d] = rows[mt.row];
  }
}

// A pose that starts a track inside the position gate of a confirmed track that this frame left
// unmatched may be that track's person, seen too poorly to be re-identified yet: the track that
// contests it (its internal id), or -1. Not a track whose person walked out of the view (of size
// `view`): whoever comes in there is shown at once (step 5 takes them for that track only if
// position and likeness agree).
std::int64_t PoseAssociator::Impl::contestingTrack(const Pose& pose, cv::Size view,
                                                   const FrameMatches& m) const {
  if (settings.contested_time <= 0.f) return -1;
  for (size_t i = 0; i < tracks.size(); ++i) {
    const Track& t = tracks[i];
    if (m.matched[i] || !confirmed(t) || leftView(t, view)) continue;
    if (inGate(t, pose)) return t.id;
  }
  return -1;
}

// A tentative track born where a lost confirmed track may take its pose back (step 5 lets a
// confirmed track take the pose of a tentative one) is not shown while that track is still lost:
// a person partly hidden behind a walking partner came back as a new track for 2-4 frames before
// their own took them back, and the new id was shown meanwhile (vtest.avi, frames 729-732 and
// 765-767). Shown once confirmed, or once the contesting track ended or took someone else.
bool PoseAssociator::Impl::stillContested(const Track& t, const FrameMatches& m) const {
  if (t.contested_by < 0 || confirmed(t)) return false;
  // At most contested_time: at a slow inference rate min_track_length frames would hide a
  // person for seconds.
  if (time - t.start_time > settings.contested_time + 1e-9) return false;
  for (size_t i = 0; i < tracks.size(); ++i)
    if (tracks[i].id == t.contested_by) return !m.matched[i];
  return false;
}

// Step 6: every high-scoring pose still free starts a tentative track. Where reentry_time is on,
// a pose that looks like a departed person (a track that ended within reentry_time) takes that
// person's output id back: appearance >= reentry_min_similarity and ahead of the next departed
// person by kReentryMargin (two similar-looking people who both left: neither is guessed).
// Position and time do not count: a person who leaves the view may come back anywhere.
void PoseAssociator::Impl::birth(const Poses& poses, cv::Size view, const std::vector<int>& high,
                                 const std::vector<Descriptor>& appearance, FrameMatches& m) {
  std::vector<int> born;
  for (int d : high)
    if (m.track_of[d] < 0) born.push_back(d);
  departed.erase(
      std::remove_if(departed.begin(), departed.end(),
                     [&](const Departed& e) { return time - e.time > settings.reentry_time; }),
      departed.end());
  std::vector<int> returning(poses.size(), -1);  // pose -> index into departed
  if (reentry() && !departed.empty() && !born.empty()) {
    cv::Mat psi =
        cv::Mat::zeros(static_cast<int>(departed.size()), static_cast<int>(born.size()), CV_32F);
    for (size_t r = 0; r < departed.size(); ++r)
      for (size_t c = 0; c < born.size(); ++c)
        psi.at<float>(static_cast<int>(r), static_cast<int>(c)) =
            appearanceSimilarity(departed[r].appearance, appearance[born[c]]);
    cv::Mat allowed = cv::Mat::zeros(psi.size(), CV_32F);
    for (int c = 0; c < psi.cols; ++c) {
      float best = 0.f, second = 0.f;
      int best_row = -1;
      for (int r = 0; r < psi.rows; ++r) {
        const float v = psi.at<float>(r, c);
        if (v > best) {
          second = best;
          best = v;
          best_row = r;
        } else {
          second = std::max(second, v);
        }
      }
      if (best_row >= 0 && best >= settings.reentry_min_similarity &&
          best - second >= kReentryMargin)
        allowed.at<float>(best_row, c) = best;
    }
    for (const Match& mt : matchGreedy(allowed, allowed, 1e-6f)) returning[born[mt.col]] = mt.row;
  }
  std::vector<bool> taken(departed.size(), false);
  for (int d : born) {
    Track t(next_id++, poses[d]);
    t.start_time = t.last_time = time;
    t.start_frame = frame;
    t.appearance = appearance[d];
    t.contested_by = contestingTrack(poses[d], view, m);
    if (returning[d] >= 0) {
      t.revived = departed[returning[d]];
      t.output_id = t.revived->output_id;
      taken[returning[d]] = true;
    }
    m.track_of[d] = static_cast<int>(tracks.size());
    m.matched.push_back(true);
    tracks.push_back(std::move(t));
  }
  std::vector<Departed> left;
  for (size_t i = 0; i < departed.size(); ++i)
    if (!taken[i]) left.push_back(std::move(departed[i]));
  departed = std::move(left);
}

// Step 7: matched tracks are corrected; unmatched ones are lost; long-lost ones end.
std::vector<TrackedPose> PoseAssociator::Impl::lifecycle(const Poses& poses,
                                                         const std::vector<Descriptor>& appearance,
                                                         const FrameMatches& m) {
  std::vector<TrackedPose> out;
  reported.clear();
  for (size_t d = 0; d < poses.size(); ++d) {
    const int ti = m.track_of[d];
    if (ti < 0) continue;
    Track& t = tracks[ti];
    const bool born = t.hits == 0;
    const double dt = time - t.last_time;
    if (!born) {
      t.motion.correct(poses[d]);
      t.last_time = time;
      // The running appearance: a slow blend, so that one occluded view does not replace it.
      blendAppearance(t.appearance, appearance[d], 0.9f);
    }
    t.last = poses[d];
    t.state = TrackState::kActive;
    ++t.hits;
    // Not shown before min_report_length matches, but where it was born on the stream's first
    // frame: the people already there are all shown at once.
    if (t.hits < settings.min_report_length && t.start_frame > 1) continue;
    if (stillContested(t, m)) continue;
    TrackedPose tp = report(t, smooth(t, poses[d], born ? 0.0 : dt), static_cast<int>(d));
    if (tp.tentative && !settings.output_tentative) continue;
    out.push_back(tp);
    reported.push_back(t.id);
  }
  for (size_t ti = 0; ti < m.matched.size(); ++ti)
    if (!m.matched[ti]) tracks[ti].state = TrackState::kLost;
  const double tentative_kept = tentativeLostTime();
  tracks.erase(std::remove_if(tracks.begin(), tracks.end(),
                              [&](const Track& t) {
                                const double kept =
                                    confirmed(t) ? settings.lost_time : tentative_kept;
                                const bool ends = t.state == TrackState::kLost &&
                                                  time - t.last_time > kept + 1e-9;
                                if (ends) depart(t);
                                return ends;
                              }),
               tracks.end());
  return out;
}

// A track that ends: a confirmed, reported one is kept for reentry_time as departed (one entry
// per output id, the newest appearance); a revived track that ends tentative gives its entry
// back. At most kMaxDeparted are kept (the oldest go first); birth() drops those older than
// reentry_time.
void PoseAssociator::Impl::depart(const Track& t) {
  if (!reentry()) return;
  Departed d;
  if (confirmed(t) && t.output_id >= 0) {
    d.output_id = t.output_id;
    d.appearance = t.appearance;
    d.time = time;
  } else if (t.revived) {
    d = *t.revived;
  } else {
    return;
  }
  departed.erase(std::remove_if(departed.begin(), departed.end(),
                                [&](const Departed& e) { return e.output_id == d.output_id; }),
                 departed.end());
  departed.push_back(std::move(d));
  if (departed.size() > kMaxDeparted) departed.erase(departed.begin());
}

// tentative_lost_time, but at least 1.5 frame intervals: a tentative track lives through one
// missed frame at any frame rate. A slow machine behind a leaky queue infers a 10 frames/s camera
// at 2 frames/s; 0.3 s then ended a tentative track on its first miss, and with 7 matches needed
// to confirm, people who were missed now and then kept getting new ids (vtest.avi's first 100
// frames, every 5th inferred: 16 -> 13 ids in 20 frames, against 8 ids inferring all 100). The
// frame interval is the median of the last kIntervals, so that one long gap (a camera that
// stalled) does not stretch it.
double PoseAssociator::Impl::tentativeLostTime() const {
  double interval = 0.0;
  if (!intervals.empty()) {
    std::vector<double> v(intervals.begin(), intervals.end());
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    interval = v[v.size() / 2];
  }
  return std::max(static_cast<double>(settings.tentative_lost_time), 1.5 * interval);
}

TrackedPose PoseAssociator::Impl::report(Track& t, const Pose& pose, int detection) {
  TrackedPose tp;
  tp.pose = pose;
  tp.tentative = !confirmed(t);
  tp.age = frame - t.start_frame;
  tp.age_seconds = time - t.start_time;
  tp.detection = detection;
  if (!(tp.tentative && !settings.output_tentative)) {
    if (t.output_id < 0) t.output_id = next_output_id++;
    tp.track_id = t.output_id;
  }
  return tp;
}

Pose PoseAssociator::Impl::smooth(Track& t, const Pose& pose, double dt) const {
  if (!settings.smoothing) return pose;
  if (t.filters.empty())
    t.filters.assign(2 * kNumJoints, OneEuroFilter(settings.euro_min_cutoff, settings.euro_beta,
                                                   settings.euro_d_cutoff));
  // One-Euro filters in stream time; a first sample (dt 0) passes unfiltered.
  const float step = static_cast<float>(dt > 0.0 ? dt : 1.0 / settings.frame_rate);
  Pose out = pose;
  for (int j = 0; j < kNumJoints; ++j) {
    Keypoint& k = out.keypoints[j];
    if (k.score <= 0.f) continue;
    k.x = t.filters[2 * j].filter(k.x, step);
    k.y = t.filters[2 * j + 1].filter(k.y, step);
  }
  return out;
}

PoseAssociator::PoseAssociator(const TrackerSettings& settings) : impl_(std::make_unique<Impl>()) {
  validateAssociationSettings(settings);
  impl_->settings = settings;
  impl_->thresholds = thresholdsOf(settings);
  impl_->similarity = createSimilarity(settings.similarity, similarityOptionsOf(settings));
  impl_->geometric = createSimilarity(SimilarityType::kOks, similarityOptionsOf(settings));
}

PoseAssociator::~PoseAssociator() = default;
PoseAssociator::PoseAssociator(PoseAssociator&&) noexcept = default;
PoseAssociator& PoseAssociator::operator=(PoseAssociator&&) noexcept = default;

std::vector<TrackedPose> PoseAssociator::update(const SpatialResult& result, const cv::Mat& tff,
                                                const cv::Mat& grey, double time) {
  AssociationFrame in;
  in.poses = result.poses;
  in.tff = tff;
  in.grid_to_frame = result.grid_to_frame;
  in.grey = grey;
  in.features = result.features;
  in.time = time;
  return update(in);
}

std::vector<TrackedPose> PoseAssociator::update(const AssociationFrame& in) {
  Impl& s = *impl_;
  checkPoses(in.poses);
  if (!in.grey.empty() && in.grey.type() != CV_8UC1)
    throw Error("association: the grey frame must be 8-bit, 1 channel");
  if (s.similarity->needsFlow() && in.grey.empty())
    throw Error("similarity 'flow' needs the grey frame (AssociationFrame::grey)");
  ++s.frame;
  const double previous_time = s.time;
  s.time = s.frameTime(in.time);
  const double dt = s.frame > 1 ? s.time - previous_time : 0.0;
  if (dt > 0.0) {
    s.intervals.push_back(dt);
    if (s.intervals.size() > kIntervals) s.intervals.pop_front();
  }

  // Step 1.
  const std::vector<int> dets = s.filterDetections(in.poses);
  std::vector<int> high, low;
  for (int d : dets) (in.poses[d].score >= s.settings.track_score ? high : low).push_back(d);
  const std::vector<Descriptor> appearance = describeAppearance(
      in.poses, high, in.features, in.grid_to_frame, in.bgr, s.thresholds, s.settings.reid);
  // Steps 2-3.
  const cv::Mat flow = s.denseFlow(in);
  s.estimateCamera(in, flow, dets);
  s.predictTracks(dt);
  // Steps 4-6.
  FrameMatches m{std::vector<int>(in.poses.size(), -1), std::vector<bool>(s.tracks.size(), false)};
  s.matchActive(in, s.temporalFlow(in), flow, high, low, m);
  s.undoSwaps(in.poses, appearance, m);
  // The frame's size from its grey or colour image (empty without either).
  const cv::Size frame = (in.grey.empty() ? in.bgr : in.grey).size();
  s.matchLost(in.poses, frame, high, appearance, m);
  s.giveBackToUnmatched(in.poses, high, appearance, m);
  s.birth(in.poses, frame, high, appearance, m);
  // Step 7.
  std::vector<TrackedPose> out = s.lifecycle(in.poses, appearance, m);
  if (!in.grey.empty() && s.similarity->needsFlow()) s.previous_grey = in.grey.clone();
  return out;
}

std::vector<TrackedPose> PoseAssociator::predict(double time) const {
  const Impl& s = *impl_;
  std::vector<TrackedPose> out;
  const double dt = std::isfinite(time) ? std::max(0.0, time - s.time) : 0.0;
  for (std::int64_t id : s.reported) {
    const auto it =
        std::find_if(s.tracks.begin(), s.tracks.end(), [&](const Track& t) { return t.id == id; });
    if (it == s.tracks.end()) continue;
    TrackedPose tp;
    // Extrapolated no further than a lost track is kept.
    tp.pose = it->motion.poseAfter(std::min(dt, static_cast<double>(s.settings.lost_time)));
    tp.pose.score = it->last.score;
    tp.track_id = it->output_id;
    tp.tentative = !s.confirmed(*it);
    tp.age = s.frame - it->start_frame;
    tp.age_seconds = s.time + dt - it->start_time;
    out.push_back(tp);
  }
  return out;
}

void PoseAssociator::reset() {
  impl_->tracks.clear();
  impl_->departed.clear();  // a new stream: nobody comes back into it
  impl_->reported.clear();
  impl_->previous_grey.release();
  impl_->camera_tracker.reset();
  impl_->camera = cv::Matx23f(1, 0, 0, 0, 1, 0);
  impl_->frame = 0;
  impl_->time = 0.0;
  impl_->intervals.clear();
}

int PoseAssociator::liveTracks() const {
  return static_cast<int>(impl_->tracks.size());
}
int PoseAssociator::timeFallbacks() const {
  return impl_->time_fallbacks;
}
cv::Matx23f PoseAssociator::cameraMotion() const {
  return impl_->camera;
}

}  // namespace jointflow
