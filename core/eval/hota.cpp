// HOTA as TrackEval computes it (hota.hpp).
#include "jointflow/hota.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "linear_assignment.hpp"

namespace jointflow {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

double alpha(int a) { return 0.05 * (a + 1); }

/// Dense indices of the ids of a sequence (TrackEval relabels them so).
std::map<std::int64_t, int> indexIds(const std::vector<HotaFrame>& frames,
                                     std::vector<std::int64_t> HotaFrame::*ids) {
  std::map<std::int64_t, int> index;
  for (const HotaFrame& f : frames) {
    for (std::int64_t id : f.*ids) index.emplace(id, static_cast<int>(index.size()));
  }
  return index;
}

}  // namespace

HotaCounts& HotaCounts::operator+=(const HotaCounts& o) {
  for (int a = 0; a < kHotaAlphas; ++a) {
    tp[a] += o.tp[a];
    fn[a] += o.fn[a];
    fp[a] += o.fp[a];
    ass_a[a] += o.ass_a[a];
    ass_re[a] += o.ass_re[a];
    ass_pr[a] += o.ass_pr[a];
    loc_a[a] += o.loc_a[a];
  }
  return *this;
}

HotaCounts hotaOfSequence(const std::vector<HotaFrame>& frames, HotaMatching matching) {
  HotaCounts h;
  const auto gt_index = indexIds(frames, &HotaFrame::gt_ids);
  const auto pred_index = indexIds(frames, &HotaFrame::pred_ids);
  const std::size_t ng = gt_index.size(), np = pred_index.size();
  std::int64_t gt_dets = 0, pred_dets = 0;
  for (const HotaFrame& f : frames) {
    gt_dets += static_cast<std::int64_t>(f.gt_ids.size());
    pred_dets += static_cast<std::int64_t>(f.pred_ids.size());
  }
  if (pred_dets == 0 || gt_dets == 0) {
    h.fn.fill(static_cast<double>(pred_dets == 0 ? gt_dets : 0));
    h.fp.fill(static_cast<double>(pred_dets == 0 ? 0 : pred_dets));
    return h;  // LocA stays 0 here; the final figure makes it 1, as TrackEval reports it
  }
  // The global alignment score of each id pair: how much the two ids overlap over the sequence,
  // each frame's similarity shared out among the competing ids (TrackEval's sim_iou).
  std::vector<double> potential(ng * np, 0.0), gt_count(ng, 0.0), pred_count(np, 0.0);
  std::vector<std::vector<int>> gi(frames.size()), pi(frames.size());  // dense ids per frame
  for (std::size_t t = 0; t < frames.size(); ++t) {
    const HotaFrame& f = frames[t];
    for (std::int64_t id : f.gt_ids) gi[t].push_back(gt_index.at(id));
    for (std::int64_t id : f.pred_ids) pi[t].push_back(pred_index.at(id));
    const std::size_t n = gi[t].size(), m = pi[t].size();
    std::vector<double> row_sum(n, 0.0), col_sum(m, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < m; ++j) {
        row_sum[i] += f.similarity[i * m + j];
        col_sum[j] += f.similarity[i * m + j];
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      gt_count[gi[t][i]] += 1;
      for (std::size_t j = 0; j < m; ++j) {
        const double s = f.similarity[i * m + j];
        const double denom = row_sum[i] + col_sum[j] - s;
        if (denom > kEps) potential[gi[t][i] * np + pi[t][j]] += s / denom;
      }
    }
    for (int p : pi[t]) pred_count[p] += 1;
  }
  std::vector<double> alignment(ng * np);
  for (std::size_t g = 0; g < ng; ++g) {
    for (std::size_t p = 0; p < np; ++p) {
      const double pm = potential[g * np + p];
      alignment[g * np + p] = pm / std::max(1e-300, gt_count[g] + pred_count[p] - pm);
    }
  }
  std::vector<std::vector<double>> matches(kHotaAlphas, std::vector<double>(ng * np, 0.0));
  for (std::size_t t = 0; t < frames.size(); ++t) {
    const HotaFrame& f = frames[t];
    const std::size_t n = gi[t].size(), m = pi[t].size();
    if (n == 0 || m == 0) {
      for (int a = 0; a < kHotaAlphas; ++a) {
        h.fp[a] += static_cast<double>(m);
        h.fn[a] += static_cast<double>(n);
      }
      continue;
    }
    std::vector<double> score = f.similarity;
    if (matching == HotaMatching::kAligned) {
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < m; ++j) score[i * m + j] *= alignment[gi[t][i] * np + pi[t][j]];
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
        h.loc_a[a] += s;
        matches[a][gi[t][i] * np + pi[t][j]] += 1;
      }
      h.tp[a] += tp;
      h.fn[a] += static_cast<double>(n) - tp;
      h.fp[a] += static_cast<double>(m) - tp;
    }
  }
  for (int a = 0; a < kHotaAlphas; ++a) {
    for (std::size_t g = 0; g < ng; ++g) {
      for (std::size_t p = 0; p < np; ++p) {
        const double c = matches[a][g * np + p];
        if (c == 0) continue;
        h.ass_a[a] += c * c / std::max(1.0, gt_count[g] + pred_count[p] - c);
        h.ass_re[a] += c * c / std::max(1.0, gt_count[g]);
        h.ass_pr[a] += c * c / std::max(1.0, pred_count[p]);
      }
    }
  }
  return h;
}

HotaScores hotaScores(const HotaCounts& h) {
  HotaScores out;
  for (int a = 0; a < kHotaAlphas; ++a) {
    const double tp = h.tp[a], fn = h.fn[a], fp = h.fp[a];
    const double ass_a = h.ass_a[a] / std::max(1.0, tp);
    const double det_a = tp / std::max(1.0, tp + fn + fp);
    out.hota[a] = 100.0 * std::sqrt(det_a * ass_a);
    out.mean_hota += out.hota[a];
    out.deta += 100.0 * det_a;
    out.assa += 100.0 * ass_a;
    out.detre += 100.0 * tp / std::max(1.0, tp + fn);
    out.detpr += 100.0 * tp / std::max(1.0, tp + fp);
    out.assre += 100.0 * h.ass_re[a] / std::max(1.0, tp);
    out.asspr += 100.0 * h.ass_pr[a] / std::max(1.0, tp);
    out.loca += 100.0 * std::max(1e-10, h.loc_a[a]) / std::max(1e-10, tp);
  }
  for (double* v : {&out.mean_hota, &out.deta, &out.assa, &out.loca, &out.detre, &out.detpr,
                    &out.assre, &out.asspr}) {
    *v /= kHotaAlphas;
  }
  return out;
}

}  // namespace jointflow
