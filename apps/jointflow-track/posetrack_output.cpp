// PoseTrack output of jointflow-track (posetrack_output.hpp).
#include "posetrack_output.hpp"

#include <cstdio>
#include <filesystem>

#include "jointflow/pose_associator.hpp"
#include "jointflow/posetrack_joints.hpp"

namespace jointflow::cli {
namespace {

Pose toPose(const JointFlowPerson& p) {
  Pose pose;
  pose.score = p.score;
  pose.box = {p.x, p.y, p.width, p.height};
  for (int j = 0; j < JOINTFLOW_N_KEYPOINTS; ++j)
    pose.keypoints[j] = {p.keypoints[j].x, p.keypoints[j].y, p.keypoints[j].score};
  return pose;
}

}  // namespace

PoseTrackOutput::PoseTrackOutput(std::string sequence, std::string file_prefix,
                                 std::vector<std::string> frame_names, float joint_threshold)
    : file_prefix_(std::move(file_prefix)),
      frame_names_(std::move(frame_names)),
      joint_threshold_(joint_threshold) {
  sequence_.name = std::move(sequence);
}

std::string PoseTrackOutput::fileName(std::int64_t index) const {
  if (index >= 0 && static_cast<size_t>(index) < frame_names_.size())
    return file_prefix_ + frame_names_[index];
  char number[32];
  std::snprintf(number, sizeof number, "%06lld.jpg", static_cast<long long>(index));
  return file_prefix_ + number;
}

void PoseTrackOutput::addEmptyFrame(std::int64_t index) {
  posetrack::Frame frame;
  frame.file_name = fileName(index);
  frame.image_id = frame.frame_id = index;
  sequence_.frames.push_back(std::move(frame));
  tracker_ids_.emplace_back();
}

void PoseTrackOutput::addFrame(std::int64_t index, const GstJointFlowMeta* meta) {
  const std::int64_t next = static_cast<std::int64_t>(sequence_.frames.size());
  if (index < next) index = next;
  fillTo(index);
  addEmptyFrame(index);
  posetrack::Frame& frame = sequence_.frames.back();
  const guint n = meta ? gst_jointflow_meta_get_n_persons(meta) : 0;
  std::vector<std::int64_t> track_ids;
  for (guint i = 0; i < n; ++i)
    track_ids.push_back(gst_jointflow_meta_get_person(meta, i)->track_id);
  const std::vector<int> numbers = ids_.assign(track_ids);
  for (guint i = 0; i < n; ++i) {
    const JointFlowPerson* p = gst_jointflow_meta_get_person(meta, i);
    posetrack::Person person;
    person.track_id = numbers[i];
    person.joints = posetrack::toPoseTrackJoints(toPose(*p), joint_threshold_);
    person.score = p->score;
    frame.people.push_back(std::move(person));
  }
  tracker_ids_.back() = track_ids;
}

void PoseTrackOutput::pruneShortTracks(int min_frames) {
  if (min_frames <= 1) return;
  const std::set<std::int64_t> long_tracks = longTracks(tracker_ids_, min_frames);
  for (size_t f = 0; f < sequence_.frames.size(); ++f) {
    auto& people = sequence_.frames[f].people;
    std::vector<posetrack::Person> kept;
    std::vector<std::int64_t> kept_ids;
    for (size_t i = 0; i < people.size(); ++i)
      if (long_tracks.count(tracker_ids_[f][i])) {
        kept.push_back(std::move(people[i]));
        kept_ids.push_back(tracker_ids_[f][i]);
      }
    people = std::move(kept);
    tracker_ids_[f] = std::move(kept_ids);
  }
}

void PoseTrackOutput::fillTo(std::int64_t count) {
  for (auto i = static_cast<std::int64_t>(sequence_.frames.size()); i < count; ++i)
    addEmptyFrame(i);
}

std::string PoseTrackOutput::path(const std::string& dir) const {
  return (std::filesystem::path(dir) / (sequence_.name + ".json")).string();
}

void PoseTrackOutput::write(const std::string& dir) const {
  posetrack::writeSequence(sequence_, path(dir), posetrack::Format::k2018);
}

}  // namespace jointflow::cli
