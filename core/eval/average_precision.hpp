// VOC-style average precision as poseval computes it (its computeRPC + VOCap).
#pragma once

#include <vector>

#include "frame_matching.hpp"

namespace jointflow::eval {

/// AP in [0, 1] of scored detections against `num_positives` ground-truth joints: the area under
/// the precision/recall curve with precision made monotone (PASCAL VOC 2010+). 0 without
/// detections, NaN with detections but no positives (0/0 recall, as poseval gets it).
/// Equal scores keep poseval's order for them: numpy's argsort reversed (later entries first).
double averagePrecision(const std::vector<ScoredJoint>& detections, int num_positives);

}  // namespace jointflow::eval
