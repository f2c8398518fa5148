// The Tracker facade: SpatialModel -> TemporalFlowModel (similarity "tff") -> PoseAssociator.
#include "jointflow/tracker.hpp"

#include <deque>
#include <filesystem>

#include <opencv2/imgproc.hpp>

#include "jointflow/error.hpp"
#include "jointflow/model_files.hpp"
#include "jointflow/pose_associator.hpp"
#include "jointflow/tff_model.hpp"

namespace jointflow {

struct Tracker::Impl {
  // What a submitted frame needs for its association besides the spatial network's result.
  struct Pending {
    cv::Mat grey;  ///< "flow" similarity and camera motion
    cv::Mat bgr;   ///< colour re-identification
    double time;   ///< stream time, seconds
  };

  TrackerSettings settings;
  PoseAssociator associator;
  std::unique_ptr<SpatialModel> spatial;
  std::unique_ptr<TemporalFlowModel> tff;
  std::deque<Pending> pending;  ///< submitted frames, oldest first

  explicit Impl(const TrackerSettings& s) : settings(s), associator(s) {}

  // The grey and colour frames are made at submit(): on an asynchronous engine while the network
  // runs. The colour frame is a copy there, since the caller's buffer may be gone at collect().
  Pending prepare(const cv::Mat& image, PixelOrder order, double time, bool copy) const {
    Pending p{{}, {}, time};
    const FrameNeeds needs = associator.frameNeeds();
    if (needs.grey)
      cv::cvtColor(image, p.grey,
                   order == PixelOrder::kBGR ? cv::COLOR_BGR2GRAY : cv::COLOR_RGB2GRAY);
    if (needs.bgr) {
      if (order == PixelOrder::kRGB)
        cv::cvtColor(image, p.bgr, cv::COLOR_RGB2BGR);
      else
        p.bgr = copy ? image.clone() : image;
    }
    return p;
  }

  // One frame after the spatial network, in the order of pose_associator.hpp's steps: the camera
  // motion (step 2), then the TFF on the previous maps moved by it, then the association with
  // both. The camera motion comes from the associator, since its fit leaves out the tracks' boxes.
  std::vector<TrackedPose> associate(const SpatialResult& result, const Pending& frame) {
    AssociationFrame in;
    in.poses = result.poses;
    in.grid_to_frame = result.grid_to_frame;
    in.features = result.features;
    in.grey = frame.grey;
    in.bgr = frame.bgr;
    in.time = frame.time;
    in.motion = associator.estimateMotion(in);
    if (tff) {
      if (in.motion->tff) {
        in.tff = tff->predict(result.features, result.beliefs,
                              cameraMotionOnGrid(in.motion->camera, result.grid_to_frame));
        in.tff_camera_compensated = true;
      } else {
        // "auto" between close frames: no field, but the next frame's TFF needs these maps.
        tff->remember(result.features, result.beliefs);
      }
    }
    return associator.update(in);
  }
};

Tracker::Tracker(const TrackerSettings& settings) {
  // Every setting is checked first (the associator checks its part alone): they fail fast,
  // before any model is loaded.
  validateTrackerSettings(settings);
  auto impl = std::make_unique<Impl>(settings);
  impl->spatial = createSpatialModel(settings.model_type, settings.spatial, settings.engine);
  const bool tff = settings.similarity == SimilarityType::kTff;
  const bool auto_tff = settings.similarity == SimilarityType::kAuto;
  const std::string spatial_type = toString(impl->spatial->type());
  const std::string shipped = "tff_" + spatial_type + ".onnx";
  const std::string path =
      settings.tff_model.empty() ? findShippedModel(shipped) : settings.tff_model;
  // "auto" without a shipped TFF network for the spatial model (PoseNet), or with one that does
  // not fit it (a MoveNet of other feature channels), is oks on every frame (hasTff() says so):
  // the user did not ask for the network. A TFF file named in the settings must load either way.
  // A spatial model without maps (YOLO pose) gives the TFF network nothing to read, whatever file.
  if (impl->spatial->featureChannels() == 0 && (tff || (auto_tff && !settings.tff_model.empty())))
    throw Error(std::string("similarity \"") + toString(settings.similarity) +
                "\" with a TFF model needs the spatial model's feature and belief maps, and the " +
                spatial_type +
                " spatial model has none (it gives poses only): choose the similarity auto "
                "(oks with this model), oks, iou, pckh or flow");
  const bool have_tff = !path.empty() && std::filesystem::is_regular_file(path);
  auto load = [&] {
    return std::make_unique<TemporalFlowModel>(path, impl->spatial->featureChannels(),
                                               settings.engine);
  };
  if (tff || (auto_tff && !settings.tff_model.empty())) {
    if (!have_tff)
      throw Error(std::string("similarity \"") + toString(settings.similarity) +
                  "\" needs a TFF model for the " + spatial_type + " spatial model, but " +
                  (path.empty() ? shippedModelMissing(shipped) : path + " does not exist") +
                  ": set TrackerSettings::tff_model to one (training/ makes it), "
                  "or choose the similarity oks, iou, pckh or flow");
    impl->tff = load();
  } else if (auto_tff && have_tff) {
    try {
      impl->tff = load();
    } catch (const Error&) {  // oks on every frame
    }
  }
  impl_ = std::move(impl);
}

Tracker::~Tracker() = default;
Tracker::Tracker(Tracker&&) noexcept = default;
Tracker& Tracker::operator=(Tracker&&) noexcept = default;

namespace {

void checkImage(const cv::Mat& image) {
  if (image.empty()) throw Error("Tracker::process: the image is empty");
  if (image.type() != CV_8UC3)
    throw Error("Tracker::process: expected an 8-bit 3-channel image, got type " +
                std::to_string(image.type()) + " with " + std::to_string(image.channels()) +
                " channels");
}

}  // namespace

std::vector<TrackedPose> Tracker::process(const cv::Mat& image, PixelOrder order,
                                          double timestamp) {
  if (pending() > 0) throw Error("Tracker::process: frames are pending; collect() them first");
  submit(image, order, timestamp);
  return collect();
}

std::vector<TrackedPose> Tracker::process(const SpatialResult& result, const cv::Mat& image,
                                          PixelOrder order, double timestamp) {
  checkImage(image);
  if (result.frame_size != image.size())
    throw Error("Tracker::process: the spatial result is of a " +
                std::to_string(result.frame_size.width) + "x" +
                std::to_string(result.frame_size.height) + " frame, the image is " +
                std::to_string(image.cols) + "x" + std::to_string(image.rows));
  if (pending() > 0) throw Error("Tracker::process: frames are pending; collect() them first");
  return impl_->associate(result, impl_->prepare(image, order, timestamp, false));
}

void Tracker::submit(const cv::Mat& image, PixelOrder order, double timestamp) {
  checkImage(image);
  impl_->spatial->submit(image, order);
  impl_->pending.push_back(impl_->prepare(image, order, timestamp, asynchronous()));
}

std::vector<TrackedPose> Tracker::collect() {
  if (impl_->pending.empty()) throw Error("Tracker::collect: no frame was submitted");
  const Impl::Pending frame = std::move(impl_->pending.front());
  impl_->pending.pop_front();
  return impl_->associate(impl_->spatial->collect(), frame);
}

bool Tracker::hasTff() const {
  return impl_->tff != nullptr;
}

std::vector<TrackedPose> Tracker::predict(double timestamp) const {
  return impl_->associator.predict(timestamp);
}

TrackCounts Tracker::trackCounts() const {
  return impl_->associator.trackCounts();
}

int Tracker::timeFallbacks() const {
  return impl_->associator.timeFallbacks();
}

const SpatialModel& Tracker::spatialModel() const {
  return *impl_->spatial;
}

std::string Tracker::tffModelPath() const {
  return impl_->tff ? impl_->tff->path() : std::string();
}

int Tracker::pending() const {
  return static_cast<int>(impl_->pending.size());
}

bool Tracker::asynchronous() const {
  return impl_->spatial->asynchronous();
}

std::string Tracker::engine() const {
  return impl_->spatial->engine();
}

void Tracker::reset() {
  while (!impl_->pending.empty()) {
    impl_->pending.pop_front();
    try {
      impl_->spatial->collect();  // waits for the engine; the result belongs to the old scene
    } catch (const std::exception&) {
    }
  }
  impl_->associator.reset();
  if (impl_->tff) impl_->tff->reset();
}

const TrackerSettings& Tracker::settings() const {
  return impl_->settings;
}

}  // namespace jointflow
