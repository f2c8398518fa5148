// Step 5 of PoseAssociator (pose_associator.hpp's list): lost tracks, and active ones step 4 left
// unmatched, against the poses still free (re-identification); last, the trade between a track
// left unmatched and a matched one, and the pose a track left unmatched takes back.
#include <algorithm>

#include "jointflow/matching.hpp"
#include "track_book.hpp"

namespace jointflow {
using track_book::leftView;
using track_book::pathDistance;

namespace {

// Re-identification accepts a pose up to this factor taller or shorter than the track: the
// keypoint box of a person partly seen (joints below their threshold, half out of view, coming
// out from behind something) is shorter than the person. At 1.5 a walker on vtest.avi who came
// back after 1.2 s with appearance 0.97, 84 px from the prediction, was refused at 0.667.
constexpr float kReidHeightRatio = 2.f;
// A pose that looks very like the track (appearance >= kReidStrongSimilarity) may lie half a
// height further from the prediction than the gate allows: a shaken camera's motion estimate errs
// by tens of pixels on some frames, and on the identity benchmark's shake a person who came back
// after one missed frame with appearance 0.94, 122 px from the prediction (gate 117 px), got a
// new id. Identity bench, oks: shake 18 -> 4 joint id switches, occluder 119 -> 116, vtest.avi
// unchanged (docs/identity.md).
constexpr float kReidStrongSimilarity = 0.9f;
constexpr float kReidStrongGateHeights = 0.5f;
// Added to a step-5 score where the position backs the pose (scores are at most 1).
constexpr float kPlacedRank = 1.f;
// After a gap (gap_time), taken from a step-5 likeness per gate of distance from the track's
// path: of two people who look alike to the re-identification, the one nearer to where the
// person was or was heading. People who stayed in view and kept their ids over 3-4 s gaps of
// vtest.avi at 10 and 2 frames/s (make bench-outages' scenes, plus a gap at 57-61 s at 2
// frames/s; no held-out set): 51 of 67 with none, 56 with 0.1, 54 with 0.2.
constexpr float kGapDistancePenalty = 0.1f;

// A free pose whose box lies almost wholly inside the box of a matched pose is a part of that
// person (MoveNet finds a second, partial person in the same body) or someone hidden behind them:
// its appearance is pooled over the person in front, so it cannot say whose it is. Identity bench,
// shake (oks): a free pose half as tall as a matched one, wholly inside its box, looked a little
// more like the track of someone lost beside it (gain 0.14), and the trade cost 28 joint id
// switches; the trades that were right covered at most half of the free pose (dropped 0.52,
// vtest.avi 0.41).
bool liesWithin(const Pose& inner, const Pose& outer) {
  constexpr float kWithin = 0.8f;
  return intersectionArea(inner.box, outer.box) > kWithin * inner.box.area();
}

}  // namespace

// OKS between a track's predicted pose and a pose, each joint's tolerance widened by how well the
// motion model knows where the person is now: after a gap in time (dropped frames, a slow frame
// rate, a track lost for a while) a person may have moved further than OKS alone allows.
float PoseAssociator::Impl::predictionOks(const Track& t, const Pose& pose) const {
  return oks(t.motion.pose(), pose, thresholds, t.motion.positionSigma());
}

// Step 5: lost tracks, and active tracks that step 4 left unmatched, against the poses still
// free. A pose is taken on OKS with the track's prediction (predictionOks >= coast_min_oks),
// or else on appearance (>= reid_min_similarity) when it lies within the position gate of the
// track's motion model (3 standard deviations of the predicted centre, at most one height per
// second hidden, plus half the person's height; one height for a pose that looks very like the
// track, ranked below the poses the position backs) of the path from where the person was last seen
// to the prediction (distanceToPath), and its height is within kReidHeightRatio of the track's. A
// confirmed track may also take a pose that a tentative track took in step 4: a person partly
// hidden for a frame or two (crossing behind someone) comes back in a view too poor for
// re-identification, starts a tentative track, and on the next frame, seen better, would stay
// with it (vtest.avi: a walker crossing behind another at frames 19-22 came back as a new track
// with appearance 0.80, 0.90 one frame later, and lost their id of 20 frames). The tentative
// track, unmatched, ends after tentative_lost_time.
// Active tracks take part because OKS alone loses small people for a frame: on vtest.avi (people
// 40-100 px tall) a walker whose pose changed kept OKS 0.39 at 3 px from its prediction with
// appearance 0.97, and got a new id (docs/identity.md: 14 -> 11 ids in the first 300 frames with
// this and the ratio below). Tentative ones too: a new track has the least motion history, so its
// prediction is the least sure, and frames apart (a stride, a slow machine) OKS lost them; on the
// Bonn sequence at strides 3 and 4, oks 28 and 30 joint id switches -> 2 and 2 (as tff and flow),
// and vtest.avi's walker entering at frame 117 kept their id (docs/tracking.md, step 5).
void PoseAssociator::Impl::matchLost(const Poses& poses, cv::Size frame,
                                     const std::vector<int>& high,
                                     const std::vector<Descriptor>& appearance, bool after_gap,
                                     FrameMatches& m) const {
  const bool reidentify = settings.reid != AppearanceModel::kOff;
  std::vector<int> rows, cols;
  for (size_t t = 0; t < tracks.size(); ++t) {
    if (tracks[t].state == TrackState::kLost || (reidentify && !m.matched[t]))
      rows.push_back(static_cast<int>(t));
  }
  // The poses still free, and those a tentative track took in step 4: a confirmed track may take
  // those back (tentativeTaken).
  auto tentativeTaken = [&](int d) {
    return m.track_of[d] >= 0 && !confirmed(tracks[m.track_of[d]]);
  };
  for (int d : high)
    if (m.track_of[d] < 0 || tentativeTaken(d)) cols.push_back(d);
  if (rows.empty() || cols.empty()) return;
  cv::Mat psi =
      cv::Mat::zeros(static_cast<int>(rows.size()), static_cast<int>(cols.size()), CV_32F);
  for (size_t r = 0; r < rows.size(); ++r) {
    const Track& t = tracks[rows[r]];
    const float track_gate = gate(t);
    // After a gap the prediction has run on for seconds at the last velocity and may lie outside
    // the view for a person who stopped or turned back while unseen (vtest.avi, 4 s gaps: two
    // walkers still in view were taken for gone and got new ids): a track with looks is looked
    // for on its likeness within the gate of its path, and its OKS, whose tolerance has grown so
    // far that it passes nearly anyone in reach, does not count (below).
    const bool by_looks = looksDecide(t, after_gap);
    const bool gone = !by_looks && leftView(t, frame);
    for (size_t c = 0; c < cols.size(); ++c) {
      if (!confirmed(t) && tentativeTaken(cols[c])) continue;
      const Pose& p = poses[cols[c]];
      // A lost track inside the view is compared along its path (poseOnPath): its person may have
      // stopped or turned back while hidden, away from the constant-velocity prediction. Two
      // walkers who meet, stand together for a second with one hidden, and go back the way they
      // came (bench/crossings.hpp, 900 cases with the Bonn train people's articulation): 77 % kept
      // their ids, 96 % with the path; crossings 97 -> 99 %; the Bonn sequence and its strides
      // unchanged. Not for one who walked out: whoever comes in where they left is taken back on
      // position only with their likeness (below).
      const float geometric_score =
          t.state == TrackState::kLost && !gone
              ? oks(track_book::poseOnPath(t, p), p, thresholds, t.motion.positionSigma())
              : predictionOks(t, p);
      // An active track had its OKS chance in step 4 (the geometric fallback, where enabled).
      const bool lost = t.state == TrackState::kLost;
      float score =
          lost && !by_looks && geometric_score >= settings.coast_min_oks ? geometric_score : 0.f;
      // One who walked out of the view is not looked for inside it on appearance: whoever comes
      // in where they went out may be someone else, and position no longer tells (vtest.avi: a
      // man in a black coat entering 1.1 s after a man in a leather jacket walked out there took
      // his id, appearance 0.94). A person coming back is recognised by re-entry (reentry_time)
      // once the track has ended, with its stricter likeness. Position alone does not tell either:
      // the prediction's tolerance grows with the time lost, so after a few seconds anyone
      // entering there passes OKS. Taken back on position, they must also look like the track:
      // on vtest.avi a woman in a red top entering 2.7 s after a bald man walked out took his id
      // on OKS 0.82 (appearance 0.67), while a man coming back 2 s after he walked out there
      // (appearance 0.90) and the woman back 3 s after she left (0.89) were their own tracks.
      if (gone && reidentify && score > 0.f &&
          appearanceSimilarity(t.appearance, appearance[cols[c]]) < settings.reid_min_similarity)
        score = 0.f;
      bool placed = score > 0.f;  // where the track's prediction says the person is
      if (reidentify && !gone) {
        const float h = std::max(p.keypointBox(1e-12f).h, 1.f);
        const float ratio = h / t.motion.height();
        const float similar = appearanceSimilarity(t.appearance, appearance[cols[c]]);
        const float distance = pathDistance(t, p);
        const float allowed =
            track_gate +
            (similar >= kReidStrongSimilarity ? kReidStrongGateHeights * t.motion.height() : 0.f);
        if (distance <= allowed && ratio > 1.f / kReidHeightRatio && ratio < kReidHeightRatio &&
            similar >= settings.reid_min_similarity) {
          // After a gap the gate spans most of the view, so the likeness alone ranks the
          // poses in it, less a little for the distance from the path.
          const float behind =
              after_gap ? kGapDistancePenalty * distance / std::max(track_gate, 1.f) : 0.f;
          score = std::max(score, similar - behind);
          placed = placed || distance <= track_gate;
        }
      }
      // A pose that only the strong likeness's wider gate lets in ranks below every pose the
      // position backs, however alike: the widening is for a camera estimate that erred, not a
      // reason to prefer someone further away. vtest.avi: a bald man hidden 0.4 s behind another
      // walker came back 6 px from his path (OKS 0.79, appearance 0.93), and a man in a leather
      // jacket who had just come in 111 px from it (appearance 0.94) took his id.
      if (placed) score += kPlacedRank;
      psi.at<float>(static_cast<int>(r), static_cast<int>(c)) = score;
    }
  }
  // Scores are in (0, 2]; 0 = not allowed. Greedy: the surest pair first.
  for (const Match& mt : matchGreedy(psi, psi, 1e-6f)) {
    const int d = cols[mt.col];
    if (m.track_of[d] >= 0) m.matched[m.track_of[d]] = false;  // the tentative track gives it up
    m.matched[rows[mt.row]] = true;
    m.track_of[d] = rows[mt.row];
  }
}

// The last part of step 5: a confirmed track that took a pose in step 4 and a confirmed track
// left unmatched trade, when the first looks more like a pose still free and the second more like
// the first's pose (swapGain > swap_margin, each pose within the other track's gate): the first
// gets the free pose, the second its pose. Two people overlapping, one of them seen for a frame
// as one pose: the position gives it to the wrong track, whose own person, seen again, would
// start a new track. Bonn sequence with half the frames dropped (identity bench, oks): two
// people on the right crossing at a turn of the play, only one detected; the track of the one
// behind took the pose of the one in front, whose track was left lost, and the one behind came
// back as a new track (32 joint id switches, the new track hidden 5 frames by contested_time).
void PoseAssociator::Impl::giveBackToUnmatched(const Poses& poses, const std::vector<int>& high,
                                               const std::vector<Descriptor>& appearance,
                                               FrameMatches& m) {
  if (settings.swap_margin <= 0.f) return;
  const std::vector<int> pose_of = m.poseOfTrack();
  struct Trade {
    float gain;
    int taker, unmatched, free_pose;
  };
  std::vector<Trade> trades;
  for (int d : high) {
    if (m.track_of[d] >= 0 || appearance[d].empty()) continue;
    for (size_t a = 0; a < tracks.size(); ++a) {
      const Track& ta = tracks[a];
      if (!comparable(ta, pose_of[a], appearance) || !inGate(ta, poses[d]) ||
          liesWithin(poses[d], poses[pose_of[a]]))
        continue;
      for (size_t b = 0; b < tracks.size(); ++b) {
        const Track& tb = tracks[b];
        if (!mayClaim(tb, m.matched[b], poses[pose_of[a]])) continue;
        const float gain = swapGain(ta, appearance[pose_of[a]], tb, appearance[d]);
        if (gain > settings.swap_margin)
          trades.push_back({gain, static_cast<int>(a), static_cast<int>(b), d});
      }
    }
  }
  std::sort(trades.begin(), trades.end(),
            [](const Trade& x, const Trade& y) { return x.gain > y.gain; });
  std::vector<bool> traded(tracks.size(), false);
  for (const Trade& t : trades) {
    if (traded[t.taker] || traded[t.unmatched] || m.track_of[t.free_pose] >= 0) continue;
    traded[t.taker] = traded[t.unmatched] = true;
    const int taken = pose_of[t.taker];
    m.track_of[taken] = t.unmatched;
    m.matched[t.unmatched] = true;
    m.track_of[t.free_pose] = t.taker;
    restartAt(tracks[t.taker], poses[t.free_pose]);
    restartAt(tracks[t.unmatched], poses[taken]);
  }
}

// Step 5, after the trades: a confirmed track left unmatched takes back a pose that a confirmed
// track took but does not look like (appearance below reid_min_similarity), when the pose looks
// like it (at least reid_min_similarity, by more than swap_margin) and lies within its gate. The
// track that took it is left unmatched. Two people cross, one in front hides the other, and the
// one pose seen is near both tracks: a similarity that compares places (the TFF's tau_delta
// counts every joint that moved less than 12 px as the same joint's) may hand it to the hidden
// person's track, whose own person then comes back as a new track while the one in front, whose
// track was lost for the frames their poses merged, is left without theirs. vtest.avi frame 475
// (tff): a woman in a red top and a man in a leather jacket cross; the one pose seen, the man's,
// went to her track (appearance 0.77), his track, lost 2 frames, scored 0.94 against it; she came
// back from behind the sign as a new id. Nothing else takes a pose back here: giveBackToUnmatched
// needs a free pose for the taker, and there is none while one stands in front of the other.
void PoseAssociator::Impl::takeBackUnlike(const Poses& poses, cv::Size frame,
                                          const std::vector<Descriptor>& appearance,
                                          FrameMatches& m) {
  if (settings.swap_margin <= 0.f || settings.reid == AppearanceModel::kOff) return;
  const std::vector<int> pose_of = m.poseOfTrack();
  struct TakeBack {
    float gain;
    int holder, claimant, pose;
  };
  std::vector<TakeBack> candidates;
  for (size_t a = 0; a < tracks.size(); ++a) {
    const int d = pose_of[a];
    if (!comparable(tracks[a], d, appearance)) continue;
    const float held = appearanceSimilarity(tracks[a].appearance, appearance[d]);
    if (held >= settings.reid_min_similarity) continue;
    for (size_t b = 0; b < tracks.size(); ++b) {
      const Track& tb = tracks[b];
      if (!mayClaim(tb, m.matched[b], poses[d]) || leftView(tb, frame)) continue;
      const float claim = appearanceSimilarity(tb.appearance, appearance[d]);
      if (claim >= settings.reid_min_similarity && claim - held > settings.swap_margin)
        candidates.push_back({claim - held, static_cast<int>(a), static_cast<int>(b), d});
    }
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const TakeBack& x, const TakeBack& y) { return x.gain > y.gain; });
  for (const TakeBack& c : candidates) {
    if (m.track_of[c.pose] != c.holder || m.matched[c.claimant]) continue;
    m.track_of[c.pose] = c.claimant;
    m.matched[c.claimant] = true;
    m.matched[c.holder] = false;
  }
}

}  // namespace jointflow
