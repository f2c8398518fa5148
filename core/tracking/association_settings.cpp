// Range checks of the association settings, one message per setting naming what was expected.
#include <cmath>
#include <string>

#include "jointflow/error.hpp"
#include "jointflow/pose_associator.hpp"

namespace jointflow {
namespace {

void require(bool ok, const std::string& name, const std::string& expected, double value) {
  if (!ok)
    throw Error("tracker setting " + name + " = " + std::to_string(value) + " is out of range, " +
                "expected " + expected);
}

bool finite(float v) {
  return std::isfinite(v);
}

}  // namespace

void validateAssociationSettings(const TrackerSettings& s) {
  require(finite(s.min_potential), "min_potential", "a finite number", s.min_potential);
  require(s.min_track_length >= 1, "min_track_length", ">= 1", s.min_track_length);
  require(s.min_report_length >= 1, "min_report_length", ">= 1", s.min_report_length);
  require(finite(s.contested_time) && s.contested_time >= 0.f && s.contested_time <= 3600.f,
          "contested_time", "0 to 3600 s", s.contested_time);
  require(finite(s.lost_time) && s.lost_time >= 0.f && s.lost_time <= 3600.f, "lost_time",
          "0 to 3600 s", s.lost_time);
  require(finite(s.tentative_lost_time) && s.tentative_lost_time >= 0.f &&
              s.tentative_lost_time <= 3600.f,
          "tentative_lost_time", "0 to 3600 s", s.tentative_lost_time);
  require(s.reid_min_similarity >= 0.f && s.reid_min_similarity <= 1.f, "reid_min_similarity",
          "in [0, 1]", s.reid_min_similarity);
  require(finite(s.reentry_time) && s.reentry_time >= 0.f && s.reentry_time <= 3600.f,
          "reentry_time", "0 to 3600 s", s.reentry_time);
  require(s.reentry_min_similarity >= 0.f && s.reentry_min_similarity <= 1.f,
          "reentry_min_similarity", "in [0, 1]", s.reentry_min_similarity);
  require(finite(s.swap_margin) && s.swap_margin >= 0.f && s.swap_margin <= 2.f, "swap_margin",
          "in [0, 2]", s.swap_margin);
  require(s.max_persons >= 1, "max_persons", ">= 1", s.max_persons);
  require(s.joint_threshold >= 0.f && s.joint_threshold <= 1.f, "joint_threshold", "in [0, 1]",
          s.joint_threshold);
  if (!s.joint_thresholds.empty() && s.joint_thresholds.size() != kNumJoints)
    throw Error("tracker setting joint_thresholds has " +
                std::to_string(s.joint_thresholds.size()) +
                " values, expected 17 (one per COCO joint) or none");
  require(s.tff_oks_weight >= 0.f && s.tff_oks_weight <= 1.f, "tff_oks_weight", "in [0, 1]",
          s.tff_oks_weight);
  // The TFF keeps 1 - both; a float's rounding (0.3 + 0.7) is not the user's fault.
  require(s.tff_flow_weight >= 0.f && s.tff_flow_weight <= 1.f - s.tff_oks_weight + 1e-6f,
          "tff_flow_weight",
          "in [0, 1 - tff_oks_weight] = [0, " + std::to_string(1.f - s.tff_oks_weight) +
              "] (the TFF's weight is 1 - both; lower one of them)",
          s.tff_flow_weight);
  require(s.auto_tff_gap >= 0.f && s.auto_tff_gap <= 3600.f, "auto_tff_gap", "in [0, 3600] seconds",
          s.auto_tff_gap);
  require(s.track_score >= 0.f && s.track_score <= 1.f, "track_score", "in [0, 1]", s.track_score);
  require(s.coast_min_oks >= 0.f && s.coast_min_oks <= 1.f, "coast_min_oks", "in [0, 1]",
          s.coast_min_oks);
  require(s.duplicate_oks >= 0.f && s.duplicate_oks <= 1.f, "duplicate_oks", "in [0, 1] (0 = off)",
          s.duplicate_oks);
  require(finite(s.min_person_size) && s.min_person_size >= 0.f, "min_person_size", ">= 0 px",
          s.min_person_size);
  require(finite(s.frame_rate) && s.frame_rate > 0.f, "frame_rate", "> 0 frames per second",
          s.frame_rate);
  require(finite(s.euro_min_cutoff) && s.euro_min_cutoff > 0.f, "euro_min_cutoff", "> 0 Hz",
          s.euro_min_cutoff);
  require(finite(s.euro_beta) && s.euro_beta >= 0.f, "euro_beta", ">= 0", s.euro_beta);
  require(finite(s.euro_d_cutoff) && s.euro_d_cutoff > 0.f, "euro_d_cutoff", "> 0 Hz",
          s.euro_d_cutoff);
  // tau_delta, line_samples, sigma_flow and min_common_joints are checked by createSimilarity.
}

}  // namespace jointflow
