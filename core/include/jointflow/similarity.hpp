// Person similarities for association: the paper's TFF potential (Sec. 4.2, Eq. 5-7) and its
// baselines (Sec. 6.1 "Comparison to Baselines", Eq. 8-9), each selectable by name.
//
// All positions are frame pixels unless a name says "grid". A joint counts as detected when its
// score is > 0 and >= the joint threshold of JointThresholds.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/spatial_model.hpp"
#include "jointflow/types.hpp"

namespace jointflow {

/// Per-joint detection thresholds: a keypoint takes part in Psi when score >= threshold[j].
using JointThresholds = std::array<float, kNumJoints>;

inline bool isDetected(const Keypoint& k, float threshold) {
  return k.score > 0.f && k.score >= threshold;
}

// --- The paper's equations, one function each ---------------------------------------------------

/// Bilinear sample of channel `channel` of a {1, C, H, W} CV_32F map at grid point p; p is
/// clamped to the grid (cell centres at integers).
float sampleBilinear(const cv::Mat& map, int channel, cv::Point2f p);

/// Eq. 5: E_aggr = integral over o in [0, 1] of T_j(i(o)) . (to - from)/|to - from|, with
/// i(o) = (1 - o) from + o to, approximated by the mean over `samples` points o = k/(samples-1)
/// (both ends included; samples >= 2). `from` and `to` in grid coordinates; `tff` is
/// {1, 2*J, H, W}. Returns 0 when from == to.
float flowFieldAggregate(const cv::Mat& tff, int joint, cv::Point2f from_grid, cv::Point2f to_grid,
                         int samples);

/// Eq. 6: E_j = 1 when the joint moved less than tau_delta frame pixels, else E_aggr evaluated on
/// the grid (positions mapped from frame pixels with grid_to_frame.toGrid).
float jointPotential(const cv::Mat& tff, const GridTransform& grid_to_frame, int joint,
                     cv::Point2f from_frame, cv::Point2f to_frame, float tau_delta, int samples);

/// Eq. 7: Psi = sum over joints detected in both poses of E_j. `common` (if given) receives the
/// number of such joints.
float tffPersonPotential(const cv::Mat& tff, const GridTransform& grid_to_frame,
                         const Pose& previous, const Pose& current,
                         const JointThresholds& thresholds, float tau_delta, int samples,
                         int* common = nullptr);

/// Eq. 9: E_flow = exp(-|to - (from + flow)|^2 / sigma_flow^2), flow = f(p_(t-1)).
float flowEnergy(cv::Point2f from, cv::Point2f to, cv::Point2f flow, float sigma_flow);

/// Eq. 8 (IoU): IoU of the tight boxes around the detected keypoints of each pose.
float poseBoxIou(const Pose& a, const Pose& b, const JointThresholds& thresholds);

/// Head size of a COCO pose, as PCKh needs it (PoseTrack uses 0.6 x the head-box diagonal; a COCO
/// pose has no head box). Estimated as the ear-to-ear distance when both ears are detected (a
/// head box is about 1.3 head widths tall, so 0.6 x its diagonal is about one head width), else
/// half the shoulder width, else a sixth of the longer side of the keypoint box; 0 when none.
float headSize(const Pose& pose, const JointThresholds& thresholds);

/// Eq. 8 (PCKh): fraction of the joints detected in both poses that lie within 0.5 x the mean head
/// size of the two poses; 0 when no joint is detected in both.
float pckh(const Pose& a, const Pose& b, const JointThresholds& thresholds);

/// Eq. 8 (OKS): COCO object keypoint similarity between two poses, mean over the joints detected
/// in both of exp(-d^2 / (2 s^2 k_j^2)), k_j = 2 sigma_j (kCocoSigmas), s^2 = the mean area of the
/// two keypoint boxes; 0 when no joint is detected in both.
float oks(const Pose& a, const Pose& b, const JointThresholds& thresholds);

// --- Potential matrices
// ---------------------------------------------------------------------------

/// What a similarity may use besides the poses. Unused members may stay empty.
struct SimilarityInput {
  cv::Mat tff;                  ///< {1, 34, H, W} between the previous and the current frame
  GridTransform grid_to_frame;  ///< of the TFF's grid
  cv::Mat flow;                 ///< CV_32FC2 dense optical flow previous -> current, frame size
};

/// Potentials between previous poses (rows) and current poses (columns).
struct Potentials {
  cv::Mat psi;        ///< CV_32F: Psi of Eq. 7 / Eq. 8, what the matching maximises
  cv::Mat per_joint;  ///< CV_32F: Psi per joint detected in both (Psi itself for IoU, PCKh,
                      ///< OKS), compared with the minimum potential
};

class Similarity {
 public:
  virtual ~Similarity() = default;
  virtual std::string name() const = 0;
  /// Whether compute() needs SimilarityInput::tff (resp. ::flow).
  virtual bool needsTff() const { return false; }
  virtual bool needsFlow() const { return false; }
  /// Throws jointflow::Error when the input lacks what the similarity needs.
  virtual Potentials compute(const Poses& previous, const Poses& current,
                             const SimilarityInput& input) const = 0;
};

struct SimilarityOptions {
  JointThresholds thresholds{};  ///< per-joint detection thresholds
  float tau_delta = 2.f;         ///< Eq. 6, frame pixels (paper: 2)
  int line_samples = 10;         ///< Eq. 5 samples
  float sigma_flow = 30.f;       ///< Eq. 9, frame pixels (paper: 30)
};

/// Creates "tff", "oks", "iou", "pckh" or "flow"; throws jointflow::Error for any other name or
/// for options out of range.
std::unique_ptr<Similarity> createSimilarity(const std::string& name,
                                             const SimilarityOptions& options);

/// The names createSimilarity accepts.
const std::vector<std::string>& similarityNames();

}  // namespace jointflow
