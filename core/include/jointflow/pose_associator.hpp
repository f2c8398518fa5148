// Online association of per-frame poses into tracks, without any network: the part of the
// Tracker after the spatial and temporal models. Benchmarks and evaluation feed it the same
// detections for every similarity.
//
// Per inferred frame, one named step each (docs/tracking.md, "One frame"):
//   1. detections: minimum person size, duplicate suppression, at most max_persons;
//   2. camera:     the global camera motion previous -> current frame (sparse corners with a robust
//                  similarity fit, or the dense flow when the similarity is "flow");
//   3. predict:    every track is moved by the camera motion and advanced to this frame's time by
//                  its motion model (a constant-velocity Kalman filter, camera motion removed);
//   4. match active: the tracks matched on the previous inferred frame against the poses, with
//                  the chosen similarity (Psi, paper Eq. 5-9) and matcher (Eq. 1), high-scoring
//                  poses first, then the low ones (ByteTrack); with geometric_fallback the active
//                  tracks left over get a second chance on OKS with their prediction; two
//                  confirmed tracks whose poses each look more like the other (swap_margin)
//                  take each other's pose;
//   5. match lost: the tracks lost for less than lost_time against the poses still free (and
//                  those tentative tracks took: a confirmed track may take them back), on OKS
//                  with their prediction or, failing that, on appearance within the position gate
//                  their motion model allows (re-identification; a track whose person walked
//                  out of the view is taken back on OKS only by a pose that also looks like it,
//                  and never on appearance alone); active tracks that step 4 left unmatched take
//                  part on appearance; last, a confirmed track still unmatched and a matched one
//                  trade (swap_margin) when the first looks like the matched pose and the second
//                  like a pose still free; a confirmed track still unmatched takes back a pose
//                  that looks like it from a confirmed track it does not look like; step 4's
//                  swap check again for the pairs with a track found in this step;
//   6. birth:      every high-scoring pose still free starts a tentative track; one born near
//                  where a departed person (reentry_time) who looks like it was last seen waits
//                  to be recognised;
//   7. lifecycle:  matched tracks are corrected and become active (confirmed after
//                  min_track_length matches; reported from min_report_length matches, or at
//                  once on the stream's first frame; one born in the gate of a confirmed track
//                  lost there only once confirmed, that track found or ended, or contested_time
//                  passed; one waiting to be recognised takes the departed person's id back, or
//                  a new one, once confirmed or contested_time passed; a confirmed one that took
//                  a new id takes a departed person's id back when its running look clearly is
//                  theirs within its first 10 s); unmatched ones become lost; tracks lost for
//                  longer than lost_time (tentative_lost_time) end, confirmed ones are remembered
//                  as departed for reentry_time. Ids are never reused, except by a departed person
//                  coming back.
//
// Time is stream time in seconds (AssociationFrame::time). A frame without a time, or with one not
// after the previous frame's, is taken 1 / frame_rate after it.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/spatial_model.hpp"
#include "jointflow/tracker.hpp"
#include "jointflow/types.hpp"

namespace jointflow {

/// Step 2 of one frame, estimated ahead of PoseAssociator::update (PoseAssociator::estimateMotion):
/// what a caller that computes the TFF itself needs first. The Tracker runs its TFF network on the
/// previous frame's maps moved by `camera`, so the camera motion must be known before the network
/// runs, and the camera motion leaves the tracks' boxes out of its fit, which only the associator
/// knows.
struct FrameMotion {
  /// The camera motion previous -> current frame pixels (2x3; identity without
  /// camera_compensation, or on a stream's first frame).
  cv::Matx23f camera{1, 0, 0, 0, 1, 0};
  /// "flow": the dense optical flow previous -> current frame (frame size, empty on a first frame
  /// or a new frame size); `camera` is fitted to it, and step 4 matches on it.
  cv::Mat flow;
  /// Step 4 matches this frame on a TFF: "tff" always, "auto" where the frame is auto_tff_gap or
  /// more after the previous one. Where false the TFF network only keeps this frame's maps for the
  /// next frame (AssociationFrame::tff is not read).
  bool tff = false;
  /// The poses step 1 kept (indices into AssociationFrame::poses), whose boxes the camera fit left
  /// out: update() goes on with them rather than filter the same poses again.
  std::vector<int> detections;
};

/// One frame's input to the association.
struct AssociationFrame {
  Poses poses;  ///< detections in frame pixels
  /// {1, 34, H, W}: the TFF from the previous frame to this one ("tff", "auto"; empty: step 4
  /// falls back to OKS for this frame).
  cv::Mat tff;
  /// How `tff` was computed. false: on the previous frame's maps as they were, so it holds all
  /// apparent motion (camera included): each joint's line integral starts where it was detected.
  /// true: on the previous frame's maps moved by the camera motion of `motion` (the Tracker's TFF
  /// network), so it holds the people's own motion: each joint's line integral starts where it
  /// was detected moved by the camera.
  bool tff_camera_compensated = false;
  GridTransform grid_to_frame;  ///< grid of `tff` and `features`
  cv::Mat grey;                 ///< 8-bit grey frame ("flow"; camera motion when given)
  cv::Mat features;             ///< {1, C, H, W} spatial features (re-identification)
  cv::Mat bgr;                  ///< the frame, 8-bit BGR (colour re-identification)
  double time = std::numeric_limits<double>::quiet_NaN();  ///< stream time, seconds
  /// Step 2, when the caller estimated it with PoseAssociator::estimateMotion on this frame just
  /// before update() (the Tracker, whose TFF depends on it). Empty: update() estimates it so.
  std::optional<FrameMotion> motion;
};

/// The images an association frame needs besides the poses (PoseAssociator::frameNeeds).
struct FrameNeeds {
  bool grey = false;  ///< AssociationFrame::grey: the flow similarity, tff's flow, camera motion
  bool bgr = false;   ///< AssociationFrame::bgr: colour re-identification
};

class PoseAssociator {
 public:
  /// Throws jointflow::Error naming the setting at fault for values out of range or unknown
  /// names. Given TrackerSettings, takes the AssociationSettings in them.
  explicit PoseAssociator(const AssociationSettings& settings);
  ~PoseAssociator();
  PoseAssociator(PoseAssociator&&) noexcept;
  PoseAssociator& operator=(PoseAssociator&&) noexcept;

  /// Associates one frame's poses with the tracks and returns the tracked poses of this frame,
  /// in the order of the input poses. Throws jointflow::Error when the similarity lacks its input
  /// (e.g. "flow" without a grey image).
  std::vector<TrackedPose> update(const AssociationFrame& frame);

  /// Step 2 of update(frame) alone, for a caller that must know the camera motion before it
  /// computes the frame's TFF: it then passes the result in AssociationFrame::motion to the
  /// update() of the same frame, next. Changes only the camera estimator's state (its previous
  /// frame), as update() would. Throws as update() does for a frame it cannot associate.
  FrameMotion estimateMotion(const AssociationFrame& frame);

  /// The poses the last update() reported, moved on to `time` by each track's motion model (for
  /// frames the networks skip); the tracks are not changed. A time before the last update's
  /// gives the poses as reported.
  std::vector<TrackedPose> predict(double time) const;

  /// What a frame must bring for these settings, asked of the similarity (its cues) and of the
  /// steps that read images: callers make only those (the grey frame costs a conversion).
  FrameNeeds frameNeeds() const;

  /// Forgets every track and the previous frame; ids keep counting up.
  void reset();

  /// Number of live tracks (active or lost).
  int liveTracks() const;
  /// Active and lost tracks now, output ids given out so far.
  TrackCounts trackCounts() const;
  /// Frames so far whose time was missing or not after the previous one (taken 1 / frame_rate
  /// later instead).
  int timeFallbacks() const;
  /// The camera motion estimated for the last frame (2x3, previous -> current frame pixels).
  cv::Matx23f cameraMotion() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The rule of the paper's offline pruning (Sec. 6.2: 7 frames): the track ids seen on at least
/// `min_length` frames, given the ids of each frame. Every output that prunes asks this.
std::set<std::int64_t> longTracks(const std::vector<std::vector<std::int64_t>>& ids_per_frame,
                                  int min_length);

/// Offline pruning of tracks shorter than min_length frames (longTracks), for file processing:
/// removes their poses from `frames` and renumbers the remaining ids 1, 2, ... in order of first
/// appearance.
void pruneShortTracks(std::vector<std::vector<TrackedPose>>& frames, int min_length);

/// Throws jointflow::Error naming the first association setting out of range
/// (validateTrackerSettings checks the networks' settings too).
void validateAssociationSettings(const AssociationSettings& settings);

}  // namespace jointflow
