// The appearance of a person, for re-identifying a lost track when it comes back, as BoT-SORT
// uses a re-id embedding, but with no extra network and almost no cost:
//   - features: the spatial network's own feature map (SpatialResult::features) read at the
//     detected keypoints, minus the frame's mean feature (what every person shares), pooled per
//     body part (head, arms, legs), each part L2-normalised;
//   - features-colour: also an HSV colour histogram of the torso and of the legs.
// Descriptors are L2-normalised, so the similarity of two is their dot product. On vtest.avi,
// for the same person 1 s (2 s) apart against the others then present (docs/reid-bench.md), the
// network's features alone rank the right person first in 75 % (62 %) of cases, with the colour
// of torso and legs in 97 % (95 %): MoveNet's 24 feature channels describe pose more than people.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/setting_enums.hpp"
#include "jointflow/similarity.hpp"
#include "jointflow/spatial_model.hpp"

namespace jointflow {

using Descriptor = std::vector<float>;

/// The descriptors of poses[i] for each i in `which` (others stay empty; empty also when nothing
/// can be read). `features` is {1, C, H, W} on the grid of `grid_to_frame`; `bgr` the frame
/// (kFeaturesColour).
std::vector<Descriptor> describeAppearance(const Poses& poses, const std::vector<int>& which,
                                           const cv::Mat& features,
                                           const GridTransform& grid_to_frame, const cv::Mat& bgr,
                                           const JointThresholds& thresholds,
                                           AppearanceModel model);

/// Cosine similarity of two descriptors; 0 when either is empty or their sizes differ.
float appearanceSimilarity(const Descriptor& a, const Descriptor& b);

/// a <- normalise(alpha a + (1 - alpha) b): a track's running appearance (b when a is empty).
void blendAppearance(Descriptor& a, const Descriptor& b, float alpha);

}  // namespace jointflow
