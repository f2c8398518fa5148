// Step 4 of PoseAssociator (pose_associator.hpp's list): the tracks matched on the previous
// inferred frame against this frame's poses, and the swaps their looks undo.
#include <algorithm>
#include <numeric>
#include <optional>

#include "jointflow/matching.hpp"
#include "track_book.hpp"

namespace jointflow {
namespace {

// Sub-matrix of potentials for the chosen rows and columns.
Potentials select(const Potentials& p, const std::vector<int>& rows, const std::vector<int>& cols) {
  Potentials out{
      cv::Mat::zeros(static_cast<int>(rows.size()), static_cast<int>(cols.size()), CV_32F),
      cv::Mat::zeros(static_cast<int>(rows.size()), static_cast<int>(cols.size()), CV_32F)};
  for (size_t r = 0; r < rows.size(); ++r)
    for (size_t c = 0; c < cols.size(); ++c) {
      out.psi.at<float>(r, c) = p.psi.at<float>(rows[r], cols[c]);
      out.per_joint.at<float>(r, c) = p.per_joint.at<float>(rows[r], cols[c]);
    }
  return out;
}

// TrackerSettings::tff_oks_weight and tff_flow_weight: the TFF's potential per joint of each pair
// mixed with the OKS of the track's prediction and the mean joint energy of the flow (Eq. 9),
// (1 - w_o - w_f) x the TFF's + w_o x OKS + w_f x E_flow, and Psi that mix times the joints in
// both, so that greedy matching still ranks pairs by their evidence in all (Eq. 7's sum). Without
// a flow (`flow` null) its weight goes to OKS: the mix stays on the same scale.
void mixWithGeometry(Potentials& tff, const Potentials& oks, const Potentials* flow, float w_oks,
                     float w_flow, const Poses& previous, const Poses& current,
                     const JointThresholds& thresholds) {
  if (!flow) {
    w_oks += w_flow;
    w_flow = 0.f;
  }
  for (int r = 0; r < tff.psi.rows; ++r)
    for (int c = 0; c < tff.psi.cols; ++c) {
      int joints = 0;
      for (int j = 0; j < kNumJoints; ++j)
        joints += isDetected(previous[r].keypoints[j], thresholds[j]) &&
                  isDetected(current[c].keypoints[j], thresholds[j]);
      float& per_joint = tff.per_joint.at<float>(r, c);
      per_joint = (1.f - w_oks - w_flow) * per_joint + w_oks * oks.psi.at<float>(r, c) +
                  (flow ? w_flow * flow->per_joint.at<float>(r, c) : 0.f);
      tff.psi.at<float>(r, c) = per_joint * static_cast<float>(joints);
    }
}

}  // namespace

// Step 4: the tracks matched on the previous inferred frame.
void PoseAssociator::Impl::matchActive(const AssociationFrame& in,
                                       const track_book::MotionCues& cues,
                                       const std::vector<int>& high, const std::vector<int>& low,
                                       FrameMatches& m) const {
  const cv::Mat &tff = cues.tff, &flow = cues.flow;
  std::vector<int> active;
  for (size_t t = 0; t < tracks.size(); ++t) {
    if (tracks[t].state != TrackState::kActive) continue;
    // After a gap (TrackerSettings::gap_time) a track that step 5 can recognise is left to it.
    if (confirmed(tracks[t]) && looksDecide(tracks[t], cues.after_gap)) continue;
    active.push_back(static_cast<int>(t));
  }
  std::vector<int> dets(high);
  dets.insert(dets.end(), low.begin(), low.end());
  if (active.empty() || dets.empty()) return;

  Poses current;
  for (int d : dets) current.push_back(in.poses[d]);
  // The TFF and the flow carry the apparent motion from where the joints were in the previous
  // frame (a TFF computed on camera-compensated maps: from there moved by the camera); the
  // geometric similarities compare with the prediction instead.
  const bool lacks =
      (similarity->needsTff() && tff.empty()) || (similarity->needsFlow() && flow.empty());
  const Similarity& primary = lacks ? *geometric : *similarity;
  const bool from_last = !lacks && (similarity->needsTff() || similarity->needsFlow());
  const bool compensated_tff = similarity->needsTff() && in.tff_camera_compensated;
  Poses previous;
  for (int t : active)
    previous.push_back(!from_last        ? tracks[t].motion.pose()
                       : compensated_tff ? movePose(tracks[t].last, camera, {0.f, 0.f})
                                         : tracks[t].last);
  // Without a TFF or flow between the two frames (the grid changed, a frame came without its
  // map) the geometric similarity stands in for this one frame.
  Potentials all = primary.compute(previous, current, {tff, in.grid_to_frame, flow});
  if (!lacks && similarity->needsTff() &&
      settings.tff_oks_weight + settings.tff_flow_weight > 0.f) {
    Poses predicted, last;
    for (int t : active) {
      predicted.push_back(tracks[t].motion.pose());
      last.push_back(tracks[t].last);  // the flow, like the frames, holds the camera's motion
    }
    std::optional<Potentials> moved;
    if (!cues.mix_flow.empty())
      moved = flow_energy->compute(last, current, {{}, {}, cues.mix_flow, cues.mix_flow_scale});
    mixWithGeometry(all, geometric->compute(predicted, current, {}), moved ? &*moved : nullptr,
                    settings.tff_oks_weight, settings.tff_flow_weight, previous, current,
                    thresholds);
  }

  const auto high_end = static_cast<int>(high.size());
  for (const bool high_pass : {true, false}) {
    std::vector<int> rows, cols;
    for (size_t r = 0; r < active.size(); ++r)
      if (!m.matched[active[r]]) rows.push_back(static_cast<int>(r));
    for (int c = high_pass ? 0 : high_end;
         c < (high_pass ? high_end : static_cast<int>(dets.size())); ++c)
      cols.push_back(c);
    if (rows.empty() || cols.empty()) continue;
    const Potentials p = select(all, rows, cols);
    for (const Match& mt :
         matchPoses(settings.matcher, p.psi, p.per_joint, settings.min_potential)) {
      m.matched[active[rows[mt.row]]] = true;
      m.track_of[dets[cols[mt.col]]] = active[rows[mt.row]];
    }
  }

  if (!settings.geometric_fallback) return;
  std::vector<int> rows, cols;
  for (int t : active)
    if (!m.matched[t]) rows.push_back(t);
  for (int d : high)
    if (m.track_of[d] < 0) cols.push_back(d);
  if (rows.empty() || cols.empty()) return;
  cv::Mat psi =
      cv::Mat::zeros(static_cast<int>(rows.size()), static_cast<int>(cols.size()), CV_32F);
  for (size_t r = 0; r < rows.size(); ++r)
    for (size_t c = 0; c < cols.size(); ++c)
      psi.at<float>(static_cast<int>(r), static_cast<int>(c)) =
          predictionOks(tracks[rows[r]], in.poses[cols[c]]);
  for (const Match& mt : matchPoses(settings.matcher, psi, psi, settings.coast_min_oks)) {
    m.matched[rows[mt.row]] = true;
    m.track_of[cols[mt.col]] = rows[mt.row];
  }
}

// Step 4, last: two confirmed tracks whose poses each look more like the other track (by more
// than swap_margin in all), and lie within its position gate, take each other's pose. Why: two
// people walking side by side or crossing are one box apart, and position, OKS, the TFF and the
// flow can all hand each track the other's pose for a frame; the tracks then go on with the
// wrong people. On vtest.avi (oks, `jointflow-track`) a man in a red and navy jacket and a
// blonde woman in a black coat walking side by side swapped ids at frame 148: his track's look
// against her pose 0.97, hers against his 0.97, each against its own 0.83 and 0.87 (gain 0.24).
// The swap is judged on the sum of both pairs, not pose by pose: a person half hidden behind the
// other shows the front one's coat, which raises both pairings of that pose alike.
void PoseAssociator::Impl::undoSwaps(const Poses& poses, const std::vector<Descriptor>& appearance,
                                     FrameMatches& m, const std::vector<bool>* involving) {
  if (settings.swap_margin <= 0.f) return;
  const std::vector<int> pose_of = m.poseOfTrack();
  struct Swap {
    float gain;
    int a, b;
  };
  std::vector<Swap> swaps;
  for (size_t a = 0; a < tracks.size(); ++a)
    for (size_t b = a + 1; b < tracks.size(); ++b) {
      if (involving && !(*involving)[a] && !(*involving)[b]) continue;
      if (!comparable(tracks[a], pose_of[a], appearance) ||
          !comparable(tracks[b], pose_of[b], appearance))
        continue;
      const Track &ta = tracks[a], &tb = tracks[b];
      const Pose &pa = poses[pose_of[a]], &pb = poses[pose_of[b]];
      if (!inGate(ta, pb) || !inGate(tb, pa)) continue;
      const float gain = swapGain(ta, appearance[pose_of[a]], tb, appearance[pose_of[b]]);
      if (gain > settings.swap_margin)
        swaps.push_back({gain, static_cast<int>(a), static_cast<int>(b)});
    }
  // The surest first; a track takes part in one swap at most.
  std::sort(swaps.begin(), swaps.end(),
            [](const Swap& x, const Swap& y) { return x.gain > y.gain; });
  std::vector<bool> swapped(tracks.size(), false);
  for (const Swap& s : swaps) {
    if (swapped[s.a] || swapped[s.b]) continue;
    swapped[s.a] = swapped[s.b] = true;
    std::swap(m.track_of[pose_of[s.a]], m.track_of[pose_of[s.b]]);
    // Each motion model starts again at its new pose: whose path it followed is not known (the
    // position may have handed the poses over frames ago or in this one). Kept, a model jumps to
    // the other person's place; swapped with the poses, the same is wrong the other way round.
    // vtest.avi: a man in a black coat whose swap was undone, kept with his model, was hidden for
    // a frame and his track ran on that jump to a man entering at the border (identity bench,
    // oks: 20 ids against 19 with the restart).
    for (const int t : {s.a, s.b}) restartAt(tracks[t], poses[pose_of[t == s.a ? s.b : s.a]]);
  }
}

// How much more alike two tracks and two poses are paired the other way round: the appearance
// similarities of a with pose_b and b with pose_a, less those of a with pose_a and b with pose_b;
// 0 unless all four are positive (a part seen in both), or a pose with no colour seen would count
// as unlike anyone.
float PoseAssociator::Impl::swapGain(const Track& a, const Descriptor& pose_a, const Track& b,
                                     const Descriptor& pose_b) const {
  const float own_a = appearanceSimilarity(a.appearance, pose_a),
              own_b = appearanceSimilarity(b.appearance, pose_b),
              cross_a = appearanceSimilarity(a.appearance, pose_b),
              cross_b = appearanceSimilarity(b.appearance, pose_a);
  if (std::min({own_a, own_b, cross_a, cross_b}) <= 0.f) return 0.f;
  return cross_a + cross_b - own_a - own_b;
}

// A track that takes a pose another track followed starts its motion model again there.
void PoseAssociator::Impl::restartAt(Track& t, const Pose& pose) const {
  t.motion = MotionModel(pose);
  t.filters.clear();
}

}  // namespace jointflow
