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
  using Score = float (*)(const Pose&, const Pose&, const JointThresholds&);
  PairwiseSimilarity(std::string name, Score score, const SimilarityOptions& o)
      : name_(std::move(name)), score_(score), options_(o) {}
  std::string name() const override { return name_; }
  Potentials compute(const Poses& previous, const Poses& current,
                     const SimilarityInput&) const override {
    Potentials p = emptyPotentials(previous.size(), current.size());
    for (size_t m = 0; m < previous.size(); ++m)
      for (size_t n = 0; n < current.size(); ++n)
        p.psi.at<float>(m, n) = score_(previous[m], current[n], options_.thresholds);
    p.per_joint = p.psi.clone();
    return p;
  }

 private:
  std::string name_;
  Score score_;
  SimilarityOptions options_;
};

// Sums a per-joint energy over the joints detected in both poses (Eq. 7 with E_j from Eq. 6 for
// "tff", from Eq. 9 for "flow").
template <typename Energy>
Potentials sumOverJoints(const Poses& previous, const Poses& current, const JointThresholds& t,
                         const Energy& e) {
  Potentials p = emptyPotentials(previous.size(), current.size());
  for (size_t m = 0; m < previous.size(); ++m) {
    for (size_t n = 0; n < current.size(); ++n) {
      float psi = 0.f;
      int common = 0;
      for (int j = 0; j < kNumJoints; ++j) {
        const Keypoint& a = previous[m].keypoints[j];
        const Keypoint& b = current[n].keypoints[j];
        if (!isDetected(a, t[j]) || !isDetected(b, t[j])) continue;
        psi += e(j, a, b);
        ++common;
      }
      p.psi.at<float>(m, n) = psi;
      p.per_joint.at<float>(m, n) = common ? psi / common : 0.f;
    }
  }
  return p;
}

class TffSimilarity : public Similarity {
 public:
  explicit TffSimilarity(const SimilarityOptions& o) : options_(o) {}
  std::string name() const override { return "tff"; }
  bool needsTff() const override { return true; }
  Potentials compute(const Poses& previous, const Poses& current,
                     const SimilarityInput& in) const override {
    if (in.tff.empty() || in.tff.type() != CV_32F || in.tff.dims != 4 ||
        in.tff.size[1] != 2 * kNumJoints)
      throw Error(
          "similarity 'tff' needs a TFF map CV_32F {1, 34, H, W} between the previous "
          "and the current frame");
    const cv::Mat tff = in.tff.isContinuous() ? in.tff : in.tff.clone();
    // Eq. 7 joint by joint rather than pair by pair: all pairs of one joint read the same two
    // planes of the TFF, which then stay in cache.
    Potentials p = emptyPotentials(previous.size(), current.size());
    cv::Mat common = cv::Mat::zeros(p.psi.size(), CV_32S);
    const JointThresholds& t = options_.thresholds;
    for (int j = 0; j < kNumJoints; ++j) {
      for (size_t m = 0; m < previous.size(); ++m) {
        const Keypoint& a = previous[m].keypoints[j];
        if (!isDetected(a, t[j])) continue;
        float* psi = p.psi.ptr<float>(static_cast<int>(m));
        int* n_common = common.ptr<int>(static_cast<int>(m));
        for (size_t n = 0; n < current.size(); ++n) {
          const Keypoint& b = current[n].keypoints[j];
          if (!isDetected(b, t[j])) continue;
          psi[n] += jointPotential(tff, in.grid_to_frame, j, {a.x, a.y}, {b.x, b.y},
                                   options_.tau_delta, options_.line_samples);
          ++n_common[n];
        }
      }
    }
    for (int r = 0; r < p.psi.rows; ++r)
      for (int c = 0; c < p.psi.cols; ++c) {
        const int n = common.at<int>(r, c);
        p.per_joint.at<float>(r, c) = n ? p.psi.at<float>(r, c) / n : 0.f;
      }
    return p;
  }

 private:
  SimilarityOptions options_;
};

class FlowSimilarity : public Similarity {
 public:
  explicit FlowSimilarity(const SimilarityOptions& o) : options_(o) {}
  std::string name() const override { return "flow"; }
  bool needsFlow() const override { return true; }
  Potentials compute(const Poses& previous, const Poses& current,
                     const SimilarityInput& in) const override {
    if (in.flow.empty() || in.flow.type() != CV_32FC2)
      throw Error(
          "similarity 'flow' needs a dense optical flow CV_32FC2 between the previous "
          "and the current frame");
    const cv::Mat& f = in.flow;
    return sumOverJoints(
        previous, current, options_.thresholds, [&](int, const Keypoint& a, const Keypoint& b) {
          const int x = std::clamp(static_cast<int>(std::lround(a.x)), 0, f.cols - 1);
          const int y = std::clamp(static_cast<int>(std::lround(a.y)), 0, f.rows - 1);
          const cv::Vec2f v = f.at<cv::Vec2f>(y, x);
          return flowEnergy({a.x, a.y}, {b.x, b.y}, {v[0], v[1]}, options_.sigma_flow);
        });
  }

 private:
  SimilarityOptions options_;
};

}  // namespace

const std::vector<std::string>& similarityNames() {
  static const std::vector<std::string> names = {"tff", "oks", "iou", "pckh", "flow"};
  return names;
}

std::unique_ptr<Similarity> createSimilarity(const std::string& name,
                                             const SimilarityOptions& options) {
  if (!(options.tau_delta >= 0.f) || !std::isfinite(options.tau_delta))
    throw Error("similarity: tau_delta must be a finite distance >= 0 px, got " +
                std::to_string(options.tau_delta));
  if (options.line_samples < 2 || options.line_samples > 1000)
    throw Error("similarity: line_samples must be in 2..1000, got " +
                std::to_string(options.line_samples));
  if (!(options.sigma_flow > 0.f) || !std::isfinite(options.sigma_flow))
    throw Error("similarity: sigma_flow must be a finite width > 0 px, got " +
                std::to_string(options.sigma_flow));
  for (float t : options.thresholds)
    if (!(t >= 0.f && t <= 1.f))
      throw Error("similarity: joint thresholds must lie in [0, 1], got " + std::to_string(t));
  if (name == "tff") return std::make_unique<TffSimilarity>(options);
  if (name == "flow") return std::make_unique<FlowSimilarity>(options);
  if (name == "oks") return std::make_unique<PairwiseSimilarity>("oks", &oks, options);
  if (name == "iou") return std::make_unique<PairwiseSimilarity>("iou", &poseBoxIou, options);
  if (name == "pckh") return std::make_unique<PairwiseSimilarity>("pckh", &pckh, options);
  throw Error("unknown similarity '" + name + "', expected tff, oks, iou, pckh or flow");
}

}  // namespace jointflow
