// HOTA, Higher Order Tracking Accuracy (Luiten et al., IJCV 2020), as TrackEval computes it: at
// each threshold alpha = 0.05, 0.10, ..., 0.95 on a similarity in [0, 1], detections are matched
// one to one per frame; DetA = TP / (TP + FN + FP) says how much is found, AssA, the mean over the
// true positives of TPA / (TPA + FNA + FPA) of their pair of ids, says how well ids hold, and
// HOTA = sqrt(DetA x AssA). Reported figures are means over the alphas.
//
// Used for boxes (mot_evaluation.hpp: similarity IoU, TrackEval's MOT HOTA) and for PoseTrack joints
// (evaluation.hpp: per joint, similarity max(0, 1 - d / 0.5001) of the head-normalised distance d,
// as PoseTrack21's keypoint HOTA).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace jointflow {

/// The HOTA thresholds alpha = 0.05, 0.10, ..., 0.95.
constexpr int kHotaAlphas = 19;

/// One frame: the ids on both sides (unique within the frame) and their similarities.
struct HotaFrame {
  std::vector<std::int64_t> gt_ids, pred_ids;
  std::vector<double> similarity;  ///< gt rows x pred columns, row-major, in [0, 1]
};

/// How each frame's one-to-one matching is chosen (the Hungarian method, maximum total).
enum class HotaMatching {
  /// TrackEval's: similarity x the pair's global alignment score over the sequence, so that
  /// pairs which stay together win ties of position.
  kAligned,
  /// PoseTrack21's keypoint HOTA: the similarity alone.
  kSimilarity,
};

/// HOTA's sums over the alphas, before the final ratios: what sequences combine by adding.
struct HotaCounts {
  std::array<double, kHotaAlphas> tp{}, fn{}, fp{};
  /// Association and localisation sums over the true positives (TrackEval weights each
  /// sequence's AssA, AssRe, AssPr and LocA by its TP to combine; these are those products).
  std::array<double, kHotaAlphas> ass_a{}, ass_re{}, ass_pr{}, loc_a{};
  HotaCounts& operator+=(const HotaCounts& other);
};

/// The final figures, percent: at each alpha and their means.
struct HotaScores {
  std::array<double, kHotaAlphas> hota{};
  double mean_hota = 0, deta = 0, assa = 0, loca = 0, detre = 0, detpr = 0, assre = 0, asspr = 0;
};

/// TrackEval's HOTA.eval_sequence on one sequence's frames.
HotaCounts hotaOfSequence(const std::vector<HotaFrame>& frames, HotaMatching matching);

/// TrackEval's _compute_final_fields, averaged over the alphas. With no true positive at an
/// alpha, LocA there is 1 (TrackEval's max(1e-10, .) / max(1e-10, .)).
HotaScores hotaScores(const HotaCounts& counts);

}  // namespace jointflow
