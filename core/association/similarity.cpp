// The similarities selectable by name, as potential matrices (rows: previous, columns: current).
#include <algorithm>
#include <cmath>

#include "jointflow/error.hpp"
#include "jointflow/similarity.hpp"

namespace jointflow {
namespace {

Potentials emptyPotentials(size_t rows, size_t cols) {
  return {cv::Mat::zeros(static_cast<int>(rows), static_cast<int>(cols), CV_32F),
          cv::Mat::zeros(static_cast<int>(rows), static_cast<int>(cols), CV_32F)};
}

// IoU, PCKh and OKS: Psi is the score itself (Eq. 8).
class PairwiseSimilarity : public Similarity {
 public:
  using Score = float (*)(const Pose&, const Pose&, const SimilarityOptions&);
  PairwiseSimilarity(SimilarityType type, Score score, const SimilarityOptions& o)
      : type_(type), score_(score), options_(o) {}
  SimilarityType type() const override { return type_; }
  Potentials compute(const Poses& previous, const Poses& current,
                     const SimilarityInput&) const override {
    Potentials p = emptyPotentials(previous.size(), current.size());
    for (size_t m = 0; m < previous.size(); ++m)
      for (size_t n = 0; n < current.size(); ++n)
        p.psi.at<float>(m, n) = score_(previous[m], current[n], options_);
    p.per_joint = p.psi.clone();
    return p;
  }

 private:
  SimilarityType type_;
  Score score_;
  SimilarityOptions options_;
};

// Psi of Eq. 7 for every pair, and Psi per joint detected in both for the minimum potential.
template <typename Energy>
Potentials sumOverJoints(const Poses& previous, const Poses& current, const JointThresholds& t,
                         const Energy& energy) {
  Potentials p = emptyPotentials(previous.size(), current.size());
  for (size_t m = 0; m < previous.size(); ++m) {
    for (size_t n = 0; n < current.size(); ++n) {
      int common = 0;
      const float psi = personPotential(previous[m], current[n], t, energy, &common);
      p.psi.at<float>(m, n) = psi;
      p.per_joint.at<float>(m, n) = common ? psi / common : 0.f;
    }
  }
  return p;
}

// "tff", and "auto" where its TFF runs (the associator decides per frame, pose_associator.cpp).
class TffSimilarity : public Similarity {
 public:
  TffSimilarity(SimilarityType type, const SimilarityOptions& o) : type_(type), options_(o) {}
  SimilarityType type() const override { return type_; }
  bool needsTff() const override { return true; }
  Potentials compute(const Poses& previous, const Poses& current,
                     const SimilarityInput& in) const override {
    if (in.tff.empty() || in.tff.type() != CV_32F || in.tff.dims != 4 ||
        in.tff.size[1] != 2 * kNumJoints)
      throw Error(
          "similarity 'tff' needs a TFF map CV_32F {1, 34, H, W} between the previous "
          "and the current frame");
    const cv::Mat tff = in.tff.isContinuous() ? in.tff : in.tff.clone();
    // E_j of Eq. 6.
    return sumOverJoints(previous, current, options_.thresholds,
                         [&](int j, const Keypoint& a, const Keypoint& b) {
                           return jointPotential(tff, in.grid_to_frame, j, {a.x, a.y}, {b.x, b.y},
                                                 options_.tau_delta, options_.line_samples);
                         });
  }

 private:
  SimilarityType type_;
  SimilarityOptions options_;
};

class FlowSimilarity : public Similarity {
 public:
  explicit FlowSimilarity(const SimilarityOptions& o) : options_(o) {}
  SimilarityType type() const override { return SimilarityType::kFlow; }
  bool needsFlow() const override { return true; }
  Potentials compute(const Poses& previous, const Poses& current,
                     const SimilarityInput& in) const override {
    if (in.flow.empty() || in.flow.type() != CV_32FC2)
      throw Error(
          "similarity 'flow' needs a dense optical flow CV_32FC2 between the previous "
          "and the current frame");
    if (!(in.flow_scale >= 1.f) || !std::isfinite(in.flow_scale))
      throw Error("similarity 'flow': flow_scale must be a finite factor >= 1, got " +
                  std::to_string(in.flow_scale));
    const cv::Mat& f = in.flow;
    const float scale = in.flow_scale;
    // E_flow of Eq. 9, the flow read at the previous keypoint's pixel.
    return sumOverJoints(
        previous, current, options_.thresholds, [&](int, const Keypoint& a, const Keypoint& b) {
          const int x = std::clamp(static_cast<int>(std::lround(a.x / scale)), 0, f.cols - 1);
          const int y = std::clamp(static_cast<int>(std::lround(a.y / scale)), 0, f.rows - 1);
          const cv::Vec2f v = f.at<cv::Vec2f>(y, x) * scale;
          return flowEnergy({a.x, a.y}, {b.x, b.y}, {v[0], v[1]}, options_.sigma_flow);
        });
  }

 private:
  SimilarityOptions options_;
};

}  // namespace

std::unique_ptr<Similarity> createSimilarity(SimilarityType type,
                                             const SimilarityOptions& options) {
  switch (type) {
    case SimilarityType::kTff:
    case SimilarityType::kAuto:
      return std::make_unique<TffSimilarity>(type, options);
    case SimilarityType::kFlow:
      return std::make_unique<FlowSimilarity>(options);
    case SimilarityType::kIou:
      return std::make_unique<PairwiseSimilarity>(
          type,
          [](const Pose& a, const Pose& b, const SimilarityOptions& o) {
            return poseBoxIou(a, b, o.thresholds);
          },
          options);
    case SimilarityType::kPckh:
      return std::make_unique<PairwiseSimilarity>(
          type,
          [](const Pose& a, const Pose& b, const SimilarityOptions& o) {
            return pckh(a, b, o.thresholds, o.min_common_joints);
          },
          options);
    case SimilarityType::kOks:
      break;
  }
  return std::make_unique<PairwiseSimilarity>(
      SimilarityType::kOks,
      [](const Pose& a, const Pose& b, const SimilarityOptions& o) {
        return oks(a, b, o.thresholds, 0.f, o.min_common_joints);
      },
      options);
}

}  // namespace jointflow
