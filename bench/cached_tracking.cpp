// Every similarity on the same detections (see cached_tracking.hpp).
#include "cached_tracking.hpp"

#include <chrono>
#include <sstream>

#include "jointflow/error.hpp"
#include "jointflow/posetrack_joints.hpp"

namespace jointflow::bench {

namespace pt = jointflow::posetrack;
using Clock = std::chrono::steady_clock;

namespace {

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

CachedFrame estimateFrame(SpatialModel& model, cv::Mat image) {
  const auto t0 = Clock::now();
  CachedFrame frame{image, model.estimate(image), 0.0};
  frame.spatial_seconds = secondsSince(t0);
  return frame;
}

SimilarityTrackers::SimilarityTrackers(const std::vector<std::string>& similarities,
                                       const TrackerSettings& base)
    : similarities_(similarities) {
  for (const std::string& similarity : similarities) {
    TrackerSettings s = base;
    s.similarity = parseEnum<SimilarityType>(similarity);
    trackers_.push_back(std::make_unique<Tracker>(s));
  }
}

std::vector<TrackRun> SimilarityTrackers::run(
    int count, const std::function<const CachedFrame&(int)>& frame_at,
    const std::function<double(int)>& time_at, const std::function<void(int)>& progress) {
  std::vector<TrackRun> runs(trackers_.size());
  for (size_t i = 0; i < trackers_.size(); ++i) {
    trackers_[i]->reset();
    runs[i].similarity = similarities_[i];
  }
  for (int k = 0; k < count; ++k) {
    const CachedFrame& frame = frame_at(k);
    const double time = time_at(k);
    for (size_t i = 0; i < trackers_.size(); ++i) {
      const auto t0 = Clock::now();
      runs[i].frames.push_back(
          trackers_[i]->process(frame.spatial, frame.image, PixelOrder::kBGR, time));
      runs[i].seconds += secondsSince(t0);
    }
    if (progress) progress(k);
  }
  return runs;
}

pt::Sequence predictionSequence(const pt::Sequence& ground_truth, const TrackRun& run,
                                float joint_threshold) {
  if (run.frames.size() != ground_truth.frames.size())
    throw Error("predictionSequence: " + std::to_string(run.frames.size()) +
                " tracked frames for " + std::to_string(ground_truth.frames.size()) +
                " ground-truth frames");
  pt::Sequence out = ground_truth;
  for (size_t f = 0; f < out.frames.size(); ++f) {
    pt::Frame& frame = out.frames[f];
    frame.people.clear();
    frame.ignore_regions.clear();
    for (const TrackedPose& t : run.frames[f]) {
      pt::Person person;
      person.track_id = t.track_id;
      person.score = t.pose.score;
      person.joints = pt::toPoseTrackJoints(t.pose, joint_threshold);
      frame.people.push_back(std::move(person));
    }
  }
  return out;
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace jointflow::bench
