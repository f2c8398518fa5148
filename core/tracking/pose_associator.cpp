// PoseAssociator: the online track book. One function per step of pose_associator.hpp's list;
// update() calls them in order. Steps 4 and 5 are in match_active.cpp and match_lost.cpp, the
// gates in track_gates.cpp, the shared state in track_book.hpp.
#include "jointflow/pose_associator.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>
#include <optional>
#include <string>

#include "jointflow/error.hpp"
#include "jointflow/image_shrink.hpp"
#include "track_book.hpp"

namespace jointflow {
using track_book::FrameMatches;
using track_book::leftView;
using track_book::Track;

namespace {

JointThresholds thresholdsOf(const AssociationSettings& s) {
  JointThresholds t;
  t.fill(s.joint_threshold);
  if (!s.joint_thresholds.empty())
    std::copy(s.joint_thresholds.begin(), s.joint_thresholds.end(), t.begin());
  return t;
}

SimilarityOptions similarityOptionsOf(const AssociationSettings& s) {
  SimilarityOptions o;
  o.thresholds = thresholdsOf(s);
  o.tau_delta = s.tau_delta;
  o.line_samples = s.line_samples;
  o.sigma_flow = s.sigma_flow;
  o.min_common_joints = s.min_common_joints;
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

// Updates over which the frame interval (for tentativeLostTime) is taken.
constexpr size_t kIntervals = 9;

}  // namespace

// A pose overlapping another matched pose by more than this share of its box shows part of the
// other person: its look does not update its track's appearance (lifecycle says why) nor decide
// a swap (undoSwaps).
constexpr float kClearOverlap = 0.1f;

bool PoseAssociator::Impl::overlapsAnother(const Poses& poses, int d, const FrameMatches& m) {
  for (size_t o = 0; o < poses.size(); ++o)
    if (static_cast<int>(o) != d && m.track_of[o] >= 0 &&
        intersectionArea(poses[d].box, poses[o].box) > kClearOverlap * poses[d].box.area())
      return true;
  return false;
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

void PoseAssociator::Impl::checkFrame(const AssociationFrame& in) const {
  checkPoses(in.poses);
  if (!in.grey.empty() && in.grey.type() != CV_8UC1)
    throw Error("association: the grey frame must be 8-bit, 1 channel");
  if (similarity->needsFlow() && in.grey.empty())
    throw Error("similarity 'flow' needs the grey frame (AssociationFrame::grey)");
}

// Dense optical flow previous -> current, for the "flow" similarity.
cv::Mat PoseAssociator::Impl::denseFlow(const AssociationFrame& in) {
  if (!similarity->needsFlow() || previous_grey.empty() || previous_grey.size() != in.grey.size())
    return {};
  return optical_flow(previous_grey, in.grey);
}

// The flow of tff's mix (TrackerSettings::tff_flow_weight): DIS on the grey frames shrunk to at
// most kMixFlowSide px on the longer side, computed only where `wanted` (the TFF matches frames
// far apart). Every frame's shrunk grey is kept: whether the next frame wants it is known only
// then.
cv::Mat PoseAssociator::Impl::mixFlow(const AssociationFrame& in, bool wanted, float* scale) {
  // Why 480: on the Bonn slow-engine cases (960x540) the mix kept as many ids with the flow of
  // frames halved (480x270) as at full size, at a fraction of its cost (DIS medium on vtest.avi's
  // 768x576 frames: 31 ms; shrunk to 480x360: 12 ms; 2 cores); at a third (320x180) it lost 4
  // MOTA points at 1 frame in 12.
  constexpr int kMixFlowSide = 480;
  if (!similarity->needsTff() || settings.tff_flow_weight <= 0.f || in.grey.empty()) {
    previous_small_grey.release();
    return {};
  }
  // shrinkImage's steps, not INTER_AREA: this runs on every frame of the default similarity, and
  // area by a fractional factor took 0.93 ms of one core on vtest.avi's frames, shrinkImage 0.12.
  const cv::Mat small = shrinkToSide(in.grey, kMixFlowSide);
  cv::Mat flow;
  if (wanted && previous_small_grey.size() == small.size()) {
    flow = mix_optical_flow(previous_small_grey, small);
    *scale = static_cast<float>(in.grey.cols) / static_cast<float>(small.cols);
  }
  previous_small_grey = small;
  return flow;
}

// Step 2: the camera motion, with the people's boxes (this frame's detections `dets`, the tracks'
// last) left out of the fit.
cv::Matx23f PoseAssociator::Impl::estimateCamera(const AssociationFrame& in, const cv::Mat& flow,
                                                 const std::vector<int>& dets) {
  if (!settings.camera_compensation) return cv::Matx23f(1, 0, 0, 0, 1, 0);
  std::vector<Box> people;
  for (int d : dets) people.push_back(in.poses[d].box);
  for (const Track& t : tracks) people.push_back(t.motion.pose().box);
  if (!flow.empty()) {
    camera_tracker.reset();  // flow is missing only where the tracker has no previous frame
    return cameraMotionFromFlow(flow, people);
  }
  return camera_tracker.update(in.grey, people);  // an empty frame resets it
}

// Step 2 of a frame, taken before update() moves the clock and the tracks on to it: the dense flow
// of "flow", the camera motion, and whether step 4 matches on a TFF.
// "auto" between frames that are not auto_tff_gap apart wants none: step 4 then matches on oks
// (its fallback where the TFF lacks), and the network only keeps the maps.
FrameMotion PoseAssociator::Impl::motion(const AssociationFrame& in, const std::vector<int>& dets) {
  FrameMotion m;
  m.detections = dets;
  m.flow = denseFlow(in);
  m.camera = estimateCamera(in, m.flow, dets);
  // update()'s dt, from a copy of the clock (the frame's time is taken there).
  const double dt = frame > 0 ? FrameClock(clock).next(in.time) - time : 0.0;
  m.tff = similarity->needsTff() &&
          (settings.similarity != SimilarityType::kAuto || dt >= settings.auto_tff_gap);
  return m;
}

// Step 3: every track follows the camera, then its own motion over dt seconds.
void PoseAssociator::Impl::predictTracks(double dt) {
  for (Track& t : tracks) {
    t.motion.applyCamera(camera);
    t.motion.predict(dt);
    t.born_at = applyMotion(camera, t.born_at);
  }
  followDeparted();
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
// one born near where a departed person (a track that ended within reentry_time) was last seen,
// and looking close to like them, waits to be recognised (reentry.cpp): the look of a first view
// at the border does not yet tell.
void PoseAssociator::Impl::birth(const Poses& poses, cv::Size view, const std::vector<int>& high,
                                 const std::vector<Descriptor>& appearance, FrameMatches& m) {
  for (int d : high) {
    if (m.track_of[d] >= 0) continue;
    Track t(next_id++, poses[d]);
    t.start_time = t.last_time = time;
    t.start_frame = frame;
    t.appearance = appearance[d];
    t.born_at = t.motion.centre();
    t.contested_by = contestingTrack(poses[d], view, m);
    t.reentry_pending = mayBeReturning(t, view);
    m.track_of[d] = static_cast<int>(tracks.size());
    m.matched.push_back(true);
    tracks.push_back(std::move(t));
  }
}

// Step 7: matched tracks are corrected; unmatched ones are lost; long-lost ones end.
std::vector<TrackedPose> PoseAssociator::Impl::lifecycle(const Poses& poses, cv::Size view,
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
      // The running appearance: a slow blend, so that one occluded view does not replace it,
      // and none from a pose that overlaps another matched pose (by more than kClearOverlap of
      // its box): where two people cross or walk side by side, a pose's colours and features are
      // partly the other person's, and a few frames of them made each track look like the other,
      // so that a swap at the crossing could no longer be undone (undoSwaps). vtest.avi (labelled,
      // tests/data/vtest-identity, auto): per visit, re-entry off, IDF1 85.1 -> 87.3, HOTA 85.0 ->
      // 87.0, AssA 78.3 -> 82.2; per person, re-entry on, IDF1 78.0 -> 81.5, AssA 66.6 -> 73.3.
      // The price: 6 more ID switches (20 -> 26), swaps now undone a few frames later instead of
      // kept (frames 37, 112).
      if (!overlapsAnother(poses, static_cast<int>(d), m))
        blendAppearance(t.appearance, appearance[d], 0.9f);
    }
    t.last = poses[d];
    t.state = TrackState::kActive;
    ++t.hits;
    recognise(t, view);
    recogniseLate(t, view);
    if (t.reentry_pending) continue;  // not shown before it is recognised, or not
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
                                const bool ends =
                                    t.state == TrackState::kLost &&
                                    time - t.last_time > lostLifetime(t, tentative_kept) + 1e-9;
                                if (ends) depart(t);
                                return ends;
                              }),
               tracks.end());
  return out;
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

// lost_time once confirmed. A tentative track already shown (min_report_length matches, or born
// on the stream's first frame) is kept lost_time x hits / min_track_length, at least
// tentative_kept: the more often a person was seen, the less likely they are a false detection,
// and the less a new id for them is worth the risk. One never shown keeps tentative_kept. Why:
// identity bench, pan: a person seen on the first 5 frames (5 of 7 matches) walked out of the
// view as the pan turned and came back 0.4 s later under a new id; kept 2.1 s instead of 0.3 s,
// their track took them back (pan 22 -> 8 joint id switches with every similarity; vtest.avi's
// oks and tff counts unchanged, iou and pckh 1 and 2 ids fewer; on the Bonn train motion, whose
// simulated false people now linger longer, oks makes one person switch more at strides 1 and 3;
// docs/identity.md).
double PoseAssociator::Impl::lostLifetime(const Track& t, double tentative_kept) const {
  if (confirmed(t)) return settings.lost_time;
  if (t.output_id < 0) return tentative_kept;
  return std::max(tentative_kept, static_cast<double>(settings.lost_time) * t.hits /
                                      std::max(1, settings.min_track_length));
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
    tp.previous_track_id = t.shown_before;
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

PoseAssociator::PoseAssociator(const AssociationSettings& settings)
    : impl_(std::make_unique<Impl>()) {
  validateAssociationSettings(settings);
  impl_->settings = settings;
  impl_->clock.setFrameDuration(1.0 / settings.frame_rate);
  impl_->thresholds = thresholdsOf(settings);
  impl_->similarity = createSimilarity(settings.similarity, similarityOptionsOf(settings));
  impl_->geometric = createSimilarity(SimilarityType::kOks, similarityOptionsOf(settings));
  impl_->flow_energy = createSimilarity(SimilarityType::kFlow, similarityOptionsOf(settings));
}

PoseAssociator::~PoseAssociator() = default;
PoseAssociator::PoseAssociator(PoseAssociator&&) noexcept = default;
PoseAssociator& PoseAssociator::operator=(PoseAssociator&&) noexcept = default;

FrameMotion PoseAssociator::estimateMotion(const AssociationFrame& in) {
  Impl& s = *impl_;
  s.checkFrame(in);
  return s.motion(in, s.filterDetections(in.poses));
}

std::vector<TrackedPose> PoseAssociator::update(const AssociationFrame& in) {
  Impl& s = *impl_;
  s.checkFrame(in);
  // Steps 1 and 2, unless the caller took them (estimateMotion, then its TFF on the motion);
  // before the clock moves on to this frame.
  const FrameMotion motion = in.motion ? *in.motion : s.motion(in, s.filterDetections(in.poses));
  const std::vector<int>& dets = motion.detections;
  ++s.frame;
  const double previous_time = s.time;
  s.time = s.clock.next(in.time);
  const double dt = s.frame > 1 ? s.time - previous_time : 0.0;
  if (dt > 0.0) {
    s.intervals.push_back(dt);
    if (s.intervals.size() > kIntervals) s.intervals.pop_front();
  }

  std::vector<int> high, low;
  for (int d : dets) (in.poses[d].score >= s.settings.track_score ? high : low).push_back(d);
  const std::vector<Descriptor> appearance = describeAppearance(
      in.poses, high, in.features, in.grid_to_frame, in.bgr, s.thresholds, s.settings.reid);
  // Step 3.
  s.camera = motion.camera;
  s.predictTracks(dt);
  // Steps 4-6.
  FrameMatches m{std::vector<int>(in.poses.size(), -1), std::vector<bool>(s.tracks.size(), false)};
  track_book::MotionCues cues;
  // Frames far apart: where auto's TFF runs, and where the flow joins tff's mix (closer frames
  // lie within the TFF's reach, and the flow would cost without keeping an id more).
  const bool far = dt >= s.settings.auto_tff_gap;
  cues.tff = motion.tff ? in.tff : cv::Mat();
  cues.flow = motion.flow;
  cues.mix_flow = s.mixFlow(in, !cues.tff.empty() && far, &cues.mix_flow_scale);
  cues.after_gap = s.settings.gap_time > 0.f && dt >= s.settings.gap_time;
  s.matchActive(in, cues, high, low, m);
  s.undoSwaps(in.poses, appearance, m);
  const std::vector<bool> matched_in_step4 = m.matched;
  // The frame's size from its grey or colour image (empty without either).
  const cv::Size frame = (in.grey.empty() ? in.bgr : in.grey).size();
  s.matchLost(in.poses, frame, high, appearance, cues.after_gap, m);
  s.giveBackToUnmatched(in.poses, high, appearance, m);
  s.takeBackUnlike(in.poses, frame, appearance, m);
  // Step 4's swap check again, for the pairs with a track that step 5 found: a person stepping out
  // from behind another, whose track was lost while the two were seen as one, is given the other's
  // pose by position as often as the other's active track is given theirs, and step 4's check ran
  // before the lost track had a pose. vtest.avi (labels, auto): two men in dark coats crossing at
  // frame 728 kept each other's ids for good; now the swap is undone when the hidden one is found
  // again 3 frames later. Per visit 26 -> 22 id switches, IDF1 87.3 -> 90.0 (docs/tracking.md).
  std::vector<bool> found_in_step5(m.matched.size());
  for (size_t t = 0; t < m.matched.size(); ++t)
    found_in_step5[t] = m.matched[t] && !matched_in_step4[t];
  s.undoSwaps(in.poses, appearance, m, &found_in_step5);
  s.birth(in.poses, frame, high, appearance, m);
  // Step 7.
  std::vector<TrackedPose> out = s.lifecycle(in.poses, frame, appearance, m);
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

FrameNeeds PoseAssociator::frameNeeds() const {
  const Impl& s = *impl_;
  FrameNeeds n;
  n.grey = s.similarity->needsFlow() || s.settings.camera_compensation ||
           (s.similarity->needsTff() && s.settings.tff_flow_weight > 0.f);
  n.bgr = s.settings.reid == AppearanceModel::kFeaturesColour;
  return n;
}

void PoseAssociator::reset() {
  impl_->tracks.clear();
  impl_->departed.clear();  // a new stream: nobody comes back into it
  impl_->reported.clear();
  impl_->previous_grey.release();
  impl_->previous_small_grey.release();
  impl_->camera_tracker.reset();
  impl_->camera = cv::Matx23f(1, 0, 0, 0, 1, 0);
  impl_->frame = 0;
  impl_->time = 0.0;
  impl_->clock.reset();
  impl_->intervals.clear();
}

int PoseAssociator::liveTracks() const {
  return static_cast<int>(impl_->tracks.size());
}
TrackCounts PoseAssociator::trackCounts() const {
  TrackCounts counts;
  for (const Track& t : impl_->tracks)
    (t.state == track_book::TrackState::kLost ? counts.lost : counts.active)++;
  counts.created = impl_->next_output_id - 1;
  return counts;
}
int PoseAssociator::timeFallbacks() const {
  return impl_->clock.fallbacks();
}
cv::Matx23f PoseAssociator::cameraMotion() const {
  return impl_->camera;
}

}  // namespace jointflow
