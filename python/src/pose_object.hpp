// jointflow.Pose: one tracked person as Python sees it, made from the core's TrackedPose
// (jointflow.Tracker) or from a JointFlowPerson of GstJointFlowMeta (jointflow.gst). Both
// extension modules make the same type: _jointflow registers it, jointflow.gst imports
// _jointflow first and returns instances through pybind11's shared type registry.
#pragma once

#include <array>
#include <cstdint>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace jointflow::python {

struct Pose {
  std::int64_t id = -1;
  bool tentative = true;
  float score = 0.f;
  std::array<float, 4> box{};          ///< x, y, w, h in frame pixels
  pybind11::array_t<float> keypoints;  ///< (17, 3): x, y, score; made once, owned by the pose
  int age = 0;
  double age_seconds = 0.0;
  std::int64_t previous_id = 0;  ///< TrackedPose::previous_track_id
};

/// A Pose whose keypoints are copied from `xyz`: 17 (x, y, score) triples, `stride` floats apart.
Pose makePose(std::int64_t id, bool tentative, float score, const std::array<float, 4>& box,
              const float* xyz, std::size_t stride, int age, double age_seconds,
              std::int64_t previous_id);

/// Registers jointflow.Pose in `m` (the _jointflow module only).
void registerPose(pybind11::module_& m);

}  // namespace jointflow::python
