// PoseNet MobileNetV1 behind the SpatialModel interface (tensor names: models/README.md).
#include <cmath>

#include "jointflow/posenet_decoder.hpp"
#include "spatial_models.hpp"
#include "tensor.hpp"

namespace jointflow::detail {
namespace {

std::vector<DisplacementChannels> blockYX(int n) {
  std::vector<DisplacementChannels> d;
  for (int j = 0; j < n; ++j) d.push_back({n + j, j});  // 0..n-1 = dy, n..2n-1 = dx
  return d;
}

NetSpec poseNetSpec() {
  NetSpec s;
  s.type = ModelType::kPoseNet;
  s.what = "PoseNet MobileNetV1";
  s.heads = {{"heatmaps", {}},
             {"offsets", blockYX(kNumJoints)},
             {"displacement_fwd", blockYX(16)},
             {"displacement_bwd", blockYX(16)}};
  s.features = "features";
  s.rule = {16, 1};  // 16k + 1, so that cell i is input pixel 16 i
  s.input_scale = 1.0 / 127.5;
  s.input_mean = 127.5;  // RGB to [-1, 1]
  s.stride = 16.f;
  s.grid_of_input = [](int n) { return (n - 1) / 16 + 1; };
  return s;
}

class PoseNetModel : public NetSpatialModel {
 public:
  PoseNetModel(const SpatialOptions& o, const EngineOptions& engine)
      : NetSpatialModel(poseNetSpec(), o, engine) {}

 protected:
  // Scales are averaged as probabilities, not logits.
  void prepare(Tensors& t) const override {
    cv::Mat& h = t.at("heatmaps");  // continuous: a private copy of the net's output
    float* p = h.ptr<float>();
    for (size_t i = 0; i < h.total(); ++i) p[i] = 1.f / (1.f + std::exp(-p[i]));
  }
  Poses decode(const Tensors& t, float stride) const override {
    PoseNetHeads heads{t.at("heatmaps"), t.at("offsets"), t.at("displacement_fwd"),
                       t.at("displacement_bwd")};
    PoseNetDecodeOptions o;
    o.stride = stride;
    o.max_persons = options_.max_persons;
    o.part_threshold = options_.part_threshold;
    o.nms_radius = options_.nms_radius;
    return decodePoseNet(heads, o);
  }
  cv::Mat beliefs(const Tensors& t) const override { return t.at("heatmaps"); }
};

}  // namespace

std::unique_ptr<SpatialModel> createPoseNet(const SpatialOptions& options,
                                            const EngineOptions& engine) {
  return std::make_unique<PoseNetModel>(options, engine);
}

}  // namespace jointflow::detail
