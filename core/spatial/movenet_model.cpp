// MoveNet MultiPose behind the SpatialModel interface (tensor names: models/README.md).
#include "jointflow/movenet_decoder.hpp"
#include "spatial_models.hpp"
#include "tensor.hpp"

namespace jointflow::detail {
namespace {

std::vector<DisplacementChannels> interleavedYX(int pairs) {
  std::vector<DisplacementChannels> d;
  for (int j = 0; j < pairs; ++j) d.push_back({2 * j + 1, 2 * j});  // 2j = dy, 2j+1 = dx
  return d;
}

NetSpec moveNetSpec() {
  NetSpec s;
  s.type = ModelType::kMoveNet;
  s.what = "MoveNet MultiPose";
  s.heads = {{"center", {}},
             {"heatmaps", {}},
             {"regression", interleavedYX(kNumJoints)},
             {"offsets", interleavedYX(kNumJoints)},
             {"box_scale", {{1, 0}}},  // (h, w): sizes scale like displacements
             {"box_offset", {{1, 0}}}};
  s.features = "features";
  s.rule = {32, 0};
  s.input_scale = 1.0;  // RGB 0..255, normalised inside the graph
  s.stride = 4.f;
  s.grid_of_input = [](int n) { return n / 4; };
  return s;
}

class MoveNetModel : public NetSpatialModel {
 public:
  MoveNetModel(const SpatialOptions& o, const EngineOptions& engine)
      : NetSpatialModel(moveNetSpec(), o, engine) {}

 protected:
  Poses decode(const Tensors& t, float) const override {
    MoveNetHeads heads{t.at("center"),  t.at("heatmaps"),  t.at("regression"),
                       t.at("offsets"), t.at("box_scale"), t.at("box_offset")};
    MoveNetDecodeOptions o;
    o.max_persons = options_.max_persons;
    o.min_centre_score = options_.person_threshold;
    return decodeMoveNet(heads, o);
  }
  cv::Mat beliefs(const Tensors& t) const override { return t.at("heatmaps"); }
};

}  // namespace

std::unique_ptr<SpatialModel> createMoveNet(const SpatialOptions& options,
                                            const EngineOptions& engine) {
  return std::make_unique<MoveNetModel>(options, engine);
}

}  // namespace jointflow::detail
