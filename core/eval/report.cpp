// Printing PoseTrack results: poseval's two tables, a per-joint table, and JSON.
#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "jointflow/evaluation.hpp"

namespace jointflow {

using namespace posetrack;

namespace {

/// poseval's body parts: (head top, neck, nose), shoulders, elbows, wrists, hips, knees, ankles.
const std::vector<std::vector<int>> kParts = {
    {kPtHeadTop, kPtNeck, kPtNose}, {kPtRightShoulder, kPtLeftShoulder},
    {kPtRightElbow, kPtLeftElbow},  {kPtRightWrist, kPtLeftWrist},
    {kPtRightHip, kPtLeftHip},      {kPtRightKnee, kPtLeftKnee},
    {kPtRightAnkle, kPtLeftAnkle}};
const char* const kPartNames[] = {"Head", "Shou", "Elb ", "Wri ", "Hip ", "Knee", "Ankl"};

/// Plain mean: a NaN joint makes its part NaN, as numpy's mean in poseval's table.
double partMean(const PoseTrackEvalResult& r, const std::vector<int>& joints,
                double JointScores::*field) {
  double sum = 0.0;
  for (int j : joints) sum += r.joints[j].*field;
  return sum / static_cast<double>(joints.size());
}

/// HOTA of a body part from its joints' pooled HOTA counts (as the total).
HotaScores partHota(const PoseTrackEvalResult& r, const std::vector<int>& joints) {
  HotaCounts pooled;
  for (int j : joints) pooled += r.joints[j].hota;
  return hotaScores(pooled);
}

/// IDF1 of a body part from its joints' summed identity counts (as the total).
double partIdf1(const PoseTrackEvalResult& r, const std::vector<int>& joints) {
  double tp = 0.0, fp = 0.0, fn = 0.0;
  for (int j : joints) {
    tp += static_cast<double>(r.joints[j].counts.id_true_positives);
    fp += static_cast<double>(r.joints[j].counts.id_false_positives);
    fn += static_cast<double>(r.joints[j].counts.id_false_negatives);
  }
  return 2 * tp + fp + fn > 0 ? 100.0 * 2 * tp / (2 * tp + fp + fn) : std::nan("");
}

std::string cell(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%5.1f", v);
  return buf;
}

nlohmann::json number(double v) {
  return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v);
}

nlohmann::json scoresJson(const JointScores& s) {
  const auto& c = s.counts;
  const HotaScores h = hotaScores(s.hota);
  return {{"mota", number(s.mota)},
          {"motp", number(s.motp)},
          {"precision", number(s.precision)},
          {"recall", number(s.recall)},
          {"map", number(s.ap)},
          {"num_gt", c.objects},
          {"matches", c.matches},
          {"id_switches", c.switches},
          {"misses", c.misses},
          {"false_positives", c.false_positives},
          {"idf1", number(s.idf1)},
          {"idp", number(s.id_precision)},
          {"idr", number(s.id_recall)},
          {"idtp", c.id_true_positives},
          {"idfp", c.id_false_positives},
          {"idfn", c.id_false_negatives},
          {"num_predictions", c.predictions()},
          {"hota", h.mean_hota},
          {"deta", h.deta},
          {"assa", h.assa},
          {"loca", h.loca}};
}

}  // namespace

std::string formatPoseTrackTables(const PoseTrackEvalResult& r) {
  std::ostringstream out;
  out << "Average Precision (AP) metric:\n&";
  for (const char* name : kPartNames) out << ' ' << name << " &";
  out << " Total\\\\\n&";
  for (const auto& part : kParts) out << cell(partMean(r, part, &JointScores::ap)) << " &";
  out << cell(r.total.ap) << " \\\\\n";

  out << "Multiple Object Tracking (MOT) metrics:\n&";
  for (int i = 0; i < 8; ++i) out << " MOTA &";
  out << " MOTP & Prec & Rec  \\\\\n&";
  for (const char* name : kPartNames) out << ' ' << name << " &";
  out << " Total& Total& Total& Total\\\\\n&";
  for (const auto& part : kParts) out << cell(partMean(r, part, &JointScores::mota)) << " &";
  out << cell(r.total.mota) << " &" << cell(r.total.motp) << " &" << cell(r.total.precision) << " &"
      << cell(r.total.recall) << " \\\\\n";

  out << "Identity (IDF1) metrics:\n&";
  for (int i = 0; i < 8; ++i) out << " IDF1 &";
  out << " IDP  & IDR  \\\\\n&";
  for (const char* name : kPartNames) out << ' ' << name << " &";
  out << " Total& Total& Total\\\\\n&";
  for (const auto& part : kParts) out << cell(partIdf1(r, part)) << " &";
  out << cell(r.total.idf1) << " &" << cell(r.total.id_precision) << " &" << cell(r.total.id_recall)
      << " \\\\\n";

  out << "HOTA (PoseTrack21's keypoint similarity):\n&";
  for (int i = 0; i < 8; ++i) out << " HOTA &";
  out << " DetA & AssA \\\\\n&";
  for (const char* name : kPartNames) out << ' ' << name << " &";
  out << " Total& Total& Total\\\\\n&";
  for (const auto& part : kParts) out << cell(partHota(r, part).mean_hota) << " &";
  const HotaScores total_hota = hotaScores(r.total.hota);
  out << cell(total_hota.mean_hota) << " &" << cell(total_hota.deta) << " &"
      << cell(total_hota.assa) << " \\\\\n";

  out << "\nPer joint:\n";
  char line[240];
  std::snprintf(line, sizeof line, "%-15s %6s %6s %6s %6s %6s %6s %6s %6s %6s %7s %6s %6s %6s\n",
                "joint", "AP", "MOTA", "MOTP", "Prec", "Rec", "IDF1", "IDP", "IDR", "HOTA", "GT",
                "IDSW", "FN", "FP");
  out << line;
  auto row = [&](const std::string& name, const JointScores& s) {
    const auto& c = s.counts;
    std::snprintf(line, sizeof line,
                  "%-15s %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %7lld %6lld %6lld "
                  "%6lld\n",
                  name.c_str(), s.ap, s.mota, s.motp, s.precision, s.recall, s.idf1, s.id_precision,
                  s.id_recall, hotaScores(s.hota).mean_hota, static_cast<long long>(c.objects),
                  static_cast<long long>(c.switches), static_cast<long long>(c.misses),
                  static_cast<long long>(c.false_positives));
    out << line;
  };
  for (int j = 0; j < kNumPoseTrackJoints; ++j)
    row(std::string(kPoseTrackJointNames[j]), r.joints[j]);
  row("total", r.total);
  out << "(" << r.sequences.size() << " sequence" << (r.sequences.size() == 1 ? "" : "s")
      << "; totals are means over joints, NaN left out, except IDF1, IDP, IDR and HOTA, which "
         "come from the summed counts as do the counts)\n";
  return out.str();
}

std::string poseTrackResultJson(const PoseTrackEvalResult& r) {
  nlohmann::json joints = nlohmann::json::object();
  for (int j = 0; j < kNumPoseTrackJoints; ++j) {
    joints[std::string(kPoseTrackJointNames[j])] = scoresJson(r.joints[j]);
  }
  nlohmann::json doc = {
      {"total", scoresJson(r.total)}, {"joints", joints}, {"sequences", r.sequences}};
  return doc.dump(2);
}

}  // namespace jointflow
