// The Tracker facade: SpatialModel -> TemporalFlowModel (similarity "tff") -> PoseAssociator.
#include "jointflow/tracker.hpp"

#include <deque>
#include <filesystem>

#include <opencv2/imgproc.hpp>

#include "jointflow/error.hpp"
#include "jointflow/pose_associator.hpp"
#include "jointflow/tff_model.hpp"

namespace jointflow {

struct Tracker::Impl {
  TrackerSettings settings;
  PoseAssociator associator;
  std::unique_ptr<SpatialModel> spatial;
  std::unique_ptr<TemporalFlowModel> tff;
  std::deque<cv::Mat> greys;  ///< of the pending frames, oldest first

  bool needsGrey() const {
    return settings.similarity == SimilarityType::kFlow ||
           (settings.camera_compensation && settings.coast_frames > 0);
  }

  explicit Impl(const TrackerSettings& s) : settings(s), associator(s) {}
};

Tracker::Tracker(const TrackerSettings& settings) {
  // The association settings are checked first: they fail fast, before any model is loaded.
  auto impl = std::make_unique<Impl>(settings);
  impl->spatial = createSpatialModel(settings.model_type, settings.spatial);
  if (settings.similarity == SimilarityType::kTff) {
    const std::string spatial_type = toString(impl->spatial->type());
    const std::string path =
        settings.tff_model.empty()
            ? (std::filesystem::path(defaultModelsDir()) / ("tff_" + spatial_type + ".onnx"))
                  .string()
            : settings.tff_model;
    if (!std::filesystem::is_regular_file(path))
      throw Error("similarity \"tff\" needs a TFF model for the " + spatial_type +
                  " spatial model, but " + path +
                  " does not exist: set TrackerSettings::tff_model to one (training/ makes it), "
                  "or choose the similarity oks, iou, pckh or flow");
    impl->tff = std::make_unique<TemporalFlowModel>(path, impl->spatial->featureChannels(),
                                                    settings.spatial.dnn);
  }
  impl_ = std::move(impl);
}

Tracker::~Tracker() = default;
Tracker::Tracker(Tracker&&) noexcept = default;
Tracker& Tracker::operator=(Tracker&&) noexcept = default;

std::vector<TrackedPose> Tracker::process(const cv::Mat& image, PixelOrder order) {
  if (pending() > 0) throw Error("Tracker::process: frames are pending; collect() them first");
  submit(image, order);
  return collect();
}

void Tracker::submit(const cv::Mat& image, PixelOrder order) {
  if (image.empty()) throw Error("Tracker::process: the image is empty");
  if (image.type() != CV_8UC3)
    throw Error("Tracker::process: expected an 8-bit 3-channel image, got type " +
                std::to_string(image.type()) + " with " + std::to_string(image.channels()) +
                " channels");
  impl_->spatial->submit(image, order);
  // The grey frame serves the "flow" similarity and the camera motion of coasting tracks; on an
  // asynchronous engine it is made while the network runs.
  cv::Mat grey;
  if (impl_->needsGrey())
    cv::cvtColor(image, grey, order == PixelOrder::kBGR ? cv::COLOR_BGR2GRAY : cv::COLOR_RGB2GRAY);
  impl_->greys.push_back(grey);
}

std::vector<TrackedPose> Tracker::collect() {
  if (impl_->greys.empty()) throw Error("Tracker::collect: no frame was submitted");
  const cv::Mat grey = impl_->greys.front();
  impl_->greys.pop_front();
  const SpatialResult result = impl_->spatial->collect();
  const cv::Mat tff = impl_->tff ? impl_->tff->predict(result.features, result.beliefs) : cv::Mat();
  return impl_->associator.update(result, tff, grey);
}

int Tracker::pending() const {
  return static_cast<int>(impl_->greys.size());
}

bool Tracker::asynchronous() const {
  return impl_->spatial->asynchronous();
}

std::string Tracker::engine() const {
  return impl_->spatial->engine();
}

void Tracker::reset() {
  while (!impl_->greys.empty()) {
    impl_->greys.pop_front();
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
