#include "dnn_net.hpp"

#include <algorithm>
#include <sstream>

#include <opencv2/core/utility.hpp>

#include "jointflow/error.hpp"
#include "jointflow/model_bytes.hpp"

namespace jointflow::detail {
namespace {

int cvBackend(DnnBackend b) {
  switch (b) {
    case DnnBackend::kOpenCV:
      return cv::dnn::DNN_BACKEND_OPENCV;
    case DnnBackend::kCuda:
      return cv::dnn::DNN_BACKEND_CUDA;
    case DnnBackend::kOpenVino:
      return cv::dnn::DNN_BACKEND_INFERENCE_ENGINE;
    case DnnBackend::kDefault:
      break;
  }
  return cv::dnn::DNN_BACKEND_DEFAULT;
}

int cvTarget(DnnTarget t) {
  switch (t) {
    case DnnTarget::kOpenCL:
      return cv::dnn::DNN_TARGET_OPENCL;
    case DnnTarget::kOpenCLFp16:
      return cv::dnn::DNN_TARGET_OPENCL_FP16;
    case DnnTarget::kCuda:
      return cv::dnn::DNN_TARGET_CUDA;
    case DnnTarget::kCudaFp16:
      return cv::dnn::DNN_TARGET_CUDA_FP16;
    case DnnTarget::kCpu:
      break;
  }
  return cv::dnn::DNN_TARGET_CPU;
}

// The name of an OpenCV backend or target id, for the list of what this build has.
template <typename E, int (*ToCv)(E)>
std::string nameOf(int value) {
  for (const auto& e : EnumInfo<E>::kEntries)
    if (ToCv(e.value) == value && std::string(e.nick) != "default") return e.nick;
  return std::to_string(value);
}

std::string available() {
  std::string s;
  for (const auto& [b, t] : cv::dnn::getAvailableBackends()) {
    s += (s.empty() ? "" : ", ") + nameOf<DnnBackend, cvBackend>(b) + "/" +
         nameOf<DnnTarget, cvTarget>(t);
  }
  return s.empty() ? "none" : s;
}

struct BackendTarget {
  int backend, target;
};

BackendTarget checkDnnOptions(const DnnOptions& dnn) {
  const int backend = cvBackend(dnn.backend), target = cvTarget(dnn.target);
  // The default backend is OpenCV's own unless OpenCV was built to prefer another; ask it.
  const auto targets = cv::dnn::getAvailableTargets(static_cast<cv::dnn::Backend>(backend));
  if (std::find(targets.begin(), targets.end(), target) == targets.end()) {
    throw Error(std::string("dnn backend \"") + toString(dnn.backend) + "\" with target \"" +
                toString(dnn.target) + "\" is not available in this OpenCV " + CV_VERSION +
                " build; available backend/target pairs: " + available());
  }
  if (dnn.num_threads < 0) {
    throw Error("dnn thread count must be >= 0 (0 = OpenCV's default), got " +
                std::to_string(dnn.num_threads));
  }
  return {backend, target};
}

cv::dnn::Net readNet(const std::string& path) {
  const ModelBytes bytes = sharedModelBytes(path);
  try {
    cv::dnn::Net net =
        cv::dnn::readNetFromONNX(reinterpret_cast<const char*>(bytes->data()), bytes->size());
    if (net.empty()) throw Error("model file " + path + " holds no network");
    return net;
  } catch (const cv::Exception& e) {
    throw Error("model file " + path +
                " is not an ONNX model that OpenCV can load (truncated or corrupt?): " + e.what());
  }
}

}  // namespace

std::vector<std::string> outputNames(const cv::dnn::Net& net) {
  // OpenCV's ONNX importer names one unconnected output layer after each graph output.
  return net.getUnconnectedOutLayersNames();
}

std::vector<std::string> modelOutputNames(const std::string& path) {
  return outputNames(readNet(path));
}

cv::dnn::Net loadNet(const std::string& path, const std::string& what,
                     const std::vector<std::string>& required_outputs, const DnnOptions& dnn) {
  const BackendTarget bt = checkDnnOptions(dnn);
  cv::dnn::Net net = readNet(path);
  const auto outs = outputNames(net);
  std::vector<std::string> missing;
  for (const auto& r : required_outputs) {
    if (std::find(outs.begin(), outs.end(), r) == outs.end()) missing.push_back(r);
  }
  if (!missing.empty()) {
    std::ostringstream msg;
    msg << "model file " << path << " is not a " << what << " model: expected outputs";
    for (const auto& r : required_outputs) msg << " " << r;
    msg << "; it has";
    for (const auto& o : outs) msg << " " << o;
    msg << " (missing";
    for (const auto& m : missing) msg << " " << m;
    msg << ")";
    throw Error(msg.str());
  }
  net.setPreferableBackend(bt.backend);
  net.setPreferableTarget(bt.target);
  // OpenCV's thread pool is process-wide: the last model created sets it.
  if (dnn.num_threads > 0) cv::setNumThreads(dnn.num_threads);
  return net;
}

}  // namespace jointflow::detail
