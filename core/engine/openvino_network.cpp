// The OpenVINO engine (backend "openvino"): OpenVINO's C++ runtime from the PyPI wheel `openvino`
// (scripts/openvino-venv.sh). Built into libjointflow-openvino.so, which the core loads on first
// use (openvino_loader.cpp).
//
// A SharedModel is one ONNX file read once and compiled for one device and configuration, once
// per input shape it meets (the spatial networks take any H x W, the TFF network any grid), and
// kept for the next frames. Networks whose EngineOptions::model_instance_id is the same share it,
// as DL Streamer's model-instance-id does: one copy of the weights and one executor for every
// stream of a process. Each Network (one per stream) keeps its own infer requests per shape, two
// where a frame's run is queued behind the one before (maxRuns), so streams never wait for each
// other's outputs, and runs them asynchronously.
#include <algorithm>
#include <cstring>
#include <deque>
#include <filesystem>
#include <list>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>

#include <openvino/core/preprocess/pre_post_process.hpp>
#include <openvino/openvino.hpp>

#include "jointflow/error.hpp"
#include "mat_pool.hpp"
#include "network.hpp"
#include "openvino_module.hpp"

namespace jointflow::detail {
namespace {

using ShapeKey = std::vector<size_t>;

/// What a compiled model takes: a float NCHW blob of `shape`, or an 8-bit image (`image`) whose
/// conversion to the network's float NCHW input runs in OpenVINO's graph (withLayouts()).
struct InputKey {
  ShapeKey shape;  ///< the network's NCHW input shape
  bool image = false;
  ImageInput how;

  bool operator==(const InputKey& o) const {
    return shape == o.shape && image == o.image &&
           (!image || (how.bgr == o.how.bgr && how.scale == o.how.scale && how.mean == o.how.mean));
  }
};

/// Inputs (shape and kind, InputKey) compiled and kept per model (each costs its compile time and
/// its memory): more than a stream meets unless its resolution keeps changing.
constexpr size_t kMaxShapes = 6;
/// Runs of one stream in flight at once (Network::maxRuns): a frame's run starts before the
/// outputs of the frame before are read.
constexpr int kMaxRuns = 2;

ov::Core& core() {
  static ov::Core instance;  // loads the device plugins once per process; thread-safe
  return instance;
}

// "2026.4.1" of the build number "2026.4.1-22982-e213a147257-releases/2026/4".
std::string version() {
  const std::string build = ov::get_openvino_version().buildNumber;
  return build.substr(0, build.find('-'));
}

std::string shapeText(const ShapeKey& s) {
  std::string t = "{";
  for (size_t i = 0; i < s.size(); ++i) t += (i ? ", " : "") + std::to_string(s[i]);
  return t + "}";
}

// Throws unless `device` is one OpenVINO has here (or a virtual device built on them).
void checkDevice(const std::string& device) {
  const std::vector<std::string> devices = core().get_available_devices();
  const std::string base = device.substr(0, device.find_first_of(".:("));
  for (const char* virt : {"AUTO", "HETERO", "MULTI", "BATCH"})
    if (base == virt) return;
  for (const auto& d : devices)
    if (d == device || d.substr(0, d.find('.')) == device) return;
  std::string list;
  for (const auto& d : devices) list += (list.empty() ? "" : ", ") + d;
  throw Error("OpenVINO device \"" + device + "\" is not available here; the devices there are: " +
              (list.empty() ? "none" : list) + " (and AUTO, HETERO, MULTI, BATCH built on them)");
}

// The 4-D outputs of `model` (reshaped to its input) whose planes lie a multiple of 4 KiB apart:
// handed over channels-last (NHWC) instead of NCHW. Why: the CPU plugin computes them in NHWC
// and, for an NCHW output, ends the graph with a reorder of its own that is slow where the planes
// lie a multiple of 4 KiB apart (its 34 or 24 write streams then share cache sets): on a 144x192
// grid (768x576) it took 3.5 of the TFF network's 10.0 ms and 2.4 of MoveNet's 31.5 ms
// (PERF_COUNT, 2 threads); the TFF network there 4.3 ms against 5.4 NCHW (jointflow-bench,
// 4 runs each). wait() transposes them itself, tile by tile (toPlanar). Elsewhere the plugin's
// reorder, on its own threads, wins: on a 120x160 grid (640x480, planes 75 KiB apart) MoveNet's
// forward pass took 24.0 ms against 25.9 and the element 25.8 against 27.0 (jointflow-bench
// --child-e2e max:640, medians of 4 runs each).
std::vector<std::string> aliasedOutputs(const ov::Model& model) {
  constexpr size_t kPage = 4096;
  std::vector<std::string> names;
  for (const auto& o : model.outputs()) {
    const ov::PartialShape& shape = o.get_partial_shape();
    if (!shape.rank().is_static() || shape.rank().get_length() != 4) continue;
    // An output of unknown size (never, once reshaped): channels-last, as the largest grids are.
    const bool known = shape[2].is_static() && shape[3].is_static();
    const size_t plane =
        known ? static_cast<size_t>(shape[2].get_length() * shape[3].get_length()) * sizeof(float)
              : 0;
    if (plane % kPage == 0) names.push_back(o.get_any_name());
  }
  return names;
}

// `model` with the outputs `names` handed over channels-last and, for an image key, its input
// taken as the 8-bit interleaved image itself: the conversion to float, the channel order, mean,
// scale and the transpose to NCHW run in the graph, where the CPU plugin folds them into the
// first layer's input reorder on its own threads. Why: cv::dnn::blobFromImage on the element's
// thread took 0.66 ms a frame at 640x480 (into a reused blob; 4.1 ms into a fresh one) against
// the 24-30 ms forward pass, on the two cores the network fills.
std::shared_ptr<ov::Model> withLayouts(std::shared_ptr<ov::Model> model,
                                       const std::vector<std::string>& names, const InputKey& key) {
  if (names.empty() && !key.image) return model;
  ov::preprocess::PrePostProcessor ppp(model);
  if (key.image) {
    using ov::preprocess::ColorFormat;
    ppp.input()
        .tensor()
        .set_element_type(ov::element::u8)
        .set_layout("NHWC")
        .set_color_format(key.how.bgr ? ColorFormat::BGR : ColorFormat::RGB);
    ppp.input().model().set_layout("NCHW");
    auto& steps = ppp.input().preprocess();
    steps.convert_element_type(ov::element::f32);
    if (key.how.bgr) steps.convert_color(ColorFormat::RGB);
    if (key.how.mean != 0.0) steps.mean(static_cast<float>(key.how.mean));
    if (key.how.scale != 1.0) steps.scale(static_cast<float>(1.0 / key.how.scale));
  }
  for (const std::string& name : names) {
    ppp.output(name).model().set_layout("NCHW");
    ppp.output(name).tensor().set_layout("NHWC");
  }
  return ppp.build();
}

// dst[n][c][p] = src[n][p][c] for p < pixels: channels-last -> planar. Tiles of kTile pixels keep
// the source rows in L1 and write whole cache lines of each plane. One thread: the copy is
// memory-bound (MoveNet at 768x576, 114 planes, 12.6 MB a frame: median 1.85 ms); the tiles on
// OpenCV's 2 threads took 1.92 ms, and OpenCV's 4x4 SIMD transposes gained 10-30 % alone.
void toPlanar(const float* src, float* dst, size_t batches, size_t pixels, size_t channels) {
  constexpr size_t kTile = 64;
  for (size_t n = 0; n < batches; ++n, src += pixels * channels, dst += pixels * channels) {
    for (size_t p0 = 0; p0 < pixels; p0 += kTile) {
      const size_t p1 = std::min(pixels, p0 + kTile);
      for (size_t c = 0; c < channels; ++c) {
        float* out = dst + c * pixels;
        for (size_t p = p0; p < p1; ++p) out[p] = src[p * channels + c];
      }
    }
  }
}

struct Config {
  std::string device;
  int threads = 0;
  int streams = 0;
  std::string precision;

  bool operator==(const Config& o) const {
    return device == o.device && threads == o.threads && streams == o.streams &&
           precision == o.precision;
  }
  std::string text() const {
    return "device " + device + ", " + std::to_string(threads) + " threads, " +
           std::to_string(streams) + " streams, precision " +
           (precision.empty() ? "default" : precision) + " (0 = OpenVINO's choice)";
  }
  ov::AnyMap properties() const {
    ov::AnyMap p;
    // Latency: one request at a time runs as fast as it can; explicit streams override it.
    p.emplace(ov::hint::performance_mode(ov::hint::PerformanceMode::LATENCY));
    if (threads > 0) p.emplace(ov::inference_num_threads(threads));
    if (streams > 0) p.emplace(ov::num_streams(streams));
    if (!precision.empty()) p.emplace(ov::hint::inference_precision(ov::element::Type(precision)));
    return p;
  }
};

/// A model compiled for one input, and its outputs handed over channels-last (aliasedOutputs).
struct CompiledInput {
  ov::CompiledModel model;
  std::vector<std::string> channels_last;
  bool channelsLast(const std::string& name) const {
    return std::find(channels_last.begin(), channels_last.end(), name) != channels_last.end();
  }
};

class SharedModel {
 public:
  SharedModel(const std::string& path, Config config) : path_(path), config_(std::move(config)) {
    if (!std::filesystem::is_regular_file(path))
      throw Error("model file " + path + " does not exist or is not a file");
    checkDevice(config_.device);
    try {
      model_ = core().read_model(path);
    } catch (const std::exception& e) {
      throw Error("model file " + path + " is not a model that OpenVINO " + version() +
                  " can read (truncated or corrupt?): " + e.what());
    }
    if (model_->inputs().size() != 1)
      throw Error("model file " + path + " has " + std::to_string(model_->inputs().size()) +
                  " inputs; JointFlow's networks take one");
    const ov::PartialShape in = model_->input().get_partial_shape();
    if (in.rank().is_static() && in.rank().get_length() == 4 && in[1].is_static())
      input_channels_ = static_cast<int>(in[1].get_length());
    for (const auto& o : model_->outputs()) outputs_.push_back(o.get_any_name());
  }

  const std::string& path() const { return path_; }
  const Config& config() const { return config_; }
  const std::vector<std::string>& outputs() const { return outputs_; }
  int inputChannels() const { return input_channels_; }
  /// The precision the device computes in (known after the first compile).
  std::string precision() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return precision_;
  }

  /// The model compiled for one input: compiled on first use, then kept.
  CompiledInput compiled(const InputKey& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = cache_.begin(); it != cache_.end(); ++it) {
      if (it->first == key) {
        cache_.splice(cache_.begin(), cache_, it);  // most recently used first
        return cache_.front().second;
      }
    }
    CompiledInput compiled;
    try {
      std::shared_ptr<ov::Model> model = model_->clone();
      model->reshape(ov::PartialShape(ov::Shape(key.shape)));
      compiled.channels_last = aliasedOutputs(*model);
      compiled.model = core().compile_model(withLayouts(model, compiled.channels_last, key),
                                            config_.device, config_.properties());
    } catch (const std::exception& e) {
      throw Error("model file " + path_ + ": OpenVINO " + version() + " cannot compile it for " +
                  config_.device + " with input " + shapeText(key.shape) +
                  (key.image ? " (from an 8-bit image)" : "") + ": " + e.what());
    }
    if (precision_.empty()) {
      try {
        precision_ = compiled.model.get_property(ov::hint::inference_precision).get_type_name();
      } catch (const std::exception&) {
        precision_ = "?";  // a device that does not tell
      }
    }
    cache_.emplace_front(key, compiled);
    // A request keeps its compiled model alive, so dropping one here never pulls it from under
    // a stream.
    if (cache_.size() > kMaxShapes) cache_.pop_back();
    return compiled;
  }

 private:
  std::string path_;
  Config config_;
  std::shared_ptr<ov::Model> model_;
  std::vector<std::string> outputs_;
  int input_channels_ = -1;
  mutable std::mutex mutex_;
  std::list<std::pair<InputKey, CompiledInput>> cache_;
  std::string precision_;
};

// The named instances of the process (model-instance-id): the id and the file pick one.
std::shared_ptr<SharedModel> sharedModel(const std::string& path, const EngineOptions& dnn) {
  Config config{dnn.device.empty() ? "CPU" : dnn.device, dnn.num_threads, dnn.num_streams,
                dnn.precision};
  if (dnn.model_instance_id.empty()) return std::make_shared<SharedModel>(path, config);
  static std::mutex mutex;
  static std::map<std::pair<std::string, std::string>, std::weak_ptr<SharedModel>> instances;
  std::error_code ec;
  const std::string key_path = std::filesystem::weakly_canonical(path, ec).string();
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = instances[{dnn.model_instance_id, ec ? path : key_path}];
  if (std::shared_ptr<SharedModel> shared = slot.lock()) {
    if (!(shared->config() == config))
      throw Error("model-instance-id \"" + dnn.model_instance_id + "\" runs " + path + " with " +
                  shared->config().text() + "; this instance asks for " + config.text() +
                  ": give it the same settings or another id");
    return shared;
  }
  auto shared = std::make_shared<SharedModel>(path, config);
  slot = shared;
  return shared;
}

class OpenVinoNetwork : public Network {
 public:
  explicit OpenVinoNetwork(std::shared_ptr<SharedModel> model) : model_(std::move(model)) {}

  ~OpenVinoNetwork() override {
    // Never leave a run going on memory this object owns (the input images).
    for (Run& run : runs_) {
      try {
        run.request->wait();
      } catch (...) {
      }
    }
  }

  std::vector<std::string> outputNames() const override { return model_->outputs(); }
  int inputChannels() const override { return model_->inputChannels(); }

  void setInput(const cv::Mat& blob) override {
    if (blob.type() != CV_32F || blob.dims < 2)
      throw Error("model file " + model_->path() + ": the input must be a float32 NCHW blob");
    InputKey key;
    for (int i = 0; i < blob.dims; ++i) key.shape.push_back(static_cast<size_t>(blob.size[i]));
    bind(key, blob, ov::element::f32, ov::Shape(key.shape));
  }

  void setImage(const cv::Mat& image, const ImageInput& how) override {
    if (image.depth() != CV_8U || image.dims != 2)
      throw Error("model file " + model_->path() + ": the input image must be 8-bit, 2-D");
    const size_t h = image.rows, w = image.cols, c = image.channels();
    bind({{1, c, h, w}, true, how}, image, ov::element::u8, {1, h, w, c});
  }

  void start() override {
    if (!bound_) throw Error("model file " + model_->path() + ": start() before setInput()");
    try {
      bound_->request->start_async();
    } catch (const std::exception& e) {
      throw Error("model file " + model_->path() + ": OpenVINO could not start a run: " + e.what());
    }
    runs_.push_back(std::move(*bound_));
    bound_.reset();
  }

  std::vector<cv::Mat> wait(const std::vector<std::string>& names) override {
    if (runs_.empty()) throw Error("model file " + model_->path() + ": wait() without start()");
    const Run run = std::move(runs_.front());  // holds the input until the run has ended
    runs_.pop_front();
    ov::InferRequest& request = *run.request;
    try {
      request.wait();
    } catch (const std::exception& e) {
      throw Error("model file " + model_->path() + ": OpenVINO run failed: " + e.what());
    }
    std::vector<cv::Mat> out;
    for (const auto& name : names) {
      auto given = std::find_if(run.outputs.begin(), run.outputs.end(),
                                [&](const auto& o) { return o.first == name; });
      if (given != run.outputs.end()) {
        out.push_back(given->second);  // written in place (giveOutputs)
        continue;
      }
      ov::Tensor t;
      try {
        t = request.get_tensor(name);
      } catch (const std::exception&) {
        throw Error("model file " + model_->path() + " has no output " + name);
      }
      if (t.get_element_type() != ov::element::f32)
        throw Error("model file " + model_->path() + ": output " + name + " is " +
                    t.get_element_type().get_type_name() + ", expected f32");
      const ov::Shape shape = t.get_shape();
      const float* data = t.data<const float>();
      if (shape.size() == 4 && run.compiled->input.channelsLast(name)) {
        cv::Mat m =
            outputs_.take({int(shape[0]), int(shape[3]), int(shape[1]), int(shape[2])}, CV_32F);
        toPlanar(data, m.ptr<float>(), shape[0], shape[1] * shape[2], shape[3]);
        out.push_back(m);
        continue;
      }
      std::vector<int> dims;
      for (size_t d : shape) dims.push_back(static_cast<int>(d));
      cv::Mat m = outputs_.take(dims, CV_32F);
      std::memcpy(m.data, data, t.get_byte_size());
      out.push_back(m);
    }
    return out;
  }

  bool asynchronous() const override { return true; }
  int maxRuns() const override { return kMaxRuns; }
  const void* sharedModel() const override { return model_.get(); }
  std::string engineName() const override {
    const std::string precision = model_->precision();
    return "OpenVINO " + version() + " " + model_->config().device +
           (precision.empty() ? "" : " " + precision);
  }

 private:
  // A compiled input (InputKey) and its infer requests: one per run in flight (at most kMaxRuns),
  // made as they are first needed. A list, so that a request stays where a Run points to it.
  struct Compiled {
    CompiledInput input;
    std::list<ov::InferRequest> requests;
  };
  // A run (bound, or started and not yet waited for), and the input it reads (kept alive until it
  // ends).
  struct Run {
    ov::InferRequest* request;
    const Compiled* compiled;  ///< not dropped while a run of it is in flight (compiledFor)
    cv::Mat input;
    std::vector<std::pair<std::string, cv::Mat>> outputs;  ///< written in place (giveOutputs)
  };
  bool inFlight(const ov::InferRequest& request) const {
    return std::any_of(runs_.begin(), runs_.end(),
                       [&](const Run& r) { return r.request == &request; });
  }
  bool inFlight(const Compiled& compiled) const {
    return std::any_of(runs_.begin(), runs_.end(),
                       [&](const Run& r) { return r.compiled == &compiled; });
  }

  // A free request compiled for `key` takes `input` as its tensor of `type` and `shape`: the
  // tensor wraps the memory (no copy), and the Run keeps it alive until the run ends.
  void bind(const InputKey& key, const cv::Mat& input, ov::element::Type type,
            const ov::Shape& shape) {
    if (runs_.size() >= static_cast<size_t>(kMaxRuns))
      throw Error("model file " + model_->path() + ": a new input while " +
                  std::to_string(runs_.size()) + " runs are in flight");
    bound_.reset();  // compiledFor may drop the compiled input a bound run was made for
    Compiled& compiled = compiledFor(key);
    auto free = std::find_if(compiled.requests.begin(), compiled.requests.end(),
                             [&](const ov::InferRequest& r) { return !inFlight(r); });
    if (free == compiled.requests.end()) {
      try {
        free = compiled.requests.insert(free, compiled.input.model.create_infer_request());
      } catch (const std::exception& e) {
        throw Error("model file " + model_->path() +
                    ": OpenVINO could not make an infer request: " + e.what());
      }
    }
    Run run{&*free, &compiled, input.isContinuous() ? input : input.clone(), {}};
    run.request->set_input_tensor(ov::Tensor(type, shape, run.input.data));
    giveOutputs(run);
    bound_ = std::move(run);
  }

  // The run's NCHW float outputs are written straight into buffers of the pool, which wait()
  // hands out as they are (the channels-last ones are transposed there instead). Why: copying
  // MoveNet's maps out of OpenVINO's own tensors at max:640 (8.7 MB a frame) took the bare
  // forward pass from 24.5-25.7 to 26.7-27.4 ms (3 paired jointflow-bench --child-e2e max:640
  // runs), and 4 streams on one model held 272 MiB against 240 with it gone. A buffer the run
  // writes is held by the Run until wait() hands it over, so the pool never gives it out twice.
  void giveOutputs(Run& run) {
    for (const auto& o : run.compiled->input.model.outputs()) {
      const std::string& name = o.get_any_name();
      if (run.compiled->input.channelsLast(name) || o.get_element_type() != ov::element::f32 ||
          o.get_partial_shape().is_dynamic() || o.get_partial_shape().rank().get_length() == 0)
        continue;
      const ov::Shape shape = o.get_shape();
      std::vector<int> dims(shape.begin(), shape.end());
      cv::Mat m = outputs_.take(dims, CV_32F);
      try {
        run.request->set_tensor(o, ov::Tensor(ov::element::f32, shape, m.data));
      } catch (const std::exception& e) {
        throw Error("model file " + model_->path() +
                    ": OpenVINO did not take an output buffer for " + name + ": " + e.what());
      }
      run.outputs.emplace_back(name, m);
    }
  }

  Compiled& compiledFor(const InputKey& key) {
    for (auto it = compiled_.begin(); it != compiled_.end(); ++it) {
      if (it->first == key) {
        compiled_.splice(compiled_.begin(), compiled_, it);  // most recently used first
        return compiled_.front().second;
      }
    }
    compiled_.emplace_front(key, Compiled{model_->compiled(key), {}});
    // The least recently used inputs go, but never one with a run in flight.
    for (auto it = compiled_.end(); compiled_.size() > kMaxShapes && it != compiled_.begin();) {
      --it;
      if (!inFlight(it->second)) it = compiled_.erase(it);
    }
    return compiled_.front().second;
  }

  std::shared_ptr<SharedModel> model_;
  std::list<std::pair<InputKey, Compiled>> compiled_;
  std::optional<Run> bound_;  ///< set by setInput()/setImage(), started by start()
  std::deque<Run> runs_;      ///< in flight, oldest first
  MatPool outputs_;           ///< the outputs handed out, reused once their holders let go
};

}  // namespace
}  // namespace jointflow::detail

// The module's entry point (openvino_module.hpp).
extern "C" __attribute__((visibility("default"))) jointflow::detail::Network*
jointflow_openvino_open(const std::string& path, const jointflow::EngineOptions& dnn) {
  using namespace jointflow;
  if (dnn.target != DnnTarget::kCpu)
    throw Error(std::string("dnn target \"") + toString(dnn.target) +
                "\" is cv::dnn's; with backend openvino the OpenVINO device is chosen with the "
                "device setting (e.g. CPU, GPU, AUTO)");
  if (!dnn.precision.empty() && dnn.precision != "f32" && dnn.precision != "bf16" &&
      dnn.precision != "f16")
    throw Error("OpenVINO precision \"" + dnn.precision +
                "\" is not one of: (empty = the device's default), f32, bf16, f16");
  if (dnn.num_threads < 0 || dnn.num_streams < 0)
    throw Error("OpenVINO threads and streams must be >= 0 (0 = OpenVINO's choice)");
  return new detail::OpenVinoNetwork(detail::sharedModel(path, dnn));
}
