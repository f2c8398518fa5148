// Temporal Flow Fields (paper, Sec. 4.1): the ground-truth rendering of Eq. 2-4.
//
// A TFF holds, for every joint class j, a 2-D vector field on the spatial model's map grid: near
// the straight path of joint j of person k from frame t-1 to frame t it holds the unit vector v of
// that motion, elsewhere 0. Training renders it from ground truth; tests and the association
// benchmark render "oracle" fields with the same function. Layout (the TFF contract, shared with
// training/ and models/README.md): CV_32F, 4-D {1, 2*num_joints, H, W}; channel 2j = x component,
// channel 2j+1 = y component of joint j. Grid coordinates: x = column, y = row, cell centres at
// integers.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/spatial_model.hpp"
#include "jointflow/types.hpp"

namespace jointflow {

/// The motion of one joint of one person between two frames, in grid coordinates.
struct JointMotion {
  int joint = 0;
  cv::Point2f from;  ///< p_(j,k)^(t-1)
  cv::Point2f to;    ///< p_(j,k)^t
};

/// Renders T*_j of paper Eq. 4 for j = 0..num_joints-1 on a grid of `grid` cells (width, height).
/// For a motion with lambda = |to - from| > 0 and v = (to - from) / lambda, a cell p lies in
/// Omega (Eq. 2) iff 0 <= v.(p - from) <= lambda and |v_perp.(p - from)| <= sigma (inclusive);
/// T*_(j,k)(p) = v there (Eq. 3). Per joint, the field is the sum over persons divided by the
/// number n(p) of non-zero vectors at p (Eq. 4), 0 where n(p) = 0. A motion with lambda == 0
/// contributes nothing. sigma is in grid cells (paper: 1). Throws jointflow::Error for
/// num_joints < 1, an empty grid, sigma < 0 or a joint index out of range.
cv::Mat renderTemporalFlowField(const std::vector<JointMotion>& motions, int num_joints,
                                cv::Size grid, float sigma);

/// The joint motions between two poses of one person, converted to grid coordinates: one per
/// joint whose score is >= min_score (and > 0) in both poses.
std::vector<JointMotion> jointMotions(const Pose& previous, const Pose& current,
                                      const GridTransform& grid_to_frame, float min_score);

}  // namespace jointflow
