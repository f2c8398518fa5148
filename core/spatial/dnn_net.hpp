// Internal: loading an ONNX file into a cv::dnn::Net with the requested execution settings.
#pragma once

#include <string>
#include <vector>

#include <opencv2/dnn.hpp>

#include "jointflow/spatial_model.hpp"

namespace jointflow::detail {

/// Loads `path` (bytes shared through sharedModelBytes) and applies the backend, target and
/// thread count. Throws jointflow::Error naming the file when it is missing, not a loadable ONNX
/// model, or lacks any of `required_outputs` (the message lists what `what` models provide), and
/// when the backend or target is unknown or not available in this OpenCV build.
cv::dnn::Net loadNet(const std::string& path, const std::string& what,
                     const std::vector<std::string>& required_outputs, const DnnOptions& dnn);

/// The graph output names of a loaded net.
std::vector<std::string> outputNames(const cv::dnn::Net& net);

/// Loads `path` only to list its graph outputs (for type "auto").
std::vector<std::string> modelOutputNames(const std::string& path);

}  // namespace jointflow::detail
