// PoseTrack evaluation, equivalent to the public poseval tool (leonid-pishchulin/poseval with
// py-motmetrics 1.4.0), including its quirks by default.
//
// Pose estimation (mAP): per frame, the PCKh of each prediction against each ground-truth person
// is the fraction of that person's annotated joints within 0.5 head sizes (head size = 0.6 x the
// head box diagonal). Each prediction keeps only its best person, each person then takes the
// prediction with the highest remaining PCKh, ties to the first; the others are false positives.
// Per joint, the (score, matched) pairs of all frames, sorted by score, give a VOC-style AP.
//
// Tracking (MOTA, MOTP, precision, recall): each joint class is tracked on its own. Per frame and
// joint a MotAccumulator (py-motmetrics' MOTAccumulator) gets the ground-truth track ids, the
// predicted track ids and the distances d <= 0.5 (others cannot match). Per joint:
//   MOTA = 1 - (misses + switches + false positives) / objects, precision = detections /
//   (detections + false positives), recall = detections / objects, MOTP = 1 - D / detections.
// Totals are means over the joints that are not NaN, not pooled counts; all in percent.
//
// Identity (IDF1, IDP, IDR; Ristani et al. 2016, as py-motmetrics 1.4.0 computes them from the
// same accumulator): per sequence and joint, every ground-truth id is paired with at most one
// predicted id for the whole sequence, by a global min-cost assignment that maximises IDTP, the
// number of frames in which the paired ids are within the threshold (d <= 0.5, the MOTA distance;
// any pair within it counts, not only the frame's MOTA match). IDFN = objects - IDTP, IDFP =
// predicted appearances - IDTP; IDF1 = 2 IDTP / (2 IDTP + IDFP + IDFN), IDP = IDTP / (IDTP +
// IDFP), IDR = IDTP / (IDTP + IDFN). A joint's figures come from its counts summed over the
// sequences (motmetrics' overall row); the total and the body parts from the counts summed over
// their joints (not a mean over joints, unlike MOTA).
//
// HOTA (PoseTrack21 ranks by it; hota.hpp): per sequence and joint, over every labelled frame
// (poseval's quirks 1-2 do not apply), with PoseTrack21's keypoint similarity max(0, 1 - d /
// 0.5001) of the head-normalised distance d and its matching on that similarity alone; a joint's
// figures from its counts over the sequences (TrackEval's combination), the total and the body
// parts from the counts of their joints pooled, as IDF1's. (PoseTrack21's tool averages some
// total fields over joints instead, so its total can differ slightly; each joint's is its own.)
//
// poseval's quirks, kept by default (PoseTrackEvalOptions turns each off):
//   1. the tracking part ignores the last labelled frame of every sequence;
//   2. a frame without ground truth or without predictions counts 1 miss + 1 false positive per
//      joint, whatever the number of people in it;
//   3. D sums every distance motmetrics records, not only those of the matches: all pairs within
//      the threshold (its RAW events) and the extra events of switches (ASCEND, TRANSFER, MIGRATE);
//   4. a joint without ground truth or predictions (the nose in the Bonn data) scores AP 0 and
//      MOTP 0, both averaged in; its MOTA, recall and precision are NaN and left out.
// Frames without ground-truth people are dropped before scoring (with their predictions), and
// joints inside the ground truth's ignore regions are removed from both sides, as poseval does.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "jointflow/hota.hpp"
#include "jointflow/posetrack.hpp"

namespace jointflow {

/// py-motmetrics 1.4.0's MOTAccumulator for one object class, counting its events.
/// update() does what MOTAccumulator.update does: first it keeps last frame's object ->
/// hypothesis pairs that can still match; then it pairs the rest optimally (most pairs, then
/// least total distance); a pair that differs from the object's previous hypothesis is a switch;
/// unpaired objects are misses, unpaired hypotheses false positives.
/// It also counts, per object, per hypothesis and per pair within the threshold, the frames they
/// appear in, from which counts() makes the identity figures (IDTP, IDFP, IDFN).
class MotAccumulator {
 public:
  struct Counts {
    std::int64_t objects = 0;          ///< ground-truth appearances
    std::int64_t matches = 0;          ///< MATCH events
    std::int64_t switches = 0;         ///< SWITCH events (identity switches)
    std::int64_t misses = 0;           ///< MISS events (false negatives)
    std::int64_t false_positives = 0;  ///< FP events
    std::int64_t frames = 0;
    double matched_distance = 0.0;        ///< sum of d over MATCH and SWITCH events
    double events_distance = 0.0;         ///< sum of d over all events (what poseval's MOTP uses)
    std::int64_t id_true_positives = 0;   ///< IDTP: frames of the globally paired ids in reach
    std::int64_t id_false_positives = 0;  ///< IDFP = predicted appearances - IDTP
    std::int64_t id_false_negatives = 0;  ///< IDFN = objects - IDTP
    std::int64_t detections() const { return matches + switches; }
    /// Predicted appearances (motmetrics' num_predictions): each is a detection or a FP.
    std::int64_t predictions() const { return matches + switches + false_positives; }
    Counts& operator+=(const Counts& o);
  };

  /// One frame. `distances` is row-major objects x hypotheses; a NaN or infinite entry means the
  /// pair cannot match. Ids must be unique within each list. Throws jointflow::Error otherwise.
  void update(const std::vector<std::int64_t>& object_ids,
              const std::vector<std::int64_t>& hypothesis_ids,
              const std::vector<double>& distances);

  /// The events so far, with the identity counts of the global id assignment over all frames so
  /// far (solved on each call).
  Counts counts() const;

 private:
  Counts counts_;
  /// (object, hypothesis) -> frames in which the pair is within the threshold (IDTP's input).
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> pair_frames_;
  std::int64_t frame_ = 0;
  std::map<std::int64_t, std::int64_t> match_of_object_;       ///< motmetrics' m
  std::map<std::int64_t, std::int64_t> object_of_hypothesis_;  ///< res_m (set by step 2 only)
  std::map<std::int64_t, std::int64_t> last_match_;            ///< object -> frame
  std::map<std::int64_t, std::int64_t> hypothesis_history_;    ///< hypothesis -> frame
};

/// Which of poseval's quirks to keep (see the top of this file). All true = poseval's numbers.
struct PoseTrackEvalOptions {
  bool drop_last_frame = true;       ///< quirk 1
  bool empty_frame_one_miss = true;  ///< quirk 2; false: every person / joint counts
  bool motp_all_events = true;       ///< quirk 3; false: D = distances of the matches only
  double pckh_threshold = 0.5;       ///< match radius in head sizes
};

struct JointScores {
  double ap = 0.0;                ///< percent
  double mota = 0.0;              ///< percent; NaN without ground truth
  double motp = 0.0;              ///< percent
  double precision = 0.0;         ///< percent; NaN without detections and false positives
  double recall = 0.0;            ///< percent; NaN without ground truth
  double idf1 = 0.0;              ///< percent; NaN without ground truth and predictions
  double id_precision = 0.0;      ///< IDP, percent; NaN without predictions
  double id_recall = 0.0;         ///< IDR, percent; NaN without ground truth
  MotAccumulator::Counts counts;  ///< summed over the sequences
  HotaCounts hota;                ///< summed over the sequences (the total: over the joints)
};

struct PoseTrackEvalResult {
  std::array<JointScores, posetrack::kNumPoseTrackJoints> joints;  ///< by PoseTrack joint id
  /// MOTA, MOTP, precision, recall, AP: means over the joints (NaN left out); counts summed;
  /// IDF1, IDP, IDR from the summed counts.
  JointScores total;
  std::vector<std::string> sequences;
};

/// Scores predictions against ground truth. Sequences pair by name; every ground-truth sequence
/// needs a prediction with as many frames (paired by position). Throws jointflow::Error for a
/// missing or mismatched sequence, a ground-truth person without head box or track id, a
/// prediction without track id, repeated track ids in a frame, or a sequence too short to track.
PoseTrackEvalResult evaluatePoseTrack(const std::vector<posetrack::Sequence>& ground_truth,
                                      const std::vector<posetrack::Sequence>& predictions,
                                      const PoseTrackEvalOptions& options = {});

/// Reads both sides (files or folders, see posetrack::listSequenceFiles) and scores them.
/// Prediction sequences pair with the ground truth by file name.
PoseTrackEvalResult evaluatePoseTrackFiles(const std::string& ground_truth_path,
                                           const std::string& predictions_path,
                                           const PoseTrackEvalOptions& options = {});

/// poseval's printed tables: AP and MOT by body part (Head = mean of head top, neck and nose,
/// then shoulders, elbows, wrists, hips, knees, ankles, total), IDF1 by body part (from the
/// part's summed counts), then every joint.
std::string formatPoseTrackTables(const PoseTrackEvalResult& result);

/// {"total": {"mota", "motp", "precision", "recall", "map", "idf1", "idp", "idr", ...counts},
/// "joints": {name: {...}}}, in percent; NaN becomes null.
std::string poseTrackResultJson(const PoseTrackEvalResult& result);

}  // namespace jointflow
