// The appearance of a person, for re-identifying a lost track when it comes back, as BoT-SORT
// uses a re-id embedding, but with no extra network and almost no cost:
//   - features: the spatial network's own feature map (SpatialResult::features) read at the
//     detected keypoints, minus the frame's mean feature (what every person shares), pooled per
//     body part (head, arms, legs);
//   - features-colour: also an HSV colour histogram of the torso and of the legs.
// Each part is L2-normalised, or empty where the part is not seen. Two descriptors are compared on
// the parts seen in both: a person half hidden (legs under an occluder, out of the frame) is
// compared on what shows. (With one vector over all parts, zeros for a part not seen, the same
// person with the legs hidden scored at most 0.82 in features and 0.71 in colour, under
// reid_min_similarity 0.8: people coming out from behind something could not be re-identified.)
// On vtest.avi against its hand-made identity labels (docs/reid-bench.md), a person's running
// appearance against the people present 1 s (2 s) later: the network's features alone rank the
// right person first in 64 % (54 %) of cases, with the colour of torso and legs in 93 % (89 %):
// MoveNet's 24 feature channels describe pose more than people.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/setting_enums.hpp"
#include "jointflow/similarity.hpp"
#include "jointflow/spatial_model.hpp"

namespace jointflow {

/// A person's appearance, per part: unit-length vectors, empty where the part was not seen.
struct Descriptor {
  std::vector<std::vector<float>> features;  ///< head, arms, legs (feature map)
  std::vector<std::vector<float>> colour;    ///< torso, legs (kFeaturesColour; else none)
  bool empty() const;                        ///< no feature part seen
};

/// The descriptors of poses[i] for each i in `which` (others stay empty; empty also when nothing
/// can be read). `features` is {1, C, H, W} on the grid of `grid_to_frame`; `bgr` the frame
/// (kFeaturesColour).
std::vector<Descriptor> describeAppearance(const Poses& poses, const std::vector<int>& which,
                                           const cv::Mat& features,
                                           const GridTransform& grid_to_frame, const cv::Mat& bgr,
                                           const JointThresholds& thresholds,
                                           AppearanceModel model);

/// The mean cosine of the feature parts seen in both, averaged with that of the colour parts seen
/// in both (kFeaturesColour). 0 when no feature part, or (with colour) no colour part, is seen in
/// both, or the descriptors are of different models.
float appearanceSimilarity(const Descriptor& a, const Descriptor& b);

/// A track's running appearance, per part seen in b: a <- normalise(alpha a + (1 - alpha) b)
/// (b where a has not seen the part); parts b does not see stay as they are. b when a is empty.
void blendAppearance(Descriptor& a, const Descriptor& b, float alpha);

}  // namespace jointflow
