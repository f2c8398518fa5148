// Association on real human motion with simulated detections: the Bonn PoseTrack train ground
// truth (no images) with simulated detector noise (joint jitter, missed joints, missed and false
// people), tracked by PoseAssociator with any similarity and scored with the poseval-equivalent
// evaluation; "tff-oracle" is the TFF rendered from the ground truth (paper Eq. 2-4), what a
// perfect TFF network would give. Also the timing of the association on one core. Shared by
// bench/assoc_bench.cpp and bench/identity.cpp.
#pragma once

#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/evaluation.hpp"
#include "jointflow/pose_associator.hpp"
#include "jointflow/posetrack.hpp"
#include "jointflow/types.hpp"

namespace jointflow::bench {

/// What the simulated detector gets wrong.
struct Noise {
  double jitter = 0.1;        ///< joint jitter, standard deviation in head sizes
  double miss_joint = 0.1;    ///< probability that a joint is not detected
  double miss_person = 0.05;  ///< probability that a person is not detected in a frame
  double false_person = 0.1;  ///< expected false people per frame
};

/// One detection: the PoseTrack joints written to the predictions, the COCO pose the tracker sees,
/// and the ground-truth identity (-1 for a false person).
struct Detection {
  posetrack::PoseTrackJoints joints;
  Pose pose;
  std::int64_t identity = -1;
};

struct SimFrame {
  std::vector<Detection> detections;
  std::map<std::int64_t, Pose> truth;  ///< clean ground truth by identity, for the oracle TFF
};

struct SimSequence {
  posetrack::Sequence ground_truth;  ///< the frames kept at this stride
  std::vector<SimFrame> frames;
  cv::Size frame_size;
  double frame_seconds = 0.04;  ///< stream time between kept frames (stride / 25 frames/s)
};

/// The COCO pose of PoseTrack joints (neck and head top have none), every joint scored 1, the
/// person `score`, the box around the joints.
Pose cocoPose(const posetrack::PoseTrackJoints& joints, float score);

/// Simulated detections of every `stride`-th frame of a ground-truth sequence.
SimSequence simulate(const posetrack::Sequence& gt, int stride, const Noise& noise,
                     std::mt19937& rng);

/// The simulated sequences of every file in `folder` at `stride` (those with at least 3 frames
/// left, which poseval's tracking part needs), one generator seeded with `seed` for all.
std::vector<SimSequence> simulateFolder(const std::string& folder, int stride, const Noise& noise,
                                        unsigned seed);

struct SimRunResult {
  PoseTrackEvalResult eval;            ///< the poseval-equivalent scores (IDF1 included)
  std::int64_t id_switches = 0;        ///< person level: an identity reported under a new id
  std::int64_t joint_id_switches = 0;  ///< poseval's, summed over the joint classes
};

/// Tracks every sequence with one similarity ("tff-oracle" for the rendered TFF) and scores the
/// result.
SimRunResult trackSimulated(const std::vector<SimSequence>& sims, const std::string& similarity,
                            TrackerSettings settings);

/// Association timing on one core (CPU time of the calling thread, median of `runs` runs).
struct AssociationTiming {
  double potentials_ms = 0.0;   ///< Psi of n x n people by the TFF integral
  double with_greedy_ms = 0.0;  ///< the same plus greedy matching
  double wall_ms = 0.0;         ///< wall-clock time of the latter
  double best_ms = 0.0;         ///< the fastest run with greedy matching (least disturbed)
};

/// Psi by the TFF integral + greedy matching for `people` tracks and `people` new poses on a
/// 960 x 540 frame (stride-4 TFF grid, random field).
AssociationTiming timeTffPotentials(int people, int line_samples, int runs = 200);

/// One whole PoseAssociator::update per frame with `people` people walking across a 960 x 540
/// frame, each missed in one frame in ten (so tracks are lost and found again), with a random
/// feature map for re-identification, the TFF rendered from their true motion for "tff", and
/// the frames of `video` (grey, 960 x 540; none: no frames) for "flow" and the camera motion,
/// played forward and back so that every frame follows one it followed in the video: median CPU
/// ms per frame over `frames` frames after a warm-up, everything the association does per frame
/// included.
double timeAssociatorUpdate(const std::string& similarity, int people, TrackerSettings settings,
                            const std::vector<cv::Mat>& video, int frames = 200);

}  // namespace jointflow::bench
