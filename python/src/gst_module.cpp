// jointflow.gst: the poses of GstJointFlowMeta, read from a PyGObject Gst.Buffer (a pad probe's
// info.get_buffer(), an appsink sample's get_buffer()).
//
// The GstBuffer* comes out of the Python wrapper through PyGObject's own C API (pygobject.h:
// the PyGBoxed struct and its type object, from the gi._gobject capsule), after checking that the
// object is a boxed GstBuffer, rather than from hash(buffer) as pyds and gstgva do: hash() of
// any other object is some number too, which would be read as a buffer. The meta is read through
// its public C API (jointflowmeta.h), so that this module does not depend on the struct layout
// beyond the header it is compiled with.
#include <string>

#include <gst/gst.h>
#include <pybind11/pybind11.h>
// After Python.h (pybind11); defines the _PyGObject_API pointer that pygobject_init() fills.
#include <pygobject.h>

#include "jointflowmeta.h"
#include "pose_object.hpp"

namespace py = pybind11;

namespace {

GstBuffer* bufferOf(const py::handle& object, const char* function) {
  if (!pyg_boxed_check(object.ptr(), gst_buffer_get_type()))
    throw py::type_error(std::string("jointflow.gst.") + function +
                         ": expected a Gst.Buffer (e.g. info.get_buffer() in a pad probe), got " +
                         std::string(py::str(py::type::handle_of(object).attr("__name__"))));
  auto* buffer = pyg_boxed_get(object.ptr(), GstBuffer);
  if (!buffer)
    throw py::value_error(std::string("jointflow.gst.") + function +
                          ": the Gst.Buffer holds no buffer");
  return buffer;
}

py::list poses(const py::handle& object) {
  GstBuffer* buffer = bufferOf(object, "poses");
  py::list out;
  const GstJointFlowMeta* meta = gst_buffer_get_jointflow_meta(buffer);
  const guint n = meta ? gst_jointflow_meta_get_n_persons(meta) : 0;
  for (guint i = 0; i < n; ++i) {
    const JointFlowPerson* p = gst_jointflow_meta_get_person(meta, i);
    if (!p) continue;
    static_assert(sizeof(JointFlowKeypoint) == 3 * sizeof(float), "x, y, score floats");
    out.append(jointflow::python::makePose(p->track_id, p->tentative != FALSE, p->score,
                                           {p->x, p->y, p->width, p->height}, &p->keypoints[0].x, 3,
                                           p->age, p->age_seconds, p->previous_track_id));
  }
  return out;
}

py::object frameInfo(const py::handle& object) {
  const GstJointFlowMeta* meta = gst_buffer_get_jointflow_meta(bufferOf(object, "frame_info"));
  if (!meta) return py::none();
  py::dict info;
  info["width"] = meta->width;
  info["height"] = meta->height;
  info["predicted"] = meta->predicted != FALSE;
  info["n_persons"] = gst_jointflow_meta_get_n_persons(meta);
  return std::move(info);
}

}  // namespace

PYBIND11_MODULE(gst, m) {
  m.doc() =
      "The poses that jointflowtrack attaches to GStreamer buffers (GstJointFlowMeta), for "
      "PyGObject applications: poses(buffer) in a pad probe or on an appsink sample's buffer.";
  // jointflow.Pose is registered by the core module; poses() returns that same type.
  py::module_::import("jointflow._jointflow");
  PyObject* gobject = pygobject_init(-1, -1, -1);
  if (!gobject) {
    // Said as it is: pybind11 would report an error_already_set as "initialization failed".
    const py::error_already_set error;
    throw py::import_error(std::string("PyGObject cannot be imported: ") + error.what());
  }
  Py_DECREF(gobject);

  m.def("poses", &poses, py::arg("buffer"),
        "The tracked poses of a Gst.Buffer (a list of jointflow.Pose, the same as "
        "Tracker.process returns), in pixels of the buffer's frame; [] for a buffer without "
        "JointFlow meta. Call it while the buffer is alive (inside the probe).");
  m.def("frame_info", &frameInfo, py::arg("buffer"),
        "{'width', 'height', 'predicted', 'n_persons'} of the buffer's JointFlow meta (predicted: "
        "the networks did not run on this frame), or None without one.");
}
