#include "pose_object.hpp"

#include <cstdio>
#include <string>

namespace py = pybind11;

namespace jointflow::python {

Pose makePose(std::int64_t id, bool tentative, float score, const std::array<float, 4>& box,
              const float* xyz, std::size_t stride, int age, double age_seconds,
              std::int64_t previous_id) {
  constexpr py::ssize_t kJoints = 17;
  Pose p;
  p.id = id;
  p.tentative = tentative;
  p.score = score;
  p.box = box;
  p.age = age;
  p.age_seconds = age_seconds;
  p.previous_id = previous_id;
  p.keypoints = py::array_t<float>({kJoints, py::ssize_t{3}});
  auto out = p.keypoints.mutable_unchecked<2>();
  for (py::ssize_t j = 0; j < kJoints; ++j)
    for (py::ssize_t c = 0; c < 3; ++c) out(j, c) = xyz[j * stride + c];
  return p;
}

void registerPose(py::module_& m) {
  py::class_<Pose>(m, "Pose",
                   "One tracked person in one frame. Coordinates are frame pixels (x right, y "
                   "down).")
      .def_readonly("id", &Pose::id,
                    "Track id: unique within the stream, never reused, counts up from 1")
      .def_readonly("tentative", &Pose::tentative,
                    "The track is shorter than min_track_length so far (may be a false "
                    "detection)")
      .def_readonly("score", &Pose::score, "Person score in [0, 1]")
      .def_property_readonly(
          "box",
          [](const Pose& p) { return py::make_tuple(p.box[0], p.box[1], p.box[2], p.box[3]); },
          "Person box (x, y, w, h): left, top, width, height")
      .def_readonly("keypoints", &Pose::keypoints,
                    "(17, 3) float32 array of x, y, score per COCO keypoint (KEYPOINT_NAMES "
                    "order); score 0 = not detected")
      .def_readonly("age", &Pose::age, "Inferred frames since the track started (0 on its first)")
      .def_readonly("age_seconds", &Pose::age_seconds,
                    "Stream time in seconds since the track's first detection")
      .def_readonly("previous_id", &Pose::previous_id,
                    "A person shown under a new id and recognised late as someone who had left "
                    "(reentry_time): the new id they had until then, on every frame from the "
                    "change on; 0 otherwise")
      .def("__repr__", [](const Pose& p) {
        char text[160];
        std::snprintf(text, sizeof text,
                      "<jointflow.Pose id=%lld%s score=%.3f box=(%.1f, %.1f, %.1f, %.1f) age=%d>",
                      static_cast<long long>(p.id), p.tentative ? " tentative" : "", p.score,
                      p.box[0], p.box[1], p.box[2], p.box[3], p.age);
        return std::string(text);
      });
}

}  // namespace jointflow::python
