// Any ONNX model with joint belief maps and Part Affinity Fields behind the SpatialModel
// interface, decoded by the paper's OpenPose-style decoder.
//
// Model contract: one input [1, 3, H, W], RGB 0..255 (the model normalises inside its graph),
// H and W multiples of 8; outputs `beliefs` [1, J >= 17, H/s, W/s] (COCO order first) and `pafs`
// [1, 2L, H/s, W/s] in the layout of openpose_decoder.hpp; optional `features` on the same grid
// (without it, the PAFs serve as the feature map). The stride s is input height / grid height.
#include <algorithm>

#include "../engine/network.hpp"
#include "jointflow/openpose_decoder.hpp"
#include "spatial_models.hpp"
#include "tensor.hpp"

namespace jointflow::detail {
namespace {

NetSpec openPoseSpec(bool has_features) {
  NetSpec s;
  s.type = ModelType::kOpenPose;
  s.what = "OpenPose-style (beliefs + pafs)";
  s.heads = {{"beliefs", {}}, {"pafs", {}}};  // PAFs are unit vectors: never rescaled
  s.features = has_features ? "features" : "pafs";
  s.rule = {8, 0};
  s.stride = 0.f;  // inferred
  return s;
}

class OpenPoseModel : public NetSpatialModel {
 public:
  OpenPoseModel(const SpatialOptions& o, const EngineOptions& engine, bool has_features)
      : NetSpatialModel(openPoseSpec(has_features), o, engine) {
    decode_.limbs = options_.limbs.empty() ? kCocoSkeleton : options_.limbs;
    decode_.nms_threshold = options_.nms_threshold;
    decode_.max_persons = options_.max_persons;
  }

 protected:
  Poses decode(const Tensors& t, float) const override {
    return decodeOpenPose(t.at("beliefs"), t.at("pafs"), decode_);
  }
  cv::Mat beliefs(const Tensors& t) const override {
    const cv::Mat& b = t.at("beliefs");
    cv::Mat out(std::vector<int>{1, kNumJoints, b.size[2], b.size[3]}, CV_32F);
    for (int j = 0; j < kNumJoints; ++j) {
      cv::Mat dst = plane(out, j);
      cv::min(cv::max(plane(b, j), 0.0), 1.0, dst);
    }
    return out;
  }

 private:
  OpenPoseDecodeOptions decode_;
};

}  // namespace

std::unique_ptr<SpatialModel> createOpenPose(const SpatialOptions& options,
                                             const EngineOptions& engine) {
  const auto outs = modelOutputNames(options.model_path, engine);
  const bool has_features = std::find(outs.begin(), outs.end(), "features") != outs.end();
  return std::make_unique<OpenPoseModel>(options, engine, has_features);
}

}  // namespace jointflow::detail
