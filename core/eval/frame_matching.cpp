#include "frame_matching.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "jointflow/error.hpp"

namespace jointflow::eval {

using posetrack::kNumPoseTrackJoints;
using posetrack::Person;

namespace {

/// poseval's score for a predicted joint that has none (its MIN_SCORE).
constexpr double kMissingScore = -9999.0;

/// PCKh's reference length: 0.6 x the head box diagonal (poseval's getHeadSize).
double headSize(const Person& gt, const std::string& where) {
  if (!gt.head_box) {
    throw Error(where +
                ": a ground-truth person has no head box (x1..y2 / bbox_head), which "
                "PCKh needs");
  }
  const auto& b = *gt.head_box;
  return 0.6 * std::hypot(b.x2 - b.x1, b.y2 - b.y1);
}

std::int64_t trackIdOf(const Person& p, const char* side, const std::string& where) {
  if (!p.track_id) throw Error(where + ": a " + side + " person has no track_id");
  return *p.track_id;
}

}  // namespace

FrameMatch matchFrame(const posetrack::Frame& gt, const posetrack::Frame& pred, double threshold,
                      bool empty_frame_one_miss, const std::string& where) {
  const int ng = static_cast<int>(gt.people.size());
  const int np = static_cast<int>(pred.people.size());
  const double inf = std::numeric_limits<double>::infinity();
  FrameMatch out;
  for (const Person& g : gt.people) {
    for (int j = 0; j < kNumPoseTrackJoints; ++j) out.num_gt[j] += g.joints[j] ? 1 : 0;
  }
  auto scoreOf = [](const posetrack::PoseTrackPoint& p) { return p.score.value_or(kMissingScore); };

  if (ng == 0 || np == 0) {
    for (const Person& p : pred.people) {  // no ground truth: every predicted joint is false
      for (int j = 0; j < kNumPoseTrackJoints; ++j) {
        if (p.joints[j]) out.scored[j].push_back({scoreOf(*p.joints[j]), false});
      }
    }
    for (int j = 0; j < kNumPoseTrackJoints; ++j) {
      HotaFrame& hota = out.hota[j];  // one side is empty: nothing to pair
      for (const Person& g : gt.people) {
        if (g.joints[j]) hota.gt_ids.push_back(trackIdOf(g, "ground-truth", where));
      }
      for (const Person& p : pred.people) {
        if (p.joints[j]) hota.pred_ids.push_back(trackIdOf(p, "predicted", where));
      }
      JointMotInput& mot = out.mot[j];
      if (empty_frame_one_miss) {
        // poseval's quirk: one object 0 and one hypothesis 0 that cannot pair.
        mot.gt_ids = {0};
        mot.pred_ids = {0};
      } else {
        mot.gt_ids = hota.gt_ids;
        mot.pred_ids = hota.pred_ids;
      }
      mot.distances.assign(mot.gt_ids.size() * mot.pred_ids.size(), std::nan(""));
    }
    return out;
  }

  // dist[p][g][j] in head sizes; infinite where either side lacks the joint.
  std::vector<double> dist(static_cast<std::size_t>(np) * ng * kNumPoseTrackJoints, inf);
  auto at = [&](int p, int g, int j) -> double& {
    return dist[(static_cast<std::size_t>(p) * ng + g) * kNumPoseTrackJoints + j];
  };
  for (int g = 0; g < ng; ++g) {
    const double head = headSize(gt.people[g], where);
    for (int p = 0; p < np; ++p) {
      for (int j = 0; j < kNumPoseTrackJoints; ++j) {
        const auto& a = gt.people[g].joints[j];
        const auto& b = pred.people[p].joints[j];
        if (a && b) at(p, g, j) = std::hypot(a->x - b->x, a->y - b->y) / head;
      }
    }
  }
  auto matches = [&](int p, int g, int j) { return at(p, g, j) <= threshold; };

  // PCKh of every prediction against every person, then each prediction keeps its best person.
  std::vector<double> pck(static_cast<std::size_t>(np) * ng, 0.0);
  for (int p = 0; p < np; ++p) {
    for (int g = 0; g < ng; ++g) {
      int matched = 0, annotated = 0;
      for (int j = 0; j < kNumPoseTrackJoints; ++j) {
        matched += matches(p, g, j) ? 1 : 0;
        annotated += gt.people[g].joints[j] ? 1 : 0;
      }
      pck[p * ng + g] = annotated > 0 ? static_cast<double>(matched) / annotated : matched;
    }
    int best = 0;  // first maximum, as numpy's argmax
    for (int g = 1; g < ng; ++g) {
      if (pck[p * ng + g] > pck[p * ng + best]) best = g;
    }
    for (int g = 0; g < ng; ++g) {
      if (g != best) pck[p * ng + g] = 0.0;
    }
  }
  // Each person takes the prediction with the highest remaining PCKh (none when it is 0).
  std::vector<int> gt_of_pred(np, -1);
  for (int g = 0; g < ng; ++g) {
    int best = 0;
    for (int p = 1; p < np; ++p) {
      if (pck[p * ng + g] > pck[best * ng + g]) best = p;
    }
    if (pck[best * ng + g] != 0.0) gt_of_pred[best] = g;
  }

  for (int p = 0; p < np; ++p) {
    const int g = gt_of_pred[p];
    for (int j = 0; j < kNumPoseTrackJoints; ++j) {
      const auto& b = pred.people[p].joints[j];
      if (b) out.scored[j].push_back({scoreOf(*b), g >= 0 && matches(p, g, j)});
    }
  }

  for (int j = 0; j < kNumPoseTrackJoints; ++j) {
    std::vector<int> gs, ps;
    JointMotInput& mot = out.mot[j];
    for (int g = 0; g < ng; ++g) {
      if (!gt.people[g].joints[j]) continue;
      gs.push_back(g);
      mot.gt_ids.push_back(trackIdOf(gt.people[g], "ground-truth", where));
    }
    for (int p = 0; p < np; ++p) {
      if (!pred.people[p].joints[j]) continue;
      ps.push_back(p);
      mot.pred_ids.push_back(trackIdOf(pred.people[p], "predicted", where));
    }
    mot.distances.assign(gs.size() * ps.size(), std::nan(""));
    HotaFrame& hota = out.hota[j];
    hota.gt_ids = mot.gt_ids;
    hota.pred_ids = mot.pred_ids;
    hota.similarity.assign(gs.size() * ps.size(), 0.0);
    for (std::size_t a = 0; a < gs.size(); ++a) {
      for (std::size_t b = 0; b < ps.size(); ++b) {
        const double d = at(ps[b], gs[a], j);
        if (matches(ps[b], gs[a], j)) mot.distances[a * ps.size() + b] = d;
        // PoseTrack21's distance2sim: 1 at the same place, 0 from half a head size on.
        hota.similarity[a * ps.size() + b] = std::max(0.0, 1.0 - d / 0.5001);
      }
    }
  }
  return out;
}

}  // namespace jointflow::eval
