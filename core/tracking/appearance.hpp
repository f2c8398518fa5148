// The appearance of a person, for re-identifying a lost track when it comes back: the spatial
// network's own feature vectors (SpatialResult::features) read at the person's detected keypoints
// and averaged, as BoT-SORT uses a re-id embedding but with no extra network and almost no cost;
// optionally with an HSV colour histogram of the person's box. Descriptors are L2-normalised, so
// the similarity of two is their dot product.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/setting_enums.hpp"
#include "jointflow/similarity.hpp"
#include "jointflow/spatial_model.hpp"

namespace jointflow {

using Descriptor = std::vector<float>;

/// The descriptor of `pose` (empty when nothing can be read: no features, no detected joint).
/// `features` is {1, C, H, W} on the grid of `grid_to_frame`; `bgr` the frame (kFeaturesColour).
Descriptor describeAppearance(const Pose& pose, const cv::Mat& features,
                              const GridTransform& grid_to_frame, const cv::Mat& bgr,
                              const JointThresholds& thresholds, AppearanceModel model);

/// Cosine similarity of two descriptors; 0 when either is empty or their sizes differ.
float appearanceSimilarity(const Descriptor& a, const Descriptor& b);

/// a <- normalise(alpha a + (1 - alpha) b): a track's running appearance (b when a is empty).
void blendAppearance(Descriptor& a, const Descriptor& b, float alpha);

}  // namespace jointflow
