// The JointFlow tracker: the whole online pipeline behind one call.
//
//   frame -> SpatialModel (poses, features, belief maps)
//         -> Temporal Flow Field network on (previous, current) maps   [similarity "tff"]
//         -> person potentials Psi between the tracks and the new poses
//         -> greedy (paper) or optimal bipartite matching
//         -> track book: ids, tentative tracks, coasting, smoothing
//
// One Tracker serves one stream: it keeps the previous frame's maps and poses (the one-frame
// state of the paper) and the tracks. It is not thread-safe; use one per stream.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/spatial_model.hpp"
#include "jointflow/types.hpp"

namespace jointflow {

/// The association's settings with their defaults (PoseAssociator reads these and no others);
/// paper values are noted where the paper gives one. docs/tracking.md explains each with the
/// formulas and the track lifecycle.
struct AssociationSettings {
  /// Person similarity: tff (paper), oks, iou, pckh, flow (paper baselines), or auto: oks between
  /// frames closer than auto_tff_gap and tff between frames further apart. Default auto: on the
  /// identity benchmark it keeps as many ids as the better of oks and tff on every case at the
  /// Bonn people's own speed, at oks's cost at the camera's frame rate (where every similarity
  /// keeps the ids its poses allow), and where the tracker gets 1 frame in 6 to 16 it keeps
  /// 2.4-5.4x fewer joint id switches than oks (docs/tracking.md, "The default similarity"). Not
  /// for fast motion at the camera's rate, where it is oks: see auto_tff_gap.
  SimilarityType similarity = SimilarityType::kAuto;
  Matcher matcher = Matcher::kGreedy;  ///< greedy (paper) | optimal
  /// Frame px; a joint that moved less (from its previous detection moved by the estimated
  /// camera motion) counts E_j = 1. Paper: 2, for a still camera; 12 covers the camera
  /// estimate's error (95th percentile 6-10 px under pan, shake and zoom) plus detector jitter,
  /// which otherwise leave E_aggr to decide on noise (docs/tracking.md).
  float tau_delta = 12.f;
  int line_samples = 10;    ///< samples of the TFF line integral
  float sigma_flow = 30.f;  ///< optical-flow energy width in px (paper: 30)
  /// No match below this potential per joint (Psi / joints detected in both for tff and flow, Psi
  /// itself for oks, iou, pckh); the pose starts a new track. Paper: none (0); 0.1 keeps the
  /// near-zero TFF potentials of unrelated people from matching (docs/tracking.md).
  float min_potential = 0.1f;
  /// oks and pckh: their mean over the joints detected in both poses is taken over at least this
  /// many joints, the missing ones counting 0. Paper: 1 (the plain mean). Why: a pose that shares
  /// one or two joints with a track, such as MoveNet's second, lower-body-only detection of a
  /// person whose knees the whole-body detection misses, scored a near-perfect OKS on its hip and
  /// took the track from the person's whole pose for a frame. Bonn sequence at input-size=native,
  /// stride 2, oks: 24 -> 7 joint id switches, MOTA 79.8 -> 82.1 (3: 10 switches); pckh 10 -> 7;
  /// every identity-benchmark case, the Bonn train motion and vtest.avi unchanged
  /// (docs/tracking.md).
  int min_common_joints = 5;
  /// tff only: step 4's potential per joint becomes (1 - w) x the TFF's + w x the OKS of the
  /// track's prediction with the pose (Psi = that x the joints in both); 0 = the paper's TFF
  /// potential alone (issue 12 item 3, a documented combination with geometry). With 0.5, Bonn
  /// stride 3 (max:640) 87.9 -> 88.5 MOTA, the best baseline's: a walker seen again after showing
  /// 5 joints behind another person, whose field the other's motion covered (under 0.05 per
  /// joint). Every other identity-benchmark case, vtest.avi and the Bonn strides at native size
  /// stay the same. The price, on the Bonn train motion with the TFF rendered from the ground
  /// truth (a perfect network): joint id switches 203 -> 149 at stride 1 but 72 -> 104 at stride
  /// 3, where positions say least (person switches 20 -> 13 and 10 -> 9). docs/tracking.md.
  /// Since tff_flow_weight (below) the default is 0.25: the geometry's half of the mix is shared
  /// with the flow. tff_oks_weight + tff_flow_weight <= 1; the TFF keeps the rest.
  float tff_oks_weight = 0.25f;
  /// tff and auto (where its TFF runs): weight w_f of the dense optical flow's joint energy (Eq. 9,
  /// sigma_flow) in step 4's potential per joint, (1 - w_o - w_f) x the TFF's + w_o x OKS of the
  /// prediction + w_f x E_flow. The flow is DIS (preset medium) on the grey frames shrunk to at
  /// most 480 px on the longer side, computed only between frames at least auto_tff_gap apart;
  /// between closer ones, and where no flow comes (the first frame, a new frame size), its weight
  /// goes to OKS. Why: the TFF reaches about 30 grid cells, and a slow engine's frames lie further
  /// apart than that: the field then says little, while the flow follows the image over any
  /// distance its pyramid covers; the mix keeps more ids than either alone. Identity benchmark,
  /// the Bonn sequence at 1 frame in 12 (mean MOTA over four seeds): 81.7 with w_f 0 (w_o 0.5),
  /// flow alone 83.7, the mix 86.5; 1 in 16: 83.8, 76.4, 86.3 (docs/tracking.md, "The flow in
  /// tff's mix"). Between close frames the field reaches the motion, and the flow would cost
  /// without keeping an id more (vtest.avi at 10 frames/s, tff on every frame with the flow: 16
  /// ids against 15). 0 = no flow (the TFF and OKS alone, as before).
  float tff_flow_weight = 0.25f;
  /// similarity auto: frames at least this many seconds of stream time apart are matched with
  /// the TFF, closer ones with oks, and the TFF network does not run for them; tff and auto: the
  /// flow of tff_flow_weight joins the mix from this gap on. Why: at the
  /// camera's frame rate oks keeps every id its poses allow on the identity benchmark, as tff
  /// does, at no network's cost; from 1 frame in 6 of a 30 frames/s camera (0.2 s) on, oks loses
  /// ids the TFF keeps (Bonn, 1 in 8: 645 joint id switches against 119). The TFF network was
  /// trained on frames up to 4 apart (0.13 s at 30 frames/s); 0.15 s lies between. 0: the TFF
  /// and the flow on every frame, for people who move fast at the camera's rate (sport): the
  /// Bonn frames at 8 times the speed, 1/30 s apart, 77.6 -> 88.5 MOTA (docs/tracking.md, "Fast
  /// motion at the camera's rate"); the default decides by stream time, not by motion.
  float auto_tff_gap = 0.15f;
  /// Tracks matched on fewer inferred frames are tentative (paper pruning: 7).
  int min_track_length = 7;
  /// A new track is reported, and gets its output id, once it was matched on this many inferred
  /// frames; tracks born on a stream's first inferred frame (after a reset too) are reported at
  /// once. 1 = from the first detection (the paper). 2, as ByteTrack activates a track on its
  /// second frame: a detection seen on one frame only (a false one, or a person half hidden for
  /// a frame whose track takes them back on the next) shows no id, which a person count would
  /// take for one more person. vtest.avi, 795 frames, oks: 22 -> 19 distinct ids, 16 confirmed
  /// either way; the Bonn strides unchanged (docs/tracking.md, step 7). The price: a person who
  /// comes into view is shown one inferred frame later.
  int min_report_length = 2;
  /// Seconds at most that a new track is not shown when it was born inside the position gate of
  /// a confirmed track that is lost there: until it is confirmed, or that track is matched again
  /// or ends. Such a pose is often the lost track's own person, half hidden behind a walking
  /// partner, whose track takes them back a few frames later; shown meanwhile, they would flash
  /// a new id. 0 = off. vtest.avi, 795 frames: oks 21 -> 19 distinct ids, tff 24 -> 21;
  /// occluder 42 -> 36 joint id switches with every similarity. The price: a person so born is
  /// shown later, which costs MOTA where it was someone the lost track never takes back
  /// (dropped frames, oks 88.4 -> 86.8, back to 89.5 since step 5 trades with a track left
  /// unmatched; docs/tracking.md, step 7).
  float contested_time = 1.f;
  bool smoothing = false;  ///< One-Euro smoothing of keypoints per track
  int max_persons = 100;   ///< most tracked persons per frame (as SpatialOptions::max_persons)

  // Time. Stream time in seconds (Tracker::process's timestamp): what a track may survive does
  // not depend on the frame rate, the inference interval or dropped frames.
  /// Seconds a confirmed track that is not matched stays "lost": predicted by its motion model
  /// and matched again on position, pose and appearance (re-identification). Paper: 0.
  /// 3 s, not 2: a person is lost from the first frame the detector misses them, before they are
  /// fully hidden, and comes back only once enough of them shows again, so to keep someone hidden
  /// for 2 s a track must outlive 2 s. Identity bench (docs/identity.md), occluder, oks: back
  /// under the same id after up to 2 s hidden 5 -> 7 of 8, joint id switches 102 -> 70; vtest.avi
  /// 27 -> 23 ids in 795 frames (2.5 s: 7 of 8, 74, 25; 4 s: as 3 s).
  float lost_time = 3.f;
  /// The same for tentative tracks: most are false detections, which must not take the id of a
  /// person coming back. At least 1.5 frame intervals (the median of the last 9), so that a
  /// tentative track lives through one missed frame at any frame rate: at 2 inferred frames/s
  /// (a slow machine behind a leaky queue) 0.3 s ended it on its first miss. A tentative track
  /// already reported is kept longer, lost_time x its matches / min_track_length: the more often
  /// seen, the less likely a false detection (identity bench, pan: 22 -> 8 joint id switches).
  float tentative_lost_time = 0.3f;
  /// Frames at least this many seconds of stream time apart (a camera outage, a stalled source):
  /// the confirmed tracks that have an appearance skip step 4 and are matched in step 5, on their
  /// looks within their position gates, instead of on the OKS of their predictions. Why: the
  /// prediction's tolerance grows with the time passed (predictionOks), so after a few seconds
  /// every pose in reach scores 0.86-1.0 for every track and the greedy order hands out ids;
  /// people also stop and turn back while unseen. vtest.avi with two 4 s gaps (make
  /// bench-outages, docs/outages.md): people who stayed in view kept their ids 4 of 9 times
  /// without this (4 took someone else's), 9 of 9 with it (docs/tracking.md, step 5, "After a
  /// gap"). 0 = off. 1 s: above the 0.5-0.7 s between the frames of a slow engine behind a leaky
  /// queue (1 in 12-16 of a 25 frames/s camera), which OKS and the TFF match well.
  float gap_time = 1.f;
  /// How a lost track is recognised when its person comes back. features-colour: on vtest.avi
  /// (hand-made identity labels) a person's running appearance ranks their own pose 2 s later
  /// first among the people present in 89 % of cases, the network's features alone in 54 %; of 9
  /// returns (7 people), features-colour ranks the person's own departed visit first in all 9,
  /// the features in 5 (docs/reid-bench.md).
  AppearanceModel reid = AppearanceModel::kFeaturesColour;
  /// Lowest appearance similarity (cosine) at which a lost track takes a pose that its position
  /// and pose alone do not decide. 0.8: of the pairs 1-2 s apart on vtest.avi (a person's running
  /// appearance against a pose; features-colour, hand-made labels, docs/reid-bench.md), 98.9 % of
  /// the same person's reach it and 28.7 % of different people's (0.75: 99.5 % and 44 %, 0.84:
  /// 97.5 % and 21 %); the position gate keeps most of the others out. The whole tracker there
  /// (IDF1 per person with re-entry / per visit without): 0.75 78.6 / 85.9, 0.8 81.5 / 87.3, 0.83
  /// 81.6 / 87.1, 0.85 81.6 / 87.2, 0.9 81.5 / 87.1: 0.83-0.85 trade 0.1 per person for 0.1-0.2
  /// per visit, and 0.85 lowers the Bonn MOTA at stride 3 (pckh 88.9 -> 88.5): not worth a change.
  float reid_min_similarity = 0.8f;
  /// Seconds a confirmed track that ended (lost for longer than lost_time: the person left the
  /// view, or stayed hidden) is remembered by its appearance and where it was last seen, so that
  /// its person coming back later near there gets the old id; 0 = off (the paper). Needs reid.
  /// A new track born within 0.4 of the view's longer side of a departed person who looks
  /// close to like it is shown only once it is recognised (confirmed, or contested_time); one
  /// shown under a new id takes the departed person's id back in its first 10 s once its look
  /// clearly is theirs (0.05 under reentry_min_similarity, ahead of the next by 0.08:
  /// reentry.cpp; its id changes from that frame on). 30 s:
  /// on vtest.avi people came back after 5 to 14 s (19 -> 14 ids for 11 people, every return
  /// checked by eye; docs/tracking.md, step 6).
  float reentry_time = 30.f;
  /// Lowest appearance similarity at which a new person is taken for a departed one; the best
  /// departed person must also lead the next by 0.03. Stricter than reid_min_similarity: neither
  /// position nor motion backs the guess. On vtest.avi (hand-made labels, docs/reid-bench.md) of 9
  /// returns, at 0.9 4 are taken back and nobody wrongly, 5 at 0.86-0.88, 6 at 0.84;
  /// at 0.82 and below a newcomer is taken for someone who left (0.82). The 0.03 lead refuses the
  /// rest: another departed person in dark clothes scores up to 0.97 (the man in the long black
  /// coat: 0.99 his own). The whole tracker: per person IDF1 81.5 at 0.83, 0.85, 0.88 and 0.9,
  /// 74.8 at 0.93, 71.8 at 0.95.
  float reentry_min_similarity = 0.9f;
  /// Two confirmed tracks matched to poses that each look more like the other track, by more
  /// than this in all (the two cross similarities against the two own ones), and lie within its
  /// position gate, take each other's pose: two people side by side or crossing, whose tracks
  /// the position swapped. The same margin lets a confirmed track left unmatched take the pose
  /// of a matched one that looks more like a pose still free (step 5): two people overlapping,
  /// one detected for a frame; and lets a confirmed track left unmatched take back a pose that
  /// looks like it (at least reid_min_similarity) from a confirmed track that the pose does not
  /// look like (below it), by more than this: one pose seen where two people cross. 0 = off;
  /// needs reid. 0.1: on vtest.avi the four swaps seen gained
  /// 0.18 to 0.24 on the frame they were undone, and no other pair of tracks in the clip more
  /// than 0.05 (docs/tracking.md, steps 4 and 5).
  float swap_margin = 0.1f;

  // Beyond the paper (what deployed trackers need). Defaults keep the paper's behaviour except
  // where noted.
  /// A keypoint takes part in Psi when its score is >= this (paper: joints kept by tau_NMS = 0.2
  /// are "detected").
  float joint_threshold = 0.2f;
  /// Per-joint thresholds in COCO order (17 values) overriding joint_threshold; empty = none.
  std::vector<float> joint_thresholds;
  /// Poses scoring below this start no track and are matched only in a second pass, to the tracks
  /// the first pass left over (ByteTrack). 0 = every pose is matched in the first pass.
  float track_score = 0.f;
  /// Geometric re-association: the minimum OKS between a track's prediction (camera and own
  /// motion) and a new pose, for lost tracks and the geometric fallback.
  float coast_min_oks = 0.5f;
  /// Tracks of the previous frame that the similarity leaves unmatched get a second chance on
  /// OKS >= coast_min_oks with their prediction. The TFF is 0 where people stand still, so
  /// detector jitter above tau_delta would otherwise end their tracks. false = the paper's
  /// behaviour.
  bool geometric_fallback = true;
  /// Estimate the camera motion (global similarity transform) on every inferred frame and move
  /// every track with it before any similarity is computed.
  bool camera_compensation = true;
  /// Of two poses in one frame whose OKS (over the joints both hold) is >= this, the
  /// lower-scored one is dropped; 0 = off. MoveNet sees a person close up twice, as a whole
  /// body and as an upper body on the same joints, and the two tracks took the person in turn:
  /// on the identity benchmark's zoom (1x to 1.8x) oks made 103 joint id switches, tff 41; with
  /// 0.9 every similarity makes 5 and MOTA 62.9-65.6 -> 69.3, small people 24.4 -> 24.9; no other
  /// case and no vtest.avi count moves (docs/identity.md). 0.5 and 0.7 gave the same; 0.9 keeps
  /// two real people apart unless every joint they share lies within about half a joint's
  /// tolerance of the other's.
  float duplicate_oks = 0.9f;
  float min_person_size = 0.f;   ///< px; poses whose keypoint box's longer side is smaller
                                 ///< are ignored
  bool output_tentative = true;  ///< report tracks before they reach min_track_length
  /// Frames per second assumed where a frame comes without a usable timestamp (none, or not
  /// after the previous one): its time is the previous one + 1 / frame_rate.
  float frame_rate = 30.f;
  float euro_min_cutoff = 1.f;  ///< One-Euro minimum cut-off frequency, Hz
  float euro_beta = 0.05f;      ///< One-Euro speed coefficient, 1/px
  float euro_d_cutoff = 1.f;    ///< One-Euro cut-off of the speed estimate, Hz
};

/// All tracker settings, in the parts each layer reads: the association's, which it holds as its
/// base so that every setting is read and set by its own name (settings.tau_delta) and a
/// PoseAssociator is given its part alone (PoseAssociator(settings) takes the AssociationSettings
/// in it); the spatial model's (`spatial`, for createSpatialModel); the engine's (`engine`, which
/// both networks run on); and the TFF file.
struct TrackerSettings : AssociationSettings {
  ModelType model_type = ModelType::kAuto;  ///< spatial model decoder; auto reads the ONNX outputs
  SpatialOptions spatial;                   ///< spatial model file, input size, thresholds, tiles
  EngineOptions engine;                     ///< inference engine of both networks (spatial and TFF)
  std::string tff_model;  ///< TFF ONNX file; empty = the shipped tff_<spatial type>.onnx
                          ///< (model_files.hpp: where it is looked for)
};

/// Throws jointflow::Error naming the first setting out of range, in the order of
/// trackerSettingsSchema() (settings_schema.hpp), or the first pair that does not go together.
void validateTrackerSettings(const TrackerSettings& settings);

struct TrackedPose {
  Pose pose;
  std::int64_t track_id = -1;  ///< unique within the stream, never reused (but by a person coming
                               ///< back, reentry_time); counts up from 1
  bool tentative = true;       ///< track shorter than min_track_length so far
  int age = 0;                 ///< inferred frames since the track started (0 on its first)
  double age_seconds = 0.0;    ///< stream time since the track's first detection
  int detection = -1;          ///< index of the pose in the frame's input poses
  /// For a person shown under a new id and recognised late as someone who had left
  /// (reentry_time), the new id they were shown under until then, on every frame from the change
  /// on: a consumer that missed the frame of the change (a lost message) still joins the two
  /// ids' histories. 0 = none (ids count from 1).
  std::int64_t previous_track_id = 0;
};

/// The tracks now and so far, for monitoring (jointflowtrack's statistics message).
struct TrackCounts {
  int active = 0;  ///< matched on the last inferred frame
  int lost = 0;    ///< not matched since, still kept (predicted, may be re-identified)
  /// Track ids given out since the tracker was made (reset() keeps counting, as the ids do).
  std::int64_t created = 0;
};

class Tracker {
 public:
  /// Loads the models; throws jointflow::Error with a message naming the file at fault.
  explicit Tracker(const TrackerSettings& settings);
  ~Tracker();
  Tracker(Tracker&&) noexcept;
  Tracker& operator=(Tracker&&) noexcept;

  /// Runs the whole pipeline on one frame (8-bit, 3 channels) taken at `timestamp` seconds of
  /// stream time and returns the tracked poses. Without a timestamp (NaN), or with one not after
  /// the previous frame's, the frame is taken 1 / frame_rate after the previous one. Frames may be
  /// skipped (dropped, not inferred): the tracks live through the gap in time.
  std::vector<TrackedPose> process(const cv::Mat& image, PixelOrder order = PixelOrder::kBGR,
                                   double timestamp = std::numeric_limits<double>::quiet_NaN());

  /// The same after the spatial model: `result` is the spatial model's output for `image`
  /// (benchmarks run the spatial model once and feed every similarity the same result). Throws
  /// jointflow::Error when the result is of a frame of another size.
  std::vector<TrackedPose> process(const SpatialResult& result, const cv::Mat& image,
                                   PixelOrder order = PixelOrder::kBGR,
                                   double timestamp = std::numeric_limits<double>::quiet_NaN());

  /// The poses of the last process() moved on to `timestamp` by each track's motion model, for
  /// the frames on which the networks do not run (inference interval, late frames). The tracker
  /// is not changed.
  std::vector<TrackedPose> predict(double timestamp) const;

  /// Frames so far that came without a usable timestamp (see process()).
  int timeFallbacks() const;

  /// Active and lost tracks now, ids given out so far.
  TrackCounts trackCounts() const;

  /// A TFF network runs ("tff"; "auto" where one fits the spatial model, else it is oks).
  bool hasTff() const;

  /// The spatial model (its type, options and feature channels).
  const SpatialModel& spatialModel() const;
  /// The TFF network's file, "" when none runs.
  std::string tffModelPath() const;

  /// process() in two steps, so that other work overlaps the spatial network (on an asynchronous
  /// engine, OpenVINO): submit() starts the network on the frame, collect() finishes the oldest
  /// submitted frame (TFF, association) and returns its tracked poses. Frames are collected in
  /// the order they were submitted; at most two are pending (SpatialModel::submit). With frame N
  /// submitted before frame N-1 is collected, N's network runs while N-1 is associated.
  void submit(const cv::Mat& image, PixelOrder order = PixelOrder::kBGR,
              double timestamp = std::numeric_limits<double>::quiet_NaN());
  std::vector<TrackedPose> collect();
  int pending() const;         ///< frames submitted and not collected
  bool asynchronous() const;   ///< the spatial network runs in the background after submit()
  std::string engine() const;  ///< the spatial network's engine, for logs

  /// Forgets every track and the previous frame (a cut, a seek, a flush), and drops the frames
  /// still pending. Ids keep counting up.
  void reset();

  const TrackerSettings& settings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace jointflow
