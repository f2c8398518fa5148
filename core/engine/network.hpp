// Internal: the engine seam. A Network is one ONNX file loaded on one inference engine, for one
// stream: set the input, run, read the outputs by name. Two engines implement it:
//   cv::dnn  (dnn_network.cpp), the default: backends "default", "opencv", "cuda";
//   OpenVINO (openvino_network.cpp), backend "openvino": OpenVINO's own C++ runtime, built into
//            a module of its own (libjointflow-openvino.so) that is loaded on first use, so that
//            a build or a machine without OpenVINO still runs everything else and says how to
//            get it (openvino_loader.cpp).
// The decoders and runners above it (NetSpatialModel, TemporalFlowModel) do not know which
// engine runs their network.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

#include "jointflow/engine_options.hpp"
#include "mat_pool.hpp"

namespace jointflow::detail {

/// How an 8-bit image becomes a network's float input: (pixel - mean) * scale, RGB order, NCHW.
struct ImageInput {
  bool bgr = true;  ///< the image's pixels are in B, G, R order (else R, G, B)
  double scale = 1.0;
  double mean = 0.0;
};

class Network {
 public:
  virtual ~Network() = default;

  /// The graph's output names, in graph order.
  virtual std::vector<std::string> outputNames() const = 0;
  /// Channels of the (first) input when the file fixes them, else -1.
  virtual int inputChannels() const = 0;

  /// Sets the (only) input: a float32 NCHW blob. The blob is copied or kept until the run ends.
  virtual void setInput(const cv::Mat& blob) = 0;
  /// Sets the (only) input from an 8-bit 3-channel H x W image, as ImageInput says. The image is
  /// kept (not copied) until the run ends. Here: a float blob made on the CPU (into a buffer of
  /// the pool) for setInput(); an engine that can convert in its graph overrides it (OpenVINO).
  virtual void setImage(const cv::Mat& image, const ImageInput& how) {
    cv::Mat blob = blobs_.take({1, image.channels(), image.rows, image.cols}, CV_32F);
    cv::dnn::blobFromImage(image, blob, how.scale, cv::Size(), cv::Scalar::all(how.mean), how.bgr,
                           false, CV_32F);
    setInput(blob);
  }
  /// Starts a run on the input. It runs in the background where the engine can (OpenVINO);
  /// cv::dnn runs it here and now.
  virtual void start() = 0;
  /// Waits for the run that start() began and returns the named outputs, in the order asked, in
  /// buffers that no later run writes over. Throws jointflow::Error when the run failed.
  virtual std::vector<cv::Mat> wait(const std::vector<std::string>& names) = 0;
  /// True when start() returns before the run ends (so work can overlap it).
  virtual bool asynchronous() const = 0;
  /// Runs that may be in flight at once: with 2, the next input can be set and started before
  /// wait() reads the run before (wait() returns the oldest run's outputs first).
  virtual int maxRuns() const { return 1; }
  /// "cv::dnn 4.6.0", "OpenVINO 2026.4.1 CPU", ... for messages and benchmarks.
  virtual std::string engineName() const = 0;
  /// The compiled model this network runs, where several networks can share one
  /// (EngineOptions::model_instance_id); nullptr where each has its own.
  virtual const void* sharedModel() const { return nullptr; }

  std::vector<cv::Mat> run(const cv::Mat& blob, const std::vector<std::string>& names) {
    setInput(blob);
    start();
    return wait(names);
  }

 private:
  MatPool blobs_;  ///< setImage's blobs: the one of the run before may still be in use
};

/// Loads `path` on the engine that `dnn.backend` names and checks that it has every output in
/// `required_outputs`. Throws jointflow::Error naming the file when it is missing, not a model the
/// engine can read, or lacks a required output (the message lists what `what` models provide),
/// and when the backend, target or device is unknown or not available here.
std::unique_ptr<Network> openNetwork(const std::string& path, const std::string& what,
                                     const std::vector<std::string>& required_outputs,
                                     const EngineOptions& dnn);

/// The graph output names of `path` as the engine of `dnn` reads them (for type "auto").
std::vector<std::string> modelOutputNames(const std::string& path, const EngineOptions& dnn = {});

/// Throws jointflow::Error listing what is missing unless `outs` holds every required output.
void checkOutputs(const std::string& path, const std::string& what,
                  const std::vector<std::string>& required_outputs,
                  const std::vector<std::string>& outs);

// Per engine (network.cpp picks one).
std::unique_ptr<Network> openDnnNetwork(const std::string& path, const EngineOptions& dnn);
std::unique_ptr<Network> openOpenVinoNetwork(const std::string& path, const EngineOptions& dnn);

}  // namespace jointflow::detail
