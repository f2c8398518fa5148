// Person similarities for association: the paper's TFF potential (Sec. 4.2, Eq. 5-7) and its
// baselines (Sec. 6.1 "Comparison to Baselines", Eq. 8-9), each selectable by name.
//
// All positions are frame pixels unless a name says "grid". A joint counts as detected when its
// score is > 0 and >= the joint threshold of JointThresholds.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/setting_enums.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow/types.hpp"

namespace jointflow {

/// Per-joint detection thresholds: a keypoint takes part in Psi when score >= threshold[j].
using JointThresholds = std::array<float, kNumJoints>;

inline bool isDetected(const Keypoint& k, float threshold) {
  return k.score > 0.f && k.score >= threshold;
}

// --- The paper's equations, one function each ---------------------------------------------------

/// Bilinear sample of channel `channel` of a {1, C, H, W} CV_32F continuous map at grid point p;
/// p is clamped to the grid (cell centres at integers). The one bilinear sampling of the
/// association: Eq. 5 reads the TFF through it.
inline float sampleBilinear(const cv::Mat& map, int channel, cv::Point2f p) {
  const int h = map.size[2], w = map.size[3];
  const float x = p.x < 0.f ? 0.f : (p.x > w - 1 ? static_cast<float>(w - 1) : p.x);
  const float y = p.y < 0.f ? 0.f : (p.y > h - 1 ? static_cast<float>(h - 1) : p.y);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int right = x0 < w - 1 ? 1 : 0, down = y0 < h - 1 ? w : 0;
  const float fx = x - x0, fy = y - y0;
  const float* q = map.ptr<float>() + (static_cast<size_t>(channel) * h + y0) * w + x0;
  const float top = q[0] + fx * (q[right] - q[0]);
  const float bottom = q[down] + fx * (q[down + right] - q[down]);
  return top + fy * (bottom - top);
}

/// Eq. 5: E_aggr = integral over o in [0, 1] of T_j(i(o)) . (to - from)/|to - from|, with
/// i(o) = (1 - o) from + o to, approximated by the mean over `samples` points o = k/(samples-1)
/// (both ends included; samples >= 2). `from` and `to` in grid coordinates; `tff` is
/// {1, 2*J, H, W}, continuous. Returns 0 when from == to.
float flowFieldAggregate(const cv::Mat& tff, int joint, cv::Point2f from_grid, cv::Point2f to_grid,
                         int samples);

/// Eq. 6: E_j = 1 when the joint moved less than tau_delta frame pixels, else E_aggr evaluated on
/// the grid (positions mapped from frame pixels with grid_to_frame.toGrid).
float jointPotential(const cv::Mat& tff, const GridTransform& grid_to_frame, int joint,
                     cv::Point2f from_frame, cv::Point2f to_frame, float tau_delta, int samples);

/// Eq. 7: Psi = sum over the joints detected in both poses (the indicator 1(.,.)) of the joint
/// potential E_j; `energy(j, a, b)` gives E_j for joint j from keypoint a (previous) to b
/// (current): Eq. 6 for "tff", Eq. 9 for "flow". `common` (if given) receives the number of
/// joints detected in both.
template <typename JointEnergy>
float personPotential(const Pose& previous, const Pose& current, const JointThresholds& thresholds,
                      const JointEnergy& energy, int* common = nullptr) {
  float psi = 0.f;
  int n = 0;
  for (int j = 0; j < kNumJoints; ++j) {
    const Keypoint& a = previous.keypoints[j];
    const Keypoint& b = current.keypoints[j];
    if (!isDetected(a, thresholds[j]) || !isDetected(b, thresholds[j])) continue;
    psi += energy(j, a, b);
    ++n;
  }
  if (common) *common = n;
  return psi;
}

/// Eq. 9: E_flow = exp(-|to - (from + flow)|^2 / sigma_flow^2), flow = f(p_(t-1)).
float flowEnergy(cv::Point2f from, cv::Point2f to, cv::Point2f flow, float sigma_flow);

/// Eq. 8 (IoU): IoU of the tight boxes around the detected keypoints of each pose.
float poseBoxIou(const Pose& a, const Pose& b, const JointThresholds& thresholds);

/// Head size of a COCO pose, as PCKh needs it (PoseTrack uses 0.6 x the head-box diagonal; a COCO
/// pose has no head box). Estimated as 0.63 x the shoulder width when both shoulders are detected
/// (the median ratio on the Bonn train ground truth), else 1.6 x the ear-to-ear distance, else
/// the longer side of the box of the detected keypoints / 7.5; 0 when no keypoint is detected.
float headSize(const Pose& pose, const JointThresholds& thresholds);

/// Eq. 8 (PCKh): fraction of the joints detected in both poses that lie within 0.5 x the mean head
/// size of the two poses; 0 when no joint is detected in both. With min_joints > 1 the fraction is
/// taken of at least that many joints (SimilarityOptions::min_common_joints).
float pckh(const Pose& a, const Pose& b, const JointThresholds& thresholds, int min_joints = 1);

/// Eq. 8 (OKS): COCO object keypoint similarity between two poses, mean over the joints detected
/// in both of exp(-d^2 / (2 s^2 k_j^2)), k_j = 2 sigma_j (kCocoSigmas), s^2 = the larger area of
/// the two keypoint boxes (COCO takes the ground truth's area, the whole person's: of a track
/// and a person half hidden behind someone, the larger box is the nearer to the whole person;
/// with the mean, the half box shrank every tolerance and the person lost their track);
/// 0 when no joint is detected in both. With sigma_px > 0 (beyond the paper)
/// each joint's variance grows by sigma_px^2: the OKS of a predicted pose whose position is known
/// only to sigma_px (a track's motion model after a gap), exp(-d^2 / (2 (s^2 k_j^2 + sigma^2))).
/// With min_joints > 1 the mean is taken over at least that many joints, the missing ones counting
/// 0 (SimilarityOptions::min_common_joints).
float oks(const Pose& a, const Pose& b, const JointThresholds& thresholds, float sigma_px = 0.f,
          int min_joints = 1);

// --- Potential matrices ----------------------------------------------------------------------

/// What a similarity may use besides the poses. Unused members may stay empty.
struct SimilarityInput {
  cv::Mat tff;                  ///< {1, 34, H, W} between the previous and the current frame
  GridTransform grid_to_frame;  ///< of the TFF's grid
  cv::Mat flow;                 ///< CV_32FC2 dense optical flow previous -> current
  /// Frame pixels per pixel of `flow` (> 1: the flow of shrunk frames, its vectors in its own
  /// pixels); 1 = the frame's size.
  float flow_scale = 1.f;
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
  virtual SimilarityType type() const = 0;
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
  /// oks and pckh: the mean over the joints detected in both poses is taken over at least this
  /// many joints, the missing ones counting 0 (paper: 1, the plain mean; TrackerSettings).
  int min_common_joints = 1;
};

/// Creates the similarity of a type. The options' ranges are those of the tracker settings' rows
/// (settings_schema.hpp), which validateAssociationSettings checks before the PoseAssociator
/// makes its options: they are not checked again here.
std::unique_ptr<Similarity> createSimilarity(SimilarityType type, const SimilarityOptions& options);

}  // namespace jointflow
