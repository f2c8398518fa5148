#include "frame.hpp"

#include <string>

#include <pybind11/numpy.h>

namespace py = pybind11;

namespace jointflow::python {
namespace {

std::string shapeText(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) text += (i ? ", " : "") + std::to_string(a.shape(i));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

std::string stridesText(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) text += (i ? ", " : "") + std::to_string(a.strides(i));
  return text + ")";
}

}  // namespace

cv::Mat wrapFrame(const py::handle& frame) {
  if (!py::isinstance<py::array>(frame))
    throw py::type_error(
        "frame: expected a numpy.ndarray of shape (H, W, 3) and dtype uint8, got " +
        std::string(py::str(py::type::handle_of(frame).attr("__name__"))) +
        " (numpy.asarray(image) makes one)");
  const auto a = py::reinterpret_borrow<py::array>(frame);
  if (!py::isinstance<py::array_t<std::uint8_t>>(frame) || a.itemsize() != 1)
    throw py::type_error("frame: expected dtype uint8, got " + std::string(py::str(a.dtype())) +
                         " (8-bit pixels 0..255; e.g. (frame * 255).astype(numpy.uint8) for "
                         "floats in [0, 1])");
  if (a.ndim() != 3 || a.shape(2) != 3) {
    std::string hint;
    if (a.ndim() == 2 || (a.ndim() == 3 && a.shape(2) == 1))
      hint = "; a grey frame: cv2.cvtColor(frame, cv2.COLOR_GRAY2BGR)";
    else if (a.ndim() == 3 && a.shape(2) == 4)
      hint = "; a 4-channel frame: cv2.cvtColor(frame, cv2.COLOR_BGRA2BGR)";
    throw py::value_error("frame: expected shape (H, W, 3), got " + shapeText(a) + hint);
  }
  const py::ssize_t rows = a.shape(0), cols = a.shape(1);
  if (rows == 0 || cols == 0) throw py::value_error("frame: empty, shape " + shapeText(a));
  // cv::Mat holds rows `step` bytes apart with packed pixels in each row: the channel and pixel
  // strides must be 1 and 3, and the row stride positive and at least a row's bytes.
  if (a.strides(2) != 1 || a.strides(1) != 3 || a.strides(0) < 3 * cols)
    throw py::value_error(
        "frame: the array's pixels are not contiguous (strides " + stridesText(a) +
        "; expected (>= " + std::to_string(3 * cols) +
        ", 3, 1)), e.g. a view with a step such as frame[:, ::2] or frame[..., ::-1]: pass "
        "numpy.ascontiguousarray(frame), or for an RGB frame rgb=True instead of reversing the "
        "channels");
  return cv::Mat(static_cast<int>(rows), static_cast<int>(cols), CV_8UC3,
                 const_cast<void*>(a.data()), static_cast<std::size_t>(a.strides(0)));
}

}  // namespace jointflow::python
