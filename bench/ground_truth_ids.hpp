// Who is who in the ground truth, for the identity benchmark: which predicted pose is which
// annotated person (the PCKh criterion poseval scores with), and the floor any tracker on the same
// poses can reach: the tracker's poses re-labelled with the ground truth's ids. A similarity that
// already gives that floor's id switches cannot make fewer by associating better; its remaining
// switches come from the poses (a pose that holds or lies near joints of two people, two poses
// on one person). Another similarity's tracks may write other poses (which poses a tracker
// writes depends on its tracks), so each similarity is measured against its own.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "jointflow/posetrack.hpp"

namespace jointflow::bench {

/// Joints of a ground-truth person that `pred` holds within half a head size (PCKh@0.5, the
/// head size 0.6 x the head box diagonal, as poseval), and how many the person has annotated.
struct JointAgreement {
  int annotated = 0;
  int close = 0;
};
JointAgreement jointAgreement(const posetrack::Person& gt, const posetrack::Person& pred);

/// Per ground-truth person of the frame the predicted id whose joints best match it (the share
/// of its joints within half a head size; at least half), pairs taken best first.
std::map<std::int64_t, std::int64_t> personIds(const posetrack::Frame& gt,
                                               const posetrack::Frame& pred);

/// `pred` with each pose's id replaced by the id of the ground-truth person it holds the most
/// joints of (within half a head size, at least one; pairs taken most joints first, one pose per
/// person): what a tracker that always knew who is who would write with these poses. A pose that
/// gets no person is given an id of its own in that frame (ids above every ground-truth id).
posetrack::Sequence withGroundTruthIds(const posetrack::Sequence& gt,
                                       const posetrack::Sequence& pred);

/// The joint id switches (poseval's count, summed over joints) of the sequences `pred` with
/// withGroundTruthIds: the switches of these poses that no association could have avoided.
std::int64_t groundTruthIdSwitches(const std::vector<posetrack::Sequence>& gt,
                                   const std::vector<posetrack::Sequence>& pred);

/// Id switches counted per person, not per joint: a ground-truth person whose pose (personIds)
/// carries another predicted id than the last time it carried one, as CLEAR MOT counts them for
/// boxes. poseval's count is per joint, so one person under a new id for a frame is up to 2 x 15
/// switches there and 2 here: what the identity benchmark shows beside it, to tell one event
/// from many.
std::int64_t personIdSwitches(const posetrack::Sequence& gt, const posetrack::Sequence& pred);

}  // namespace jointflow::bench
