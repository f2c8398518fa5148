// Small hand-made PoseTrack sequences for exact tests.
#pragma once

#include <cstdint>
#include <string>

#include "jointflow/posetrack.hpp"

namespace jointflow::test {

/// A person with all 15 joints on a 10 px grid around (x, y) and a 30 x 40 head box
/// (head size 0.6 x 50 = 30 px, so joints match within 15 px).
inline posetrack::Person syntheticPerson(std::int64_t track_id, double x, double y) {
  posetrack::Person p;
  p.track_id = track_id;
  for (int j = 0; j < posetrack::kNumPoseTrackJoints; ++j) {
    p.joints[j] =
        posetrack::PoseTrackPoint{x + 10.0 * (j % 4), y + 10.0 * (j / 4), std::nullopt, 1};
  }
  p.head_box = posetrack::HeadBox{x, y - 40.0, x + 30.0, y};
  return p;
}

/// `frames` frames named "<name>/00000k.jpg"; people added by the caller.
inline posetrack::Sequence syntheticSequence(const std::string& name, int frames) {
  posetrack::Sequence seq;
  seq.name = name;
  seq.source = name + ".json";
  seq.vid_id = "000001";
  for (int f = 0; f < frames; ++f) {
    posetrack::Frame frame;
    frame.file_name = "images/val/" + name + "/" + std::to_string(100000 + f).substr(1) + ".jpg";
    frame.image_id = 10000 + f;
    frame.frame_id = 10000 + f;
    seq.frames.push_back(frame);
  }
  return seq;
}

}  // namespace jointflow::test
