// PoseAssociator: the online track book (see pose_associator.hpp for the steps of one frame).
#include "jointflow/pose_associator.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <string>

#include <opencv2/video/tracking.hpp>

#include "camera_motion.hpp"
#include "jointflow/error.hpp"
#include "jointflow/matching.hpp"
#include "jointflow/similarity.hpp"
#include "one_euro_filter.hpp"

namespace jointflow {
namespace {

struct Track {
  std::int64_t id = 0;          ///< internal, unique
  std::int64_t output_id = -1;  ///< assigned when first reported
  Pose last;                    ///< the raw detection of the last matched frame
  Pose predicted;               ///< last, carried by camera and own motion while coasting
  cv::Point2f velocity{0, 0};   ///< own motion of the centre, px per frame, camera removed
  int start_frame = 0;
  int last_frame = 0;
  int length = 0;                      ///< frames matched
  int missed = 0;                      ///< consecutive frames unmatched
  std::vector<OneEuroFilter> filters;  ///< x, y per joint (smoothing only)
};

JointThresholds thresholdsOf(const TrackerSettings& s) {
  JointThresholds t;
  t.fill(s.joint_threshold);
  if (!s.joint_thresholds.empty())
    std::copy(s.joint_thresholds.begin(), s.joint_thresholds.end(), t.begin());
  return t;
}

SimilarityOptions similarityOptionsOf(const TrackerSettings& s) {
  SimilarityOptions o;
  o.thresholds = thresholdsOf(s);
  o.tau_delta = s.tau_delta;
  o.line_samples = s.line_samples;
  o.sigma_flow = s.sigma_flow;
  return o;
}

void checkPoses(const Poses& poses) {
  for (size_t i = 0; i < poses.size(); ++i)
    for (int j = 0; j < kNumJoints; ++j) {
      const Keypoint& k = poses[i].keypoints[j];
      if (!std::isfinite(k.x) || !std::isfinite(k.y) || !std::isfinite(k.score))
        throw Error("association: pose " + std::to_string(i) + ", joint " +
                    std::string(kJointNames[j]) + " has a non-finite coordinate or score");
    }
}

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

}  // namespace

struct PoseAssociator::Impl {
  TrackerSettings settings;
  JointThresholds thresholds{};
  std::unique_ptr<Similarity> similarity;
  std::unique_ptr<Similarity> geometric;  ///< OKS: coasting tracks and missing TFF/flow
  cv::Ptr<cv::DISOpticalFlow> optical_flow;
  std::vector<Track> tracks;
  cv::Mat previous_grey;
  cv::Matx23f camera{1, 0, 0, 0, 1, 0};
  std::int64_t next_id = 1;
  std::int64_t next_output_id = 1;
  int frame = 0;

  std::vector<int> filterDetections(const Poses& poses) const;
  Potentials primaryPotentials(const std::vector<int>& rows, const Poses& current,
                               const AssociationFrame& in, const cv::Mat& flow) const;
  Pose smooth(Track& t, const Pose& pose, int gap) const;
};

// Step 1: minimum size, duplicates, at most max_persons; returns indices of the kept poses.
std::vector<int> PoseAssociator::Impl::filterDetections(const Poses& poses) const {
  std::vector<int> order(poses.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return poses[a].score > poses[b].score; });
  std::vector<int> kept;
  for (int i : order) {
    const Pose& p = poses[i];
    Pose detected = p;
    for (int j = 0; j < kNumJoints; ++j)
      if (!isDetected(p.keypoints[j], thresholds[j])) detected.keypoints[j].score = 0.f;
    if (detected.countVisible(1e-12f) == 0) continue;  // nothing to associate
    const Box box = detected.keypointBox(0.f);
    if (std::max(box.w, box.h) < settings.min_person_size) continue;
    bool duplicate = false;
    if (settings.duplicate_oks > 0.f)
      for (int k : kept) duplicate |= oks(poses[k], p, thresholds) >= settings.duplicate_oks;
    if (duplicate) continue;
    kept.push_back(i);
    if (static_cast<int>(kept.size()) == settings.max_persons) break;
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

// Psi between the tracks seen in the previous frame (rows) and the current poses.
Potentials PoseAssociator::Impl::primaryPotentials(const std::vector<int>& rows,
                                                   const Poses& current, const AssociationFrame& in,
                                                   const cv::Mat& flow) const {
  Poses previous;
  for (int r : rows) previous.push_back(tracks[r].last);
  const bool lacks =
      (similarity->needsTff() && in.tff.empty()) || (similarity->needsFlow() && flow.empty());
  // Without a TFF or flow between the two frames (the grid changed, a frame came without its
  // map) the geometric similarity stands in for this one frame.
  if (lacks) return geometric->compute(previous, current, {});
  SimilarityInput input{in.tff, in.grid_to_frame, flow};
  return similarity->compute(previous, current, input);
}

Pose PoseAssociator::Impl::smooth(Track& t, const Pose& pose, int gap) const {
  if (!settings.smoothing) return pose;
  if (t.filters.empty())
    t.filters.assign(2 * kNumJoints, OneEuroFilter(settings.euro_min_cutoff, settings.euro_beta,
                                                   settings.euro_d_cutoff));
  const float dt = static_cast<float>(gap) / settings.frame_rate;
  Pose out = pose;
  for (int j = 0; j < kNumJoints; ++j) {
    Keypoint& k = out.keypoints[j];
    if (k.score <= 0.f) continue;
    k.x = t.filters[2 * j].filter(k.x, dt);
    k.y = t.filters[2 * j + 1].filter(k.y, dt);
  }
  return out;
}

PoseAssociator::PoseAssociator(const TrackerSettings& settings) : impl_(std::make_unique<Impl>()) {
  validateAssociationSettings(settings);
  impl_->settings = settings;
  impl_->thresholds = thresholdsOf(settings);
  impl_->similarity = createSimilarity(settings.similarity, similarityOptionsOf(settings));
  impl_->geometric = createSimilarity(SimilarityType::kOks, similarityOptionsOf(settings));
}

PoseAssociator::~PoseAssociator() = default;
PoseAssociator::PoseAssociator(PoseAssociator&&) noexcept = default;
PoseAssociator& PoseAssociator::operator=(PoseAssociator&&) noexcept = default;

std::vector<TrackedPose> PoseAssociator::update(const SpatialResult& result, const cv::Mat& tff,
                                                const cv::Mat& grey) {
  return update(AssociationFrame{result.poses, tff, result.grid_to_frame, grey});
}

std::vector<TrackedPose> PoseAssociator::update(const AssociationFrame& in) {
  Impl& s = *impl_;
  const TrackerSettings& cfg = s.settings;
  checkPoses(in.poses);
  if (!in.grey.empty() && in.grey.type() != CV_8UC1)
    throw Error("association: the grey frame must be 8-bit, 1 channel");
  if (s.similarity->needsFlow() && in.grey.empty())
    throw Error("similarity 'flow' needs the grey frame (AssociationFrame::grey)");
  ++s.frame;

  // Dense optical flow previous -> current, only for the "flow" similarity.
  cv::Mat flow;
  if (s.similarity->needsFlow() && !s.previous_grey.empty() &&
      s.previous_grey.size() == in.grey.size()) {
    if (!s.optical_flow)
      s.optical_flow = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_MEDIUM);
    s.optical_flow->calc(s.previous_grey, in.grey, flow);
  }

  const std::vector<int> dets = s.filterDetections(in.poses);
  const Poses& poses = in.poses;
  std::vector<int> det_track(poses.size(), -1);  // input pose -> track index
  std::vector<bool> track_matched(s.tracks.size(), false);

  // Steps 2-3: tracks seen in the previous frame, high-scoring poses first, then the low ones.
  std::vector<int> active;
  for (size_t t = 0; t < s.tracks.size(); ++t)
    if (s.tracks[t].missed == 0) active.push_back(static_cast<int>(t));
  std::vector<int> high, low;
  for (int d : dets) (poses[d].score >= cfg.track_score ? high : low).push_back(d);
  if (!active.empty() && !dets.empty()) {
    Poses current;
    for (int d : dets) current.push_back(poses[d]);
    const Potentials all = s.primaryPotentials(active, current, in, flow);
    auto column = [&](int det) {
      return static_cast<int>(std::find(dets.begin(), dets.end(), det) - dets.begin());
    };
    for (const std::vector<int>* pass : {&high, &low}) {
      std::vector<int> rows, cols;
      for (size_t r = 0; r < active.size(); ++r)
        if (!track_matched[active[r]]) rows.push_back(static_cast<int>(r));
      for (int d : *pass) cols.push_back(column(d));
      if (rows.empty() || cols.empty()) continue;
      const Potentials p = select(all, rows, cols);
      for (const Match& m : matchPoses(cfg.matcher, p.psi, p.per_joint, cfg.min_potential)) {
        const int t = active[rows[m.row]];
        const int d = dets[cols[m.col]];
        track_matched[t] = true;
        det_track[d] = t;
      }
    }
  }

  // Step 4: camera motion, own motion, coasting tracks.
  std::vector<std::pair<Pose, Pose>> matched_pairs;
  for (size_t d = 0; d < poses.size(); ++d)
    if (det_track[d] >= 0) matched_pairs.emplace_back(s.tracks[det_track[d]].last, poses[d]);
  const bool any_unmatched =
      std::find(track_matched.begin(), track_matched.end(), false) != track_matched.end();
  s.camera = cv::Matx23f(1, 0, 0, 0, 1, 0);
  if (cfg.camera_compensation) {
    if (!in.grey.empty() && !s.previous_grey.empty() && any_unmatched)
      s.camera = cameraMotionFromImages(s.previous_grey, in.grey);
    else
      s.camera = cameraMotionFromPoses(matched_pairs, cfg.joint_threshold);
  }
  // Coasting tracks, and with geometric_fallback the tracks of the previous frame that the
  // similarity left unmatched, are predicted into this frame and matched on OKS.
  std::vector<int> coasting;
  for (size_t t = 0; t < s.tracks.size(); ++t) {
    Track& tr = s.tracks[t];
    if (tr.missed > 0) {
      tr.predicted = movePose(tr.predicted, s.camera, tr.velocity);
      coasting.push_back(static_cast<int>(t));
    } else if (cfg.geometric_fallback && !track_matched[t]) {
      tr.predicted = movePose(tr.last, s.camera, tr.velocity);
      coasting.push_back(static_cast<int>(t));
    }
  }
  if (!coasting.empty()) {
    std::vector<int> free_high;
    for (int d : high)
      if (det_track[d] < 0) free_high.push_back(d);
    if (!free_high.empty()) {
      Poses previous, current;
      for (int t : coasting) previous.push_back(s.tracks[t].predicted);
      for (int d : free_high) current.push_back(poses[d]);
      const Potentials p = s.geometric->compute(previous, current, {});
      for (const Match& m : matchPoses(cfg.matcher, p.psi, p.per_joint, cfg.coast_min_oks)) {
        track_matched[coasting[m.row]] = true;
        det_track[free_high[m.col]] = coasting[m.row];
      }
    }
  }

  // Step 5: update matched tracks, start new ones, age and end the others.
  std::vector<int> det_gap(poses.size(), 1);  // frames since the track's previous detection
  for (size_t d = 0; d < poses.size(); ++d) {
    if (det_track[d] < 0) continue;
    Track& tr = s.tracks[det_track[d]];
    const int gap = s.frame - tr.last_frame;
    // Own motion per frame, camera removed. A coasting track's prediction already holds the
    // camera and its velocity over the gap, so only the prediction error is new.
    const cv::Matx23f identity(1, 0, 0, 0, 1, 0);
    const cv::Point2f own = tr.missed ? tr.velocity + meanMotion(tr.predicted, poses[d], identity) /
                                                          static_cast<float>(gap)
                                      : meanMotion(tr.last, poses[d], s.camera);
    tr.velocity = tr.length > 1 ? 0.5f * (tr.velocity + own) : own;
    tr.last = tr.predicted = poses[d];
    tr.last_frame = s.frame;
    tr.missed = 0;
    ++tr.length;
    det_gap[d] = gap;
  }
  const size_t old_count = s.tracks.size();
  for (int d : high) {
    if (det_track[d] >= 0) continue;
    Track tr;
    tr.id = s.next_id++;
    tr.last = tr.predicted = poses[d];
    tr.start_frame = tr.last_frame = s.frame;
    tr.length = 1;
    det_track[d] = static_cast<int>(s.tracks.size());
    s.tracks.push_back(std::move(tr));
  }
  for (size_t t = 0; t < old_count; ++t) {
    Track& tr = s.tracks[t];
    if (track_matched[t]) continue;
    if (tr.missed == 0) tr.predicted = movePose(tr.last, s.camera, tr.velocity);
    ++tr.missed;
  }

  std::vector<TrackedPose> out;
  for (size_t d = 0; d < poses.size(); ++d) {
    if (det_track[d] < 0) continue;
    Track& tr = s.tracks[det_track[d]];
    TrackedPose tp;
    tp.pose = s.smooth(tr, poses[d], det_gap[d]);
    tp.tentative = tr.length < cfg.min_track_length;
    tp.age = s.frame - tr.start_frame;
    tp.detection = static_cast<int>(d);
    if (tp.tentative && !cfg.output_tentative) continue;
    if (tr.output_id < 0) tr.output_id = s.next_output_id++;
    tp.track_id = tr.output_id;
    out.push_back(tp);
  }

  // Tracks unmatched for longer than the coasting window end; their ids are never reused.
  s.tracks.erase(std::remove_if(s.tracks.begin(), s.tracks.end(),
                                [&](const Track& t) { return t.missed > cfg.coast_frames; }),
                 s.tracks.end());
  if (!in.grey.empty()) s.previous_grey = in.grey.clone();
  return out;
}

void PoseAssociator::reset() {
  impl_->tracks.clear();
  impl_->previous_grey.release();
  impl_->camera = cv::Matx23f(1, 0, 0, 0, 1, 0);
}

int PoseAssociator::liveTracks() const {
  return static_cast<int>(impl_->tracks.size());
}
cv::Matx23f PoseAssociator::cameraMotion() const {
  return impl_->camera;
}

}  // namespace jointflow
