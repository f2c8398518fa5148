// Two people crossing or meeting, with real human motion: the articulation of the Bonn PoseTrack
// train people (their ground truth, no images), each carried along a walk that brings the two
// together, the one behind hidden where the one in front covers them. What a camera over a
// street or a shop shows most often where trackers swap ids (issue 42: vtest.avi's crossings),
// with the identities known exactly. Shared by the identity bench and tests/bench.
//
// Each case: two walkers of the same height come towards each other on parallel lines `offset`
// heights apart (the lower one in the image, nearer the camera, in front); they either pass
// each other ("cross") or stop where they meet for `linger` seconds and go back the way they came
// ("meet": a constant-velocity prediction sends each on into the other). The joints of the one
// behind that fall inside the box of the one in front (grown by `cover_margin`) are not detected;
// with fewer than `min_visible` joints left, the person is not detected at all.
#pragma once

#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "jointflow/posetrack.hpp"
#include "jointflow/tracker.hpp"
#include "jointflow/types.hpp"

namespace jointflow::bench {

struct CrossingOptions {
  float height = 80.f;        ///< people's height, px (vtest.avi: 40-100)
  double fps = 10.0;          ///< frames per second of the simulated camera
  float speed = 0.8f;         ///< walking speed, heights per second (a walker's pace)
  float approach = 2.5f;      ///< seconds from the start to where the two meet
  float linger = 1.f;         ///< "meet": seconds the two stand together
  float jitter = 0.02f;       ///< joint jitter, standard deviation in heights
  float miss_joint = 0.05f;   ///< probability that a visible joint is not detected
  float cover_margin = 0.1f;  ///< the front person's box grows by this share of the height
  int min_visible = 4;        ///< fewer joints detected: the person is not detected
};

enum class CrossingKind { kCross, kMeet };

/// One case: per frame, the detected poses with their identity (0 or 1).
struct CrossingCase {
  CrossingKind kind = CrossingKind::kCross;
  float offset = 0.f;  ///< vertical distance of the two lines, heights
  std::string source;  ///< the two train people: "<sequence>#<track id>+<sequence>#<track id>"
  std::vector<std::vector<std::pair<int, Pose>>> frames;
  int meet_frame = 0;  ///< where the two centres come closest
  double fps = 10.0;   ///< frames per second (stream time of frame k: k / fps)
};

/// Cases from the Bonn train ground truth (a folder of PoseTrack files): `pairs` pairs of
/// people with enough frames, each crossing and meeting at each offset. Deterministic in `seed`.
std::vector<CrossingCase> makeCrossings(const std::string& train_folder, int pairs,
                                        const std::vector<float>& offsets,
                                        const CrossingOptions& options, unsigned seed);

/// How the ids came out of the cases.
struct CrossingOutcome {
  int cases = 0;
  int kept = 0;      ///< both people leave with the ids they came with
  int swapped = 0;   ///< someone leaves with the other's id
  int new_id = 0;    ///< someone leaves under an id new to the case (and nobody swapped)
  int switches = 0;  ///< times a person was reported under another id than on their last frame
  int lost = 0;      ///< someone not reported on the last frames (neither id)
};

/// Runs a PoseAssociator (fresh per case) on every case and tallies the outcomes; `failures`,
/// if given, receives a line per case that was not kept.
/// `trace`, if given, receives per frame each person's detected centre and reported id.
CrossingOutcome trackCrossings(const std::vector<CrossingCase>& cases,
                               const TrackerSettings& settings,
                               std::vector<std::string>* failures = nullptr,
                               std::ostream* trace = nullptr);

}  // namespace jointflow::bench
