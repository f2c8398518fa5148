// A numpy frame as a cv::Mat header over the array's own memory (no copy), or a clear Python
// exception saying what is wrong with the array and how to fix it.
#pragma once

#include <pybind11/pybind11.h>
#include <opencv2/core.hpp>

namespace jointflow::python {

/// Wraps an H x W x 3 uint8 numpy array whose pixels are packed (channel stride 1, pixel stride
/// 3): C-contiguous arrays and row crops of them (frame[y0:y1, x0:x1], kept as the Mat's row
/// step). Raises TypeError (not a numpy array, wrong dtype) or ValueError (shape, empty, layout).
/// The Mat is valid while `frame` is alive and not resized.
cv::Mat wrapFrame(const pybind11::handle& frame);

}  // namespace jointflow::python
