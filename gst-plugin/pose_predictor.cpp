#include "pose_predictor.hpp"

#include <algorithm>

namespace jointflow::gst {

void PosePredictor::observe(const std::vector<TrackedPose>& poses, std::int64_t frame) {
  std::unordered_map<std::int64_t, Motion> next;
  order_.clear();
  for (const TrackedPose& tp : poses) {
    Motion m;
    m.last = tp;
    m.frame = frame;
    const auto prev = tracks_.find(tp.track_id);
    if (prev != tracks_.end() && frame > prev->second.frame) {
      const float dt = static_cast<float>(frame - prev->second.frame);
      const Pose& a = prev->second.last.pose;
      const Pose& b = tp.pose;
      for (int j = 0; j < kNumJoints; ++j) {
        // A joint missed on either frame gets no velocity rather than a jump to or from (0, 0).
        if (a.keypoints[j].score <= 0.f || b.keypoints[j].score <= 0.f) continue;
        m.velocity[2 * j] = (b.keypoints[j].x - a.keypoints[j].x) / dt;
        m.velocity[2 * j + 1] = (b.keypoints[j].y - a.keypoints[j].y) / dt;
      }
      m.box_vx = (b.box.x + b.box.w / 2 - a.box.x - a.box.w / 2) / dt;
      m.box_vy = (b.box.y + b.box.h / 2 - a.box.y - a.box.h / 2) / dt;
    }
    order_.push_back(tp.track_id);
    next.emplace(tp.track_id, m);
  }
  tracks_ = std::move(next);
}

std::vector<TrackedPose> PosePredictor::predict(std::int64_t frame) const {
  std::vector<TrackedPose> out;
  out.reserve(order_.size());
  for (std::int64_t id : order_) {
    const Motion& m = tracks_.at(id);
    const float steps =
        static_cast<float>(std::clamp<std::int64_t>(frame - m.frame, 0, max_horizon_));
    TrackedPose p = m.last;
    for (int j = 0; j < kNumJoints; ++j) {
      if (p.pose.keypoints[j].score <= 0.f) continue;
      p.pose.keypoints[j].x += m.velocity[2 * j] * steps;
      p.pose.keypoints[j].y += m.velocity[2 * j + 1] * steps;
    }
    p.pose.box.x += m.box_vx * steps;
    p.pose.box.y += m.box_vy * steps;
    out.push_back(p);
  }
  return out;
}

}  // namespace jointflow::gst
