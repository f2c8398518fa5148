// MOTChallenge box evaluation (mot_evaluation.hpp): TrackEval's preprocessing, CLEAR MOT and
// identity through the motmetrics-equivalent MotAccumulator, and TrackEval's HOTA (hota.cpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

#include "jointflow/error.hpp"
#include "jointflow/mot_evaluation.hpp"
#include "linear_assignment.hpp"

namespace jointflow::mot {

namespace fs = std::filesystem;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

/// TrackEval's _calculate_box_ious for x, y, w, h boxes (no +1 pixel).
double iou(const Box& a, const Box& b) {
  const double w = std::min(a.x + a.w, b.x + b.w) - std::max(a.x, b.x);
  const double h = std::min(a.y + a.h, b.y + b.h) - std::max(a.y, b.y);
  if (w <= 0 || h <= 0) return 0.0;
  const double inter = w * h;
  const double uni = a.w * a.h + b.w * b.h - inter;
  return uni > 0 ? inter / uni : 0.0;
}

std::vector<double> iouMatrix(const std::vector<Box>& gt, const std::vector<Box>& pred) {
  std::vector<double> m(gt.size() * pred.size());
  for (std::size_t i = 0; i < gt.size(); ++i) {
    for (std::size_t j = 0; j < pred.size(); ++j) m[i * pred.size() + j] = iou(gt[i], pred[j]);
  }
  return m;
}

/// MOT17's distractors (TrackEval): static person, distractor, reflection, person on vehicle.
bool isDistractor(const Box& gt, double min_visibility) {
  if (gt.cls == 2 || gt.cls == 7 || gt.cls == 8 || gt.cls == 12) return true;
  // The addition to TrackEval's rule (see the header): a barely visible pedestrian.
  return gt.cls == 1 && gt.flag != 0 && gt.visibility < min_visibility;
}

/// One frame after preprocessing.
struct Frame {
  std::vector<Box> gt, pred;
  std::vector<double> similarity;  ///< IoU, gt rows x pred columns
};

Frame preprocess(const std::vector<Box>& gt_all, const std::vector<Box>& pred_all,
                 const MotEvalOptions& o) {
  std::vector<Box> pred;
  for (const Box& b : pred_all) {
    if (b.confidence >= o.min_score) pred.push_back(b);
  }
  // Step 1: predictions on distractors go. TrackEval matches at a fixed 0.5 here, whatever the
  // CLEAR threshold.
  std::vector<bool> remove(pred.size(), false);
  if (!gt_all.empty() && !pred.empty()) {
    std::vector<double> scores = iouMatrix(gt_all, pred);
    for (double& s : scores) {
      if (s < 0.5 - kEps) s = 0.0;
    }
    const auto cols = eval::maxScoreAssignment(scores, static_cast<int>(gt_all.size()),
                                               static_cast<int>(pred.size()));
    for (std::size_t r = 0; r < gt_all.size(); ++r) {
      const int c = cols[r];
      if (c >= 0 && scores[r * pred.size() + c] > kEps && isDistractor(gt_all[r], o.min_visibility))
        remove[c] = true;
    }
  }
  Frame f;
  for (std::size_t j = 0; j < pred.size(); ++j) {
    if (!remove[j]) f.pred.push_back(pred[j]);
  }
  // Step 2: pedestrians to be evaluated.
  for (const Box& b : gt_all) {
    if (b.cls == 1 && b.flag != 0 && !isDistractor(b, o.min_visibility)) f.gt.push_back(b);
  }
  f.similarity = iouMatrix(f.gt, f.pred);
  return f;
}

double percent(double num, double den) {
  return den > 0 ? 100.0 * num / den : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

double MotScores::recall() const {
  return percent(static_cast<double>(clear.detections()), static_cast<double>(clear.objects));
}
double MotScores::precision() const {
  return percent(static_cast<double>(clear.detections()),
                 static_cast<double>(clear.predictions()));
}
double MotScores::mota() const {
  const auto errors = clear.misses + clear.switches + clear.false_positives;
  return clear.objects > 0 ? 100.0 - percent(static_cast<double>(errors),
                                             static_cast<double>(clear.objects))
                           : std::numeric_limits<double>::quiet_NaN();
}
double MotScores::motp() const {
  return percent(matched_iou, static_cast<double>(clear.detections()));
}
double MotScores::idf1() const {
  const double tp = static_cast<double>(clear.id_true_positives);
  return percent(2 * tp, 2 * tp + static_cast<double>(clear.id_false_positives +
                                                      clear.id_false_negatives));
}
double MotScores::idp() const {
  const double tp = static_cast<double>(clear.id_true_positives);
  return percent(tp, tp + static_cast<double>(clear.id_false_positives));
}
double MotScores::idr() const {
  const double tp = static_cast<double>(clear.id_true_positives);
  return percent(tp, tp + static_cast<double>(clear.id_false_negatives));
}

MotScores& MotScores::operator+=(const MotScores& o) {
  frames += o.frames;
  gt_dets += o.gt_dets;
  pred_dets += o.pred_dets;
  gt_ids += o.gt_ids;
  pred_ids += o.pred_ids;
  clear += o.clear;
  matched_iou += o.matched_iou;
  hota += o.hota;
  return *this;
}

MotScores evaluateSequence(const Frames& ground_truth, const Frames& predictions,
                           const MotEvalOptions& options) {
  if (!(options.iou_threshold > 0 && options.iou_threshold <= 1)) {
    throw Error("MOT evaluation: the IoU threshold must be in (0, 1], got " +
                std::to_string(options.iou_threshold));
  }
  static const std::vector<Box> kNone;
  MotScores s;
  s.frames = static_cast<std::int64_t>(ground_truth.size());
  std::set<std::int64_t> gt_ids_seen, pred_ids_seen;
  std::vector<HotaFrame> hota_frames;
  MotAccumulator acc;
  const double max_distance = 1.0 - options.iou_threshold;
  for (std::size_t t = 0; t < ground_truth.size(); ++t) {
    const Frame f =
        preprocess(ground_truth[t], t < predictions.size() ? predictions[t] : kNone, options);
    s.gt_dets += static_cast<std::int64_t>(f.gt.size());
    s.pred_dets += static_cast<std::int64_t>(f.pred.size());
    std::vector<std::int64_t> gt_ids, pred_ids;
    for (const Box& b : f.gt) gt_ids.push_back(b.id);
    for (const Box& b : f.pred) pred_ids.push_back(b.id);
    gt_ids_seen.insert(gt_ids.begin(), gt_ids.end());
    pred_ids_seen.insert(pred_ids.begin(), pred_ids.end());
    hota_frames.push_back({gt_ids, pred_ids, f.similarity});
    std::vector<double> d(f.similarity.size());
    for (std::size_t k = 0; k < d.size(); ++k) {
      // motmetrics' iou_matrix(max_iou=0.5): a distance 1 - IoU above it cannot match.
      const double dist = 1.0 - f.similarity[k];
      d[k] = dist <= max_distance ? dist : std::numeric_limits<double>::quiet_NaN();
    }
    acc.update(gt_ids, pred_ids, d);
  }
  s.gt_ids = static_cast<std::int64_t>(gt_ids_seen.size());
  s.pred_ids = static_cast<std::int64_t>(pred_ids_seen.size());
  s.clear = acc.counts();
  s.matched_iou = static_cast<double>(s.clear.detections()) - s.clear.matched_distance;
  s.hota = hotaOfSequence(hota_frames, HotaMatching::kAligned);
  return s;
}

MotEvalResult evaluateFiles(const std::string& gt_path, const std::string& pred_path,
                            const MotEvalOptions& options) {
  const std::vector<GroundTruthSequence> sequences = readGroundTruth(gt_path);
  MotEvalResult result;
  const bool pred_is_folder = fs::is_directory(pred_path);
  if (!pred_is_folder && sequences.size() > 1) {
    throw Error(gt_path + " holds " + std::to_string(sequences.size()) +
                " sequences: --pred must be a folder with a <sequence>.txt or .jsonl for each");
  }
  for (const GroundTruthSequence& seq : sequences) {
    std::string file = pred_path;
    if (pred_is_folder) {
      file.clear();
      for (const char* ext : {".txt", ".jsonl", ".json"}) {
        const fs::path candidate = fs::path(pred_path) / (seq.name + ext);
        if (fs::is_regular_file(candidate)) {
          file = candidate.string();
          break;
        }
      }
      if (file.empty()) {
        throw Error(pred_path + ": no predictions for sequence " + seq.name + " (expected " +
                    seq.name + ".txt or " + seq.name + ".jsonl)");
      }
    }
    const Frames predictions = readPredictions(file, seq.frames.size());
    result.sequences.emplace_back(seq.name, evaluateSequence(seq.frames, predictions, options));
    result.combined += result.sequences.back().second;
  }
  return result;
}

}  // namespace jointflow::mot
