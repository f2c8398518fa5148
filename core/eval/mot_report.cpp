// Printing MOT results (mot_evaluation.hpp): a table and JSON.
#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "jointflow/mot_evaluation.hpp"

namespace jointflow::mot {

namespace {

nlohmann::json number(double v) {
  return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v);
}

nlohmann::json scoresJson(const MotScores& s) {
  const HotaScores h = s.hotaScores();
  nlohmann::json per_alpha = nlohmann::json::array();
  for (double v : h.hota) per_alpha.push_back(v);
  const auto& c = s.clear;
  return {{"frames", s.frames},
          {"gt_dets", s.gt_dets},
          {"pred_dets", s.pred_dets},
          {"gt_ids", s.gt_ids},
          {"pred_ids", s.pred_ids},
          {"recall", number(s.recall())},
          {"precision", number(s.precision())},
          {"mota", number(s.mota())},
          {"motp", number(s.motp())},
          {"id_switches", c.switches},
          {"matches", c.detections()},
          {"false_positives", c.false_positives},
          {"misses", c.misses},
          {"idf1", number(s.idf1())},
          {"idp", number(s.idp())},
          {"idr", number(s.idr())},
          {"idtp", c.id_true_positives},
          {"idfp", c.id_false_positives},
          {"idfn", c.id_false_negatives},
          {"hota", h.mean_hota},
          {"deta", h.deta},
          {"assa", h.assa},
          {"loca", h.loca},
          {"detre", h.detre},
          {"detpr", h.detpr},
          {"assre", h.assre},
          {"asspr", h.asspr},
          {"hota_alpha", per_alpha}};
}

std::string row(const std::string& name, const MotScores& s) {
  const HotaScores h = s.hotaScores();
  const double frames = s.frames > 0 ? static_cast<double>(s.frames) : 1.0;
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "%-18s %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %5lld %6.1f %6.1f %6.1f %6.1f\n",
                name.c_str(), static_cast<double>(s.gt_dets) / frames,
                static_cast<double>(s.clear.detections()) / frames, s.recall(), s.precision(),
                s.mota(), s.motp(), static_cast<long long>(s.clear.switches), s.idf1(),
                h.mean_hota, h.deta, h.assa);
  return buf;
}

}  // namespace

std::string formatTable(const MotEvalResult& result) {
  std::ostringstream out;
  out << "sequence           people  found recall  prec.   MOTA   MOTP   IDSW   IDF1   HOTA"
         "   DetA   AssA\n"
      << "                   /frame /frame      %      %      %      %             %      %"
         "      %      %\n";
  for (const auto& [name, scores] : result.sequences) out << row(name, scores);
  if (result.sequences.size() > 1) out << row("combined", result.combined);
  return out.str();
}

std::string resultJson(const MotEvalResult& result) {
  nlohmann::json sequences = nlohmann::json::object();
  for (const auto& [name, scores] : result.sequences) sequences[name] = scoresJson(scores);
  return nlohmann::json{{"sequences", sequences}, {"combined", scoresJson(result.combined)}}
      .dump(1);
}

}  // namespace jointflow::mot
