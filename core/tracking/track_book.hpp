// The track book of PoseAssociator, shared by the files of its steps (pose_associator.hpp's list):
// what a track holds, what one frame's matching decides, where a track's person may be, and the
// state each step works on (PoseAssociator::Impl). Internal to core/tracking, not installed.
//   pose_associator.cpp  update(), steps 1-3, 6 and 7;
//   match_active.cpp     step 4 (and its swaps);
//   match_lost.cpp       step 5 (re-identification, and the trade with a track left unmatched);
//   track_gates.cpp      position gates, paths, the view;
//   reentry.cpp          the departed, and a newborn track recognised as one (steps 6 and 7).
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include <opencv2/video/tracking.hpp>

#include "camera_motion.hpp"
#include "dense_flow.hpp"
#include "jointflow/appearance.hpp"
#include "jointflow/frame_clock.hpp"
#include "jointflow/pose_associator.hpp"
#include "jointflow/similarity.hpp"
#include "motion_model.hpp"
#include "one_euro_filter.hpp"

namespace jointflow {
namespace track_book {

enum class TrackState {
  kActive,  ///< matched on the previous inferred frame
  kLost,    ///< not matched since `last_time`; predicted, may be re-identified
};

/// A confirmed track that ended (lost for longer than lost_time): what a person coming back
/// later is recognised by (reentry_time).
struct Departed {
  std::int64_t output_id = -1;
  Descriptor appearance;
  double time = 0.0;       ///< when its track ended
  double last_seen = 0.0;  ///< when its track was last matched
  /// Where its person was last seen, in current-frame pixels (follows the camera).
  cv::Point2f exit;
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
  /// Where the track was born, in current-frame pixels (follows the camera).
  cv::Point2f born_at;
  /// Born near where a departed person who looks like it was last seen: not shown until it is
  /// recognised as them or as someone new (reentry.cpp).
  bool reentry_pending = false;
  /// The id the track was shown under before it was recognised late as someone who had left
  /// (recogniseLate), or 0; reported with every pose from then on (TrackedPose::previous_track_id).
  std::int64_t shown_before = 0;

  Track(std::int64_t id_, const Pose& detection) : id(id_), motion(detection), last(detection) {}
};

// What one frame's matching steps decide: the track of each input pose, the tracks matched.
struct FrameMatches {
  std::vector<int> track_of;  ///< input pose -> track index, -1 = none
  std::vector<bool> matched;  ///< track index -> matched in this frame

  /// Track index -> its input pose, -1 = none (the inverse of track_of).
  std::vector<int> poseOfTrack() const {
    std::vector<int> pose_of(matched.size(), -1);
    for (size_t d = 0; d < track_of.size(); ++d)
      if (track_of[d] >= 0) pose_of[track_of[d]] = static_cast<int>(d);
    return pose_of;
  }
};

/// What step 4 matches on besides the poses.
struct MotionCues {
  cv::Mat tff;       ///< the TFF between the frames (tff, auto); empty: none this frame
  cv::Mat flow;      ///< the "flow" similarity's dense flow, frame size
  cv::Mat mix_flow;  ///< tff's mix: the flow of shrunk frames (TrackerSettings::tff_flow_weight)
  float mix_flow_scale = 1.f;  ///< frame pixels per pixel of mix_flow
  /// The frame came gap_time or more after the last: confirmed tracks with an appearance are left
  /// to step 5.
  bool after_gap = false;
};

// Where a track's person may be (track_gates.cpp says why each is so).

/// The person walked out of the view: the track's predicted centre lies outside a frame of this
/// size (empty = not known: nobody counts as gone).
bool leftView(const Track& t, cv::Size frame);
/// The track's position gate, px, for `hidden` seconds since it was last seen.
float positionGate(const Track& t, double hidden);
/// How far a pose's centre lies from the track's path (last seen -> predicted), px.
float pathDistance(const Track& t, const Pose& pose);
/// The track's predicted pose moved along its path to where it best fits `pose`.
Pose poseOnPath(const Track& t, const Pose& pose);

}  // namespace track_book

struct PoseAssociator::Impl {
  using Departed = track_book::Departed;
  using FrameMatches = track_book::FrameMatches;
  using Track = track_book::Track;
  using TrackState = track_book::TrackState;

  AssociationSettings settings;
  JointThresholds thresholds{};
  std::unique_ptr<Similarity> similarity;
  std::unique_ptr<Similarity> geometric;    ///< OKS: fallback, lost tracks, missing TFF/flow
  std::unique_ptr<Similarity> flow_energy;  ///< Eq. 9, the flow's part of tff's mix
  DenseFlow optical_flow;                   ///< the "flow" similarity's
  DenseFlow mix_optical_flow;               ///< of shrunk frames, for tff's mix
  cv::Mat previous_small_grey;              ///< the last grey frame, shrunk for mixFlow
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
  FrameClock clock;  ///< each frame's time (frame_clock.hpp), frame_duration 1 / frame_rate

  double tentativeLostTime() const;
  /// How long `t`, not matched, stays lost before it ends (`tentative_kept`: tentativeLostTime).
  double lostLifetime(const Track& t, double tentative_kept) const;
  /// Re-entry is on: departed people are remembered and recognised (it needs an appearance).
  bool reentry() const {
    return settings.reentry_time > 0.f && settings.reid != AppearanceModel::kOff;
  }
  // Re-entry (reentry.cpp).
  struct DepartedMatch {
    int index = -1;  ///< into departed, the best; -1 = none within reach
    float best = 0.f, second = 0.f;
  };
  void depart(const Track& t);
  void followDeparted();
  DepartedMatch nearestLook(const Track& t, cv::Size view, float reach_share) const;
  bool mayBeReturning(const Track& t, cv::Size view) const;
  void recognise(Track& t, cv::Size view);
  void recogniseLate(Track& t, cv::Size view);
  void takeBack(Track& t, cv::Size view, float min_similarity, float margin, float reach_share);
  /// Matched on min_track_length frames: no longer tentative.
  bool confirmed(const Track& t) const { return t.hits >= settings.min_track_length; }
  /// The track's position gate now (positionGate for the time since it was last seen).
  float gate(const Track& t) const { return track_book::positionGate(t, time - t.last_time); }
  /// The pose lies within the track's gate of its path (where the track's person may be now).
  bool inGate(const Track& t, const Pose& pose) const {
    return track_book::pathDistance(t, pose) <= gate(t);
  }
  std::int64_t contestingTrack(const Pose& pose, cv::Size view, const FrameMatches& m) const;
  bool stillContested(const Track& t, const FrameMatches& m) const;
  std::vector<int> filterDetections(const Poses& poses) const;
  cv::Mat denseFlow(const AssociationFrame& in);
  cv::Mat mixFlow(const AssociationFrame& in, bool wanted, float* scale);
  cv::Matx23f estimateCamera(const AssociationFrame& in, const cv::Mat& flow,
                             const std::vector<int>& dets);
  FrameMotion motion(const AssociationFrame& in, const std::vector<int>& dets);
  /// Throws for a frame that cannot be associated (non-finite poses, a grey frame of another
  /// type, "flow" without one).
  void checkFrame(const AssociationFrame& in) const;
  void predictTracks(double dt);
  void matchActive(const AssociationFrame& in, const track_book::MotionCues& cues,
                   const std::vector<int>& high, const std::vector<int>& low,
                   FrameMatches& m) const;
  /// With `involving`, only pairs of which one track is marked there.
  void undoSwaps(const Poses& poses, const std::vector<Descriptor>& appearance, FrameMatches& m,
                 const std::vector<bool>* involving = nullptr);
  /// After a gap (`after_gap`: gap_time), where `t` went is told by its looks: re-identification
  /// is on and the track has an appearance. Step 4 leaves such confirmed tracks to step 5, which
  /// ignores their OKS and does not take them for gone.
  bool looksDecide(const Track& t, bool after_gap) const {
    return after_gap && settings.reid != AppearanceModel::kOff && !t.appearance.empty();
  }
  /// A confirmed track matched to `pose`, both with an appearance: swapGain can weigh them.
  bool comparable(const Track& t, int pose, const std::vector<Descriptor>& appearance) const {
    return pose >= 0 && confirmed(t) && !t.appearance.empty() && !appearance[pose].empty();
  }
  /// A confirmed track left unmatched (`matched` false), with an appearance, whose gate holds
  /// `pose`: it may claim that pose from the track that took it (step 5's trade and take-back).
  bool mayClaim(const Track& t, bool matched, const Pose& pose) const {
    return !matched && confirmed(t) && !t.appearance.empty() && inGate(t, pose);
  }
  static bool overlapsAnother(const Poses& poses, int d, const FrameMatches& m);
  float swapGain(const Track& a, const Descriptor& pose_a, const Track& b,
                 const Descriptor& pose_b) const;
  void restartAt(Track& t, const Pose& pose) const;
  void giveBackToUnmatched(const Poses& poses, const std::vector<int>& high,
                           const std::vector<Descriptor>& appearance, FrameMatches& m);
  void takeBackUnlike(const Poses& poses, cv::Size frame, const std::vector<Descriptor>& appearance,
                      FrameMatches& m);
  float predictionOks(const Track& t, const Pose& pose) const;
  void matchLost(const Poses& poses, cv::Size frame, const std::vector<int>& high,
                 const std::vector<Descriptor>& appearance, bool after_gap, FrameMatches& m) const;
  void birth(const Poses& poses, cv::Size view, const std::vector<int>& high,
             const std::vector<Descriptor>& appearance, FrameMatches& m);
  std::vector<TrackedPose> lifecycle(const Poses& poses, cv::Size view,
                                     const std::vector<Descriptor>& appearance,
                                     const FrameMatches& m);
  TrackedPose report(Track& t, const Pose& pose, int detection);
  Pose smooth(Track& t, const Pose& pose, double dt) const;
};

}  // namespace jointflow
