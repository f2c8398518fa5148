#include "ground_truth_ids.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "jointflow/evaluation.hpp"

namespace jointflow::bench {
namespace pt = jointflow::posetrack;

JointAgreement jointAgreement(const pt::Person& gt, const pt::Person& pred) {
  JointAgreement a;
  if (!gt.head_box) return a;
  const double head =
      0.6 * std::hypot(gt.head_box->x2 - gt.head_box->x1, gt.head_box->y2 - gt.head_box->y1);
  for (int j = 0; j < pt::kNumPoseTrackJoints; ++j) {
    if (!gt.joints[j]) continue;
    ++a.annotated;
    const auto& b = pred.joints[j];
    if (b && std::hypot(gt.joints[j]->x - b->x, gt.joints[j]->y - b->y) <= 0.5 * head) ++a.close;
  }
  return a;
}

namespace {

struct Pair {
  double score;
  size_t g, p;
};

/// Ground-truth person g and pose p paired one to one, highest score first (stable: ties keep
/// the order of the ground truth, then of the poses).
std::vector<Pair> greedyPairs(std::vector<Pair> pairs) {
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const Pair& x, const Pair& y) { return x.score > y.score; });
  std::vector<Pair> kept;
  std::set<size_t> used_g, used_p;
  for (const Pair& q : pairs) {
    if (used_g.count(q.g) || used_p.count(q.p)) continue;
    used_g.insert(q.g);
    used_p.insert(q.p);
    kept.push_back(q);
  }
  return kept;
}

}  // namespace

std::map<std::int64_t, std::int64_t> personIds(const pt::Frame& gt, const pt::Frame& pred) {
  std::vector<Pair> pairs;
  for (size_t g = 0; g < gt.people.size(); ++g) {
    if (!gt.people[g].track_id) continue;
    for (size_t p = 0; p < pred.people.size(); ++p) {
      const JointAgreement a = jointAgreement(gt.people[g], pred.people[p]);
      const double pckh = a.annotated ? static_cast<double>(a.close) / a.annotated : 0.0;
      if (pckh >= 0.5) pairs.push_back({pckh, g, p});
    }
  }
  std::map<std::int64_t, std::int64_t> out;
  for (const Pair& q : greedyPairs(pairs))
    out[*gt.people[q.g].track_id] = *pred.people[q.p].track_id;
  return out;
}

pt::Sequence withGroundTruthIds(const pt::Sequence& gt, const pt::Sequence& pred) {
  std::int64_t next = 0;  // ids for unpaired poses start above every ground-truth id
  for (const pt::Frame& f : gt.frames)
    for (const pt::Person& a : f.people)
      if (a.track_id) next = std::max(next, *a.track_id + 1);
  pt::Sequence out = pred;
  for (size_t f = 0; f < out.frames.size() && f < gt.frames.size(); ++f) {
    pt::Frame& frame = out.frames[f];
    std::vector<Pair> pairs;
    for (size_t g = 0; g < gt.frames[f].people.size(); ++g) {
      if (!gt.frames[f].people[g].track_id) continue;
      for (size_t p = 0; p < frame.people.size(); ++p) {
        const int close = jointAgreement(gt.frames[f].people[g], frame.people[p]).close;
        if (close > 0) pairs.push_back({static_cast<double>(close), g, p});
      }
    }
    std::vector<bool> paired(frame.people.size(), false);
    for (const Pair& q : greedyPairs(pairs)) {
      frame.people[q.p].track_id = gt.frames[f].people[q.g].track_id;
      paired[q.p] = true;
    }
    for (size_t p = 0; p < frame.people.size(); ++p)
      if (!paired[p]) frame.people[p].track_id = next++;
  }
  return out;
}

std::int64_t groundTruthIdSwitches(const std::vector<pt::Sequence>& gt,
                                   const std::vector<pt::Sequence>& pred) {
  std::vector<pt::Sequence> relabelled;
  for (size_t i = 0; i < gt.size() && i < pred.size(); ++i)
    relabelled.push_back(withGroundTruthIds(gt[i], pred[i]));
  return evaluatePoseTrack(gt, relabelled).total.counts.switches;
}

std::int64_t personIdSwitches(const pt::Sequence& gt, const pt::Sequence& pred) {
  std::map<std::int64_t, std::int64_t> last;  // ground-truth id -> the predicted id it last had
  std::int64_t switches = 0;
  for (size_t f = 0; f < gt.frames.size() && f < pred.frames.size(); ++f)
    for (const auto& [person, id] : personIds(gt.frames[f], pred.frames[f])) {
      const auto [it, first] = last.try_emplace(person, id);
      if (!first && it->second != id) ++switches;
      it->second = id;
    }
  return switches;
}

}  // namespace jointflow::bench
