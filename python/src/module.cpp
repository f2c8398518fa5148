// jointflow._jointflow: the core's Tracker for numpy frames (python/jointflow/__init__.py is the
// package around it).
//
// A frame is wrapped, not copied (frame.hpp), and the GIL is released while the networks run, so
// that other Python threads (capture, display) go on meanwhile. One Tracker serves one stream; a
// mutex makes concurrent calls on the same Tracker wait for each other instead of racing.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <opencv2/core.hpp>

#include "frame.hpp"
#include "jointflow/error.hpp"
#include "jointflow/tracker.hpp"
#include "jointflow/types.hpp"
#include "pose_object.hpp"
#include "settings_args.hpp"

namespace py = pybind11;

namespace jointflow::python {
namespace {

double timestampArg(const py::handle& timestamp) {
  if (timestamp.is_none()) return std::numeric_limits<double>::quiet_NaN();
  if (PyBool_Check(timestamp.ptr()) || PyUnicode_Check(timestamp.ptr()) ||
      !PyNumber_Check(timestamp.ptr()))
    throw py::type_error("timestamp: expected seconds of stream time as a float, or None, got " +
                         std::string(py::str(py::type::handle_of(timestamp).attr("__name__"))));
  const double t = PyFloat_AsDouble(timestamp.ptr());
  if (t == -1.0 && PyErr_Occurred()) throw py::error_already_set();
  return t;
}

py::list posesList(const std::vector<TrackedPose>& tracked) {
  py::list out;
  for (const TrackedPose& t : tracked) {
    const jointflow::Pose& p = t.pose;
    out.append(makePose(t.track_id, t.tentative, p.score, {p.box.x, p.box.y, p.box.w, p.box.h},
                        &p.keypoints[0].x, sizeof(jointflow::Keypoint) / sizeof(float), t.age,
                        t.age_seconds, t.previous_track_id));
  }
  return out;
}

class PyTracker {
 public:
  explicit PyTracker(const TrackerSettings& settings) : tracker_(settings) {}

  py::list process(const py::handle& frame, bool rgb, const py::handle& timestamp) {
    const cv::Mat image = wrapFrame(frame);
    const double t = timestampArg(timestamp);
    std::vector<TrackedPose> tracked;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      frame_address_ = reinterpret_cast<std::uintptr_t>(image.data);
      const auto start = std::chrono::steady_clock::now();
      tracked = tracker_.process(image, rgb ? PixelOrder::kRGB : PixelOrder::kBGR, t);
      core_seconds_ =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return posesList(tracked);
  }

  // The bench's reference: the same call timed in C++ alone, without the Python around it.
  double processSeconds(const py::handle& frame, bool rgb) {
    const cv::Mat image = wrapFrame(frame);
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    const auto start = std::chrono::steady_clock::now();
    tracker_.process(image, rgb ? PixelOrder::kRGB : PixelOrder::kBGR);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  py::list predict(const py::handle& timestamp) {
    const double t = timestampArg(timestamp);
    if (std::isnan(t)) throw py::type_error("predict: timestamp must be seconds, not None");
    std::vector<TrackedPose> tracked;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      tracked = tracker_.predict(t);
    }
    return posesList(tracked);
  }

  void reset() {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    tracker_.reset();
  }

  py::dict settings() const { return settingsDict(tracker_.settings()); }
  std::string engine() const { return tracker_.engine(); }
  std::uintptr_t frameAddress() const { return frame_address_; }
  double coreSeconds() const { return core_seconds_; }

 private:
  Tracker tracker_;
  std::mutex mutex_;
  std::uintptr_t frame_address_ = 0;  ///< data pointer of the last frame given to the core
  double core_seconds_ = 0.0;         ///< time of the last process() in Tracker::process
};

}  // namespace
}  // namespace jointflow::python

PYBIND11_MODULE(_jointflow, m) {
  using namespace jointflow::python;
  m.doc() = "JointFlow multi-person pose tracking (the C++ core; use the jointflow package)";
  m.attr("__version__") = JOINTFLOW_VERSION;
  m.attr("_pybind11_version") =
      py::make_tuple(PYBIND11_VERSION_MAJOR, PYBIND11_VERSION_MINOR, PYBIND11_VERSION_PATCH);

  // The core's errors name the setting or file at fault; they reach Python as ValueError with
  // the same message. OpenCV's own (a model it cannot run) as RuntimeError.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const jointflow::Error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const cv::Exception& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });

  registerPose(m);

  py::tuple names(jointflow::kNumJoints);
  for (int j = 0; j < jointflow::kNumJoints; ++j) names[j] = std::string(jointflow::kJointNames[j]);
  m.attr("KEYPOINT_NAMES") = names;
  py::list limbs;
  for (const auto& [a, b] : jointflow::kCocoSkeleton) limbs.append(py::make_tuple(a, b));
  m.attr("SKELETON") = py::tuple(limbs);

  m.def("_settings_schema", &settingsSchemaList);

  py::class_<PyTracker>(m, "Tracker", trackerDoc().c_str())
      .def(py::init([](const py::kwargs& kwargs) {
             const jointflow::TrackerSettings settings = settingsFromKwargs(kwargs);
             py::gil_scoped_release release;  // loading the models takes a while
             return std::make_unique<PyTracker>(settings);
           }),
           "Loads the models; raises ValueError for a bad setting or model file.")
      .def("process", &PyTracker::process, py::arg("frame"), py::arg("rgb") = false,
           py::arg("timestamp") = py::none(),
           "Tracks the people of one frame: a numpy uint8 array (H, W, 3), BGR (OpenCV's order) "
           "or with rgb=True RGB, used in place without a copy. timestamp: seconds of stream "
           "time (None: 1 / 30 s after the previous frame). Returns a list of Pose.")
      .def("predict", &PyTracker::predict, py::arg("timestamp"),
           "The poses of the last process() moved on to `timestamp` seconds by each track's "
           "motion model, for frames the networks skip. The tracker is not changed.")
      .def("reset", &PyTracker::reset,
           "Forgets every track and the previous frame (a cut, a seek). Ids keep counting up.")
      .def_property_readonly("settings", &PyTracker::settings,
                             "The settings in force, {name: value}")
      .def_property_readonly("engine", &PyTracker::engine, "The inference engine, for logs")
      .def_property_readonly("_frame_address", &PyTracker::frameAddress,
                             "Test hook: address of the pixels the core read last")
      .def_property_readonly("_core_seconds", &PyTracker::coreSeconds,
                             "Bench hook: seconds the last process() spent in the C++ Tracker")
      .def("_process_seconds", &PyTracker::processSeconds, py::arg("frame"), py::arg("rgb") = false,
           "Bench hook: process() timed in C++ alone; returns seconds, not poses");
}
