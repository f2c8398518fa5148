// The Tracker facade: SpatialModel -> TemporalFlowModel (similarity "tff") -> PoseAssociator.
#include "jointflow/tracker.hpp"

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
  if (image.empty()) throw Error("Tracker::process: the image is empty");
  if (image.type() != CV_8UC3)
    throw Error("Tracker::process: expected an 8-bit 3-channel image, got type " +
                std::to_string(image.type()) + " with " + std::to_string(image.channels()) +
                " channels");
  const SpatialResult result = impl_->spatial->estimate(image, order);
  const cv::Mat tff = impl_->tff ? impl_->tff->predict(result.features, result.beliefs) : cv::Mat();
  // The grey frame serves the "flow" similarity and the camera motion of coasting tracks.
  cv::Mat grey;
  if (impl_->settings.similarity == SimilarityType::kFlow ||
      (impl_->settings.camera_compensation && impl_->settings.coast_frames > 0))
    cv::cvtColor(image, grey, order == PixelOrder::kBGR ? cv::COLOR_BGR2GRAY : cv::COLOR_RGB2GRAY);
  return impl_->associator.update(result, tff, grey);
}

void Tracker::reset() {
  impl_->associator.reset();
  if (impl_->tff) impl_->tff->reset();
}

const TrackerSettings& Tracker::settings() const {
  return impl_->settings;
}

}  // namespace jointflow
