// The cv::dnn engine: an ONNX file in a cv::dnn::Net with the requested backend, target and
// thread count. Runs synchronously (cv::dnn has no asynchronous forward for these backends).
#include <algorithm>

#include <opencv2/core/utility.hpp>
#include <opencv2/dnn.hpp>

#include "jointflow/error.hpp"
#include "jointflow/model_bytes.hpp"
#include "mat_pool.hpp"
#include "network.hpp"

namespace jointflow::detail {
namespace {

// kOpenVino never reaches here: it names OpenVINO's own runtime (openvino_network.cpp), not
// OpenCV's Inference Engine backend, which Debian's OpenCV is built without.
int cvBackend(DnnBackend b) {
  switch (b) {
    case DnnBackend::kOpenCV:
      return cv::dnn::DNN_BACKEND_OPENCV;
    case DnnBackend::kCuda:
      return cv::dnn::DNN_BACKEND_CUDA;
    case DnnBackend::kOpenVino:
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

BackendTarget checkDnnOptions(const EngineOptions& dnn) {
  const int backend = cvBackend(dnn.backend), target = cvTarget(dnn.target);
  // The default backend is OpenCV's own unless OpenCV was built to prefer another; ask it.
  const auto targets = cv::dnn::getAvailableTargets(static_cast<cv::dnn::Backend>(backend));
  if (std::find(targets.begin(), targets.end(), target) == targets.end()) {
    throw Error(std::string("dnn backend \"") + toString(dnn.backend) + "\" with target \"" +
                toString(dnn.target) + "\" is not available in this OpenCV " + CV_VERSION +
                " build; available backend/target pairs: " + available() +
                " (and backend openvino, OpenVINO's own runtime)");
  }
  if (dnn.num_threads < 0) {
    throw Error("dnn thread count must be >= 0 (0 = the engine's default), got " +
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

class DnnNetwork : public Network {
 public:
  // OpenCV's ONNX importer names one unconnected output layer after each graph output.
  DnnNetwork(cv::dnn::Net net, std::string path)
      : net_(std::move(net)), path_(std::move(path)), names_(net_.getUnconnectedOutLayersNames()) {}

  std::vector<std::string> outputNames() const override { return names_; }

  // The input channels of the first convolution: the importer keeps no input shape.
  int inputChannels() const override {
    auto& net = const_cast<cv::dnn::Net&>(net_);
    for (const cv::String& name : net.getLayerNames()) {
      cv::Ptr<cv::dnn::Layer> layer = net.getLayer(net.getLayerId(name));
      if (layer && layer->type == "Convolution" && !layer->blobs.empty() &&
          layer->blobs[0].dims == 4)
        return layer->blobs[0].size[1];
    }
    return -1;
  }

  void setInput(const cv::Mat& blob) override { net_.setInput(blob); }

  void start() override {
    try {
      net_.forward(outs_, names_);
    } catch (const cv::Exception& e) {
      outs_.clear();
      throw Error("model file " + path_ + ": cv::dnn forward failed: " + e.what());
    }
  }

  std::vector<cv::Mat> wait(const std::vector<std::string>& names) override {
    std::vector<cv::Mat> out;
    for (const auto& n : names) {
      const auto it = std::find(names_.begin(), names_.end(), n);
      if (it == names_.end()) throw Error("model file " + path_ + " has no output " + n);
      // The net reuses its output buffers on the next forward pass: copies, into buffers of ours
      // that the frames before have let go.
      const cv::Mat& o = outs_[it - names_.begin()];
      cv::Mat copy = o.empty() ? cv::Mat() : copies_.takeLike(o);
      o.copyTo(copy);
      out.push_back(copy);
    }
    return out;
  }

  bool asynchronous() const override { return false; }
  std::string engineName() const override { return std::string("cv::dnn ") + CV_VERSION; }

 private:
  cv::dnn::Net net_;
  std::string path_;
  std::vector<std::string> names_;
  std::vector<cv::Mat> outs_;
  MatPool copies_;
};

}  // namespace

std::unique_ptr<Network> openDnnNetwork(const std::string& path, const EngineOptions& dnn) {
  const BackendTarget bt = checkDnnOptions(dnn);
  cv::dnn::Net net = readNet(path);
  net.setPreferableBackend(bt.backend);
  net.setPreferableTarget(bt.target);
  // OpenCV's thread pool is process-wide: the last model created sets it.
  if (dnn.num_threads > 0) cv::setNumThreads(dnn.num_threads);
  return std::make_unique<DnnNetwork>(std::move(net), path);
}

}  // namespace jointflow::detail
