// poseval's evaluation flow: load and clean the sequences, match frame by frame, then the AP and
// MOT figures per joint and their means (definitions in jointflow/evaluation.hpp).
#include "jointflow/evaluation.hpp"

#include <cmath>
#include <set>

#include <opencv2/imgproc.hpp>

#include "average_precision.hpp"
#include "frame_matching.hpp"
#include "jointflow/error.hpp"

namespace jointflow {

using posetrack::Frame;
using posetrack::kNumPoseTrackJoints;
using posetrack::Person;
using posetrack::Sequence;

namespace {

/// Strictly inside (as shapely's Polygon.contains, which poseval uses).
bool inside(const posetrack::Polygon& poly, double x, double y) {
  if (poly.x.size() < 3) return false;
  std::vector<cv::Point2f> contour;
  for (std::size_t i = 0; i < poly.x.size(); ++i) {
    contour.emplace_back(static_cast<float>(poly.x[i]), static_cast<float>(poly.y[i]));
  }
  return cv::pointPolygonTest(contour, cv::Point2f(static_cast<float>(x), static_cast<float>(y)),
                              false) > 0;
}

/// poseval's removeIgnoredPoints: joints inside an ignore region go; people left without any
/// joint go too.
void removeIgnored(std::vector<Person>& people, const std::vector<posetrack::Polygon>& regions) {
  std::vector<Person> kept;
  for (Person& p : people) {
    bool any = false;
    for (auto& joint : p.joints) {
      if (!joint) continue;
      for (const auto& poly : regions) {
        if (inside(poly, joint->x, joint->y)) {
          joint.reset();
          break;
        }
      }
      any = any || joint.has_value();
    }
    if (any) kept.push_back(std::move(p));
  }
  people = std::move(kept);
}

void removeWithoutPoints(std::vector<Person>& people) {
  std::vector<Person> kept;
  for (Person& p : people) {
    if (p.has_annopoints) kept.push_back(std::move(p));
  }
  people = std::move(kept);
}

/// poseval refuses predictions with repeated track ids in a frame; motmetrics needs unique ids on
/// both sides.
void checkIds(const Sequence& seq, const char* side) {
  for (std::size_t f = 0; f < seq.frames.size(); ++f) {
    std::set<std::int64_t> seen;
    for (const Person& p : seq.frames[f].people) {
      const std::string where =
          seq.source + ": frame " + std::to_string(f) + " (" + seq.frames[f].file_name + "): ";
      if (!p.track_id) throw Error(where + "a " + side + " person has no track_id");
      if (!seen.insert(*p.track_id).second) {
        throw Error(where + "track_id " + std::to_string(*p.track_id) +
                    " appears twice among the " + side + " people");
      }
    }
  }
}

struct FramePair {
  Frame gt, pred;
};

/// poseval's cleanupData + removeIgnoredPoints for one sequence pair.
std::vector<FramePair> prepare(const Sequence& gt, const Sequence& pred) {
  if (gt.frames.size() != pred.frames.size()) {
    throw Error(pred.source + ": " + std::to_string(pred.frames.size()) +
                " prediction frames, but the ground truth " + gt.source + " has " +
                std::to_string(gt.frames.size()) + " (predictions must list the same frames)");
  }
  checkIds(gt, "ground-truth");
  checkIds(pred, "predicted");
  std::vector<FramePair> out;
  for (std::size_t f = 0; f < gt.frames.size(); ++f) {
    if (gt.frames[f].people.empty()) continue;  // unlabelled frame: dropped with its predictions
    FramePair pair{gt.frames[f], pred.frames[f]};
    removeWithoutPoints(pair.gt.people);
    removeWithoutPoints(pair.pred.people);
    if (!pair.gt.ignore_regions.empty()) {
      removeIgnored(pair.gt.people, pair.gt.ignore_regions);
      removeIgnored(pair.pred.people, pair.gt.ignore_regions);
    }
    out.push_back(std::move(pair));
  }
  return out;
}

const Sequence& findPrediction(const std::vector<Sequence>& predictions, const Sequence& gt) {
  for (const Sequence& p : predictions) {
    if (p.name == gt.name) return p;
  }
  throw Error("no prediction for the ground-truth sequence \"" + gt.name + "\" (" + gt.source +
              "): expected a prediction file named " + gt.name + ".json");
}

double nanMean(const std::vector<double>& values) {
  double sum = 0.0;
  int n = 0;
  for (double v : values) {
    if (std::isnan(v)) continue;
    sum += v;
    ++n;
  }
  return n > 0 ? sum / n : std::nan("");
}

/// motmetrics' quiet_divide in percent: NaN when the denominator is 0.
double percent(double numerator, double denominator) {
  return denominator > 0 ? 100.0 * numerator / denominator : std::nan("");
}

/// IDF1, IDP and IDR from (summed) counts, as motmetrics' idf1, idp, idr.
void finishIdentity(JointScores& s) {
  const MotAccumulator::Counts& c = s.counts;
  const auto tp = static_cast<double>(c.id_true_positives);
  s.idf1 = percent(2.0 * tp, 2.0 * tp + c.id_false_positives + c.id_false_negatives);
  s.id_precision = percent(tp, tp + c.id_false_positives);
  s.id_recall = percent(tp, tp + c.id_false_negatives);
}

/// The per-joint figures from summed counts, as poseval's computeMetrics.
void finishJoint(JointScores& s, bool motp_all_events) {
  const MotAccumulator::Counts& c = s.counts;
  const double objects = c.objects > 0 ? static_cast<double>(c.objects) : std::nan("");
  const double detections = static_cast<double>(c.detections());
  const double fp = static_cast<double>(c.false_positives);
  s.mota = 100.0 * (1.0 - static_cast<double>(c.misses + c.switches + c.false_positives) / objects);
  const double d = motp_all_events ? c.events_distance : c.matched_distance;
  s.motp = c.detections() == 0 ? 0.0 : 100.0 * (1.0 - d / detections);
  s.precision = 100.0 * detections / (fp + detections > 0 ? fp + detections : std::nan(""));
  s.recall = 100.0 * detections / objects;
  finishIdentity(s);
}

}  // namespace

PoseTrackEvalResult evaluatePoseTrack(const std::vector<Sequence>& ground_truth,
                                      const std::vector<Sequence>& predictions,
                                      const PoseTrackEvalOptions& options) {
  PoseTrackEvalResult result;
  std::array<std::vector<eval::ScoredJoint>, kNumPoseTrackJoints> scored;
  std::array<int, kNumPoseTrackJoints> num_gt{};

  for (const Sequence& gt : ground_truth) {
    const Sequence& pred = findPrediction(predictions, gt);
    const std::vector<FramePair> frames = prepare(gt, pred);
    if (frames.empty()) continue;  // no labelled frame: poseval never sees the sequence
    if (options.drop_last_frame && frames.size() < 2) {
      throw Error(gt.source +
                  ": only one labelled frame; poseval's tracking part ignores the "
                  "last frame and cannot score this sequence (evaluate with the "
                  "last frame kept instead)");
    }
    result.sequences.push_back(gt.name);
    const std::size_t tracked = options.drop_last_frame ? frames.size() - 1 : frames.size();
    std::array<MotAccumulator, kNumPoseTrackJoints> acc;
    std::array<std::vector<HotaFrame>, kNumPoseTrackJoints> hota_frames;
    for (std::size_t f = 0; f < frames.size(); ++f) {
      const std::string where = gt.source + ": frame " + frames[f].gt.file_name;
      const eval::FrameMatch m =
          eval::matchFrame(frames[f].gt, frames[f].pred, options.pckh_threshold,
                           options.empty_frame_one_miss, where);
      for (int j = 0; j < kNumPoseTrackJoints; ++j) {
        scored[j].insert(scored[j].end(), m.scored[j].begin(), m.scored[j].end());
        num_gt[j] += m.num_gt[j];
        if (f < tracked) acc[j].update(m.mot[j].gt_ids, m.mot[j].pred_ids, m.mot[j].distances);
        hota_frames[j].push_back(m.hota[j]);
      }
    }
    for (int j = 0; j < kNumPoseTrackJoints; ++j) {
      result.joints[j].counts += acc[j].counts();
      result.joints[j].hota += hotaOfSequence(hota_frames[j], HotaMatching::kSimilarity);
    }
  }

  std::vector<double> ap, mota, motp, precision, recall;
  for (int j = 0; j < kNumPoseTrackJoints; ++j) {
    JointScores& s = result.joints[j];
    s.ap = 100.0 * eval::averagePrecision(scored[j], num_gt[j]);
    finishJoint(s, options.motp_all_events);
    ap.push_back(s.ap);
    mota.push_back(s.mota);
    motp.push_back(s.motp);
    precision.push_back(s.precision);
    recall.push_back(s.recall);
    result.total.counts += s.counts;
    result.total.hota += s.hota;
  }
  result.total.ap = nanMean(ap);
  result.total.mota = nanMean(mota);
  result.total.motp = nanMean(motp);
  result.total.precision = nanMean(precision);
  result.total.recall = nanMean(recall);
  finishIdentity(result.total);
  return result;
}

PoseTrackEvalResult evaluatePoseTrackFiles(const std::string& ground_truth_path,
                                           const std::string& predictions_path,
                                           const PoseTrackEvalOptions& options) {
  std::vector<Sequence> gt, pred;
  for (const std::string& f : posetrack::listSequenceFiles(ground_truth_path)) {
    gt.push_back(posetrack::readSequence(f));
  }
  for (const std::string& f : posetrack::listSequenceFiles(predictions_path)) {
    pred.push_back(posetrack::readSequence(f));
  }
  // A single prediction file scores a single ground-truth file whatever its name.
  if (gt.size() == 1 && pred.size() == 1) pred.front().name = gt.front().name;
  return evaluatePoseTrack(gt, pred, options);
}

}  // namespace jointflow
