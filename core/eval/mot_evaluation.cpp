// MOTChallenge box evaluation (mot_evaluation.hpp): TrackEval's preprocessing, CLEAR MOT and
// identity through the motmetrics-equivalent MotAccumulator, and TrackEval's HOTA.
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

/// Dense indices of the ids that remain after preprocessing (TrackEval relabels them so).
struct IdIndex {
  std::map<std::int64_t, int> gt, pred;
  void add(const Frame& f) {
    for (const Box& b : f.gt) gt.emplace(b.id, static_cast<int>(gt.size()));
    for (const Box& b : f.pred) pred.emplace(b.id, static_cast<int>(pred.size()));
  }
};

double alpha(int a) { return 0.05 * (a + 1); }

/// TrackEval's HOTA.eval_sequence.
HotaCounts hotaOfSequence(const std::vector<Frame>& frames, const IdIndex& ids) {
  HotaCounts h;
  const std::size_t ng = ids.gt.size(), np = ids.pred.size();
  std::int64_t gt_dets = 0, pred_dets = 0;
  for (const Frame& f : frames) {
    gt_dets += static_cast<std::int64_t>(f.gt.size());
    pred_dets += static_cast<std::int64_t>(f.pred.size());
  }
  if (pred_dets == 0 || gt_dets == 0) {
    h.fn.fill(static_cast<double>(pred_dets == 0 ? gt_dets : 0));
    h.fp.fill(static_cast<double>(pred_dets == 0 ? 0 : pred_dets));
    return h;  // LocA stays 0 here; the final figure makes it 1, as TrackEval reports it
  }
  // The global alignment score of each id pair: how much the two ids overlap over the sequence,
  // each frame's similarity shared out among the competing ids (TrackEval's sim_iou).
  std::vector<double> potential(ng * np, 0.0), gt_count(ng, 0.0), pred_count(np, 0.0);
  for (const Frame& f : frames) {
    const std::size_t n = f.gt.size(), m = f.pred.size();
    std::vector<double> row_sum(n, 0.0), col_sum(m, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < m; ++j) {
        row_sum[i] += f.similarity[i * m + j];
        col_sum[j] += f.similarity[i * m + j];
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      const int g = ids.gt.at(f.gt[i].id);
      gt_count[g] += 1;
      for (std::size_t j = 0; j < m; ++j) {
        const double s = f.similarity[i * m + j];
        const double denom = row_sum[i] + col_sum[j] - s;
        if (denom > kEps) potential[g * np + ids.pred.at(f.pred[j].id)] += s / denom;
      }
    }
    for (std::size_t j = 0; j < m; ++j) pred_count[ids.pred.at(f.pred[j].id)] += 1;
  }
  std::vector<double> alignment(ng * np);
  for (std::size_t g = 0; g < ng; ++g) {
    for (std::size_t p = 0; p < np; ++p) {
      const double pm = potential[g * np + p];
      alignment[g * np + p] = pm / (gt_count[g] + pred_count[p] - pm);
    }
  }
  std::vector<std::vector<double>> matches(kHotaAlphas, std::vector<double>(ng * np, 0.0));
  std::array<double, kHotaAlphas> loc_sum{};
  for (const Frame& f : frames) {
    const std::size_t n = f.gt.size(), m = f.pred.size();
    if (n == 0 || m == 0) {
      for (int a = 0; a < kHotaAlphas; ++a) {
        h.fp[a] += static_cast<double>(m);
        h.fn[a] += static_cast<double>(n);
      }
      continue;
    }
    std::vector<double> score(n * m);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < m; ++j) {
        score[i * m + j] = alignment[ids.gt.at(f.gt[i].id) * np + ids.pred.at(f.pred[j].id)] *
                           f.similarity[i * m + j];
      }
    }
    const auto cols = eval::maxScoreAssignment(score, static_cast<int>(n), static_cast<int>(m));
    for (int a = 0; a < kHotaAlphas; ++a) {
      double tp = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const int j = cols[i];
        if (j < 0) continue;
        const double s = f.similarity[i * m + j];
        if (s < alpha(a) - kEps) continue;
        tp += 1;
        loc_sum[a] += s;
        matches[a][ids.gt.at(f.gt[i].id) * np + ids.pred.at(f.pred[j].id)] += 1;
      }
      h.tp[a] += tp;
      h.fn[a] += static_cast<double>(n) - tp;
      h.fp[a] += static_cast<double>(m) - tp;
    }
  }
  for (int a = 0; a < kHotaAlphas; ++a) {
    double ass_a = 0, ass_re = 0, ass_pr = 0;
    for (std::size_t g = 0; g < ng; ++g) {
      for (std::size_t p = 0; p < np; ++p) {
        const double c = matches[a][g * np + p];
        if (c == 0) continue;
        ass_a += c * c / std::max(1.0, gt_count[g] + pred_count[p] - c);
        ass_re += c * c / std::max(1.0, gt_count[g]);
        ass_pr += c * c / std::max(1.0, pred_count[p]);
      }
    }
    // TrackEval divides these by max(1, TP) per sequence and weights them by TP to combine; the
    // sums themselves are what both steps keep. Its LocA is weighted the same way.
    h.ass_a[a] = ass_a;
    h.ass_re[a] = ass_re;
    h.ass_pr[a] = ass_pr;
    h.loc_a[a] = loc_sum[a];
  }
  return h;
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

MotScores::Hota MotScores::hotaScores() const {
  // TrackEval's _compute_final_fields, then the mean over the alphas, in percent.
  Hota out;
  for (int a = 0; a < kHotaAlphas; ++a) {
    const double tp = hota.tp[a], fn = hota.fn[a], fp = hota.fp[a];
    const double ass_a = hota.ass_a[a] / std::max(1.0, tp);
    const double det_a = tp / std::max(1.0, tp + fn + fp);
    out.hota[a] = 100.0 * std::sqrt(det_a * ass_a);
    out.mean_hota += out.hota[a];
    out.deta += 100.0 * det_a;
    out.assa += 100.0 * ass_a;
    out.detre += 100.0 * tp / std::max(1.0, tp + fn);
    out.detpr += 100.0 * tp / std::max(1.0, tp + fp);
    out.assre += 100.0 * hota.ass_re[a] / std::max(1.0, tp);
    out.asspr += 100.0 * hota.ass_pr[a] / std::max(1.0, tp);
    out.loca += 100.0 * std::max(1e-10, hota.loc_a[a]) / std::max(1e-10, tp);
  }
  for (double* v : {&out.mean_hota, &out.deta, &out.assa, &out.loca, &out.detre, &out.detpr,
                    &out.assre, &out.asspr}) {
    *v /= kHotaAlphas;
  }
  return out;
}

MotScores& MotScores::operator+=(const MotScores& o) {
  frames += o.frames;
  gt_dets += o.gt_dets;
  pred_dets += o.pred_dets;
  gt_ids += o.gt_ids;
  pred_ids += o.pred_ids;
  clear += o.clear;
  matched_iou += o.matched_iou;
  for (int a = 0; a < kHotaAlphas; ++a) {
    hota.tp[a] += o.hota.tp[a];
    hota.fn[a] += o.hota.fn[a];
    hota.fp[a] += o.hota.fp[a];
    hota.ass_a[a] += o.hota.ass_a[a];
    hota.ass_re[a] += o.hota.ass_re[a];
    hota.ass_pr[a] += o.hota.ass_pr[a];
    hota.loc_a[a] += o.hota.loc_a[a];
  }
  return *this;
}

MotScores evaluateSequence(const Frames& ground_truth, const Frames& predictions,
                           const MotEvalOptions& options) {
  if (!(options.iou_threshold > 0 && options.iou_threshold <= 1)) {
    throw Error("MOT evaluation: the IoU threshold must be in (0, 1], got " +
                std::to_string(options.iou_threshold));
  }
  std::vector<Frame> frames;
  frames.reserve(ground_truth.size());
  IdIndex ids;
  static const std::vector<Box> kNone;
  for (std::size_t t = 0; t < ground_truth.size(); ++t) {
    frames.push_back(
        preprocess(ground_truth[t], t < predictions.size() ? predictions[t] : kNone, options));
    ids.add(frames.back());
  }
  MotScores s;
  s.frames = static_cast<std::int64_t>(frames.size());
  s.gt_ids = static_cast<std::int64_t>(ids.gt.size());
  s.pred_ids = static_cast<std::int64_t>(ids.pred.size());
  MotAccumulator acc;
  const double max_distance = 1.0 - options.iou_threshold;
  for (const Frame& f : frames) {
    s.gt_dets += static_cast<std::int64_t>(f.gt.size());
    s.pred_dets += static_cast<std::int64_t>(f.pred.size());
    std::vector<std::int64_t> gt_ids, pred_ids;
    for (const Box& b : f.gt) gt_ids.push_back(b.id);
    for (const Box& b : f.pred) pred_ids.push_back(b.id);
    std::vector<double> d(f.similarity.size());
    for (std::size_t k = 0; k < d.size(); ++k) {
      // motmetrics' iou_matrix(max_iou=0.5): a distance 1 - IoU above it cannot match.
      const double dist = 1.0 - f.similarity[k];
      d[k] = dist <= max_distance ? dist : std::numeric_limits<double>::quiet_NaN();
    }
    acc.update(gt_ids, pred_ids, d);
  }
  s.clear = acc.counts();
  s.matched_iou = static_cast<double>(s.clear.detections()) - s.clear.matched_distance;
  s.hota = hotaOfSequence(frames, ids);
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
