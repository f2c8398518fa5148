// Test helper: how many ground-truth people of a PoseTrack 2018 sequence a spatial model finds.
// A GT person is found when one prediction (each used once, best pairs first) has PCKh@0.5 on at
// least half of the person's annotated body joints. Body joints = the 12 joints COCO-17 and
// PoseTrack share by name (shoulders, elbows, wrists, hips, knees, ankles); the head joints are
// skipped (COCO has no neck or head top). Head size = 0.6 x the GT head box diagonal (poseval).
#pragma once

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "jointflow/spatial_model.hpp"

namespace jointflow::test {

struct FoundCount {
  int found = 0;
  int total = 0;
  int predictions = 0;
  double rate() const { return total ? static_cast<double>(found) / total : 0.0; }
};

inline FoundCount countFound(SpatialModel& model, const std::string& root,
                             const std::string& gt_json) {
  const auto gt = nlohmann::json::parse(std::ifstream(gt_json));
  const auto& names = gt["categories"][0]["keypoints"];
  std::vector<std::pair<int, int>> joints;  // (PoseTrack index, COCO index)
  for (int j = 5; j < kNumJoints; ++j) {
    for (size_t k = 0; k < names.size(); ++k) {
      if (names[k].get<std::string>() == kJointNames[j])
        joints.emplace_back(static_cast<int>(k), j);
    }
  }
  FoundCount count;
  for (const auto& image : gt["images"]) {
    const cv::Mat frame = cv::imread(root + "/" + image["file_name"].get<std::string>());
    if (frame.empty())
      throw std::runtime_error("cannot read " + image["file_name"].get<std::string>());
    const Poses poses = model.estimate(frame).poses;
    count.predictions += static_cast<int>(poses.size());
    struct Pair {
      double pckh;
      size_t gt, pred;
    };
    std::vector<Pair> pairs;
    size_t num_gt = 0;
    for (const auto& a : gt["annotations"]) {
      if (a["image_id"] != image["id"]) continue;
      const auto& kp = a["keypoints"];
      const auto& hb = a["bbox_head"];
      const double head = 0.6 * std::hypot(hb[2].get<double>(), hb[3].get<double>());
      int annotated = 0;
      for (const auto& [pt, coco] : joints) annotated += kp[3 * pt + 2].get<double>() > 0;
      if (annotated == 0) continue;
      for (size_t p = 0; p < poses.size(); ++p) {
        int hit = 0;
        for (const auto& [pt, coco] : joints) {
          if (kp[3 * pt + 2].get<double>() <= 0) continue;
          const auto& k = poses[p].keypoints[coco];
          if (k.score <= 0.f) continue;
          const double d =
              std::hypot(k.x - kp[3 * pt].get<double>(), k.y - kp[3 * pt + 1].get<double>());
          hit += d <= 0.5 * head;
        }
        pairs.push_back({static_cast<double>(hit) / annotated, num_gt, p});
      }
      ++num_gt;
    }
    std::sort(pairs.begin(), pairs.end(),
              [](const Pair& a, const Pair& b) { return a.pckh > b.pckh; });
    std::vector<bool> gt_used(num_gt), pred_used(poses.size());
    for (const auto& pr : pairs) {
      if (pr.pckh < 0.5 || gt_used[pr.gt] || pred_used[pr.pred]) continue;
      gt_used[pr.gt] = pred_used[pr.pred] = true;
      ++count.found;
    }
    count.total += static_cast<int>(num_gt);
  }
  return count;
}

}  // namespace jointflow::test
