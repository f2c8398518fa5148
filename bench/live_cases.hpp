// The live cases of identity-bench (bench/live_pipeline.hpp runs the pipelines):
//   - vtest.avi live against offline: distinct ids (it has no ground truth);
//   - the Bonn test sequence as a live camera: its frames played forward and backward into a clip
//     at the sequence's frame rate, through the live and the offline pipeline with each
//     similarity and each engine, and scored against the exact ground truth of the frames that
//     reached the tracker. Live, the tracker sees what the engine keeps up with: on a slow engine
//     a frame in several, at the gaps a leaky queue leaves, with real timestamps and DISCONT
//     flags; the offline run of the same clip is its reference.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "jointflow/posetrack.hpp"

namespace jointflow::bench {

/// A live case's raw figures (docs/identity.json) and its section of docs/identity.md.
struct LiveCase {
  nlohmann::json figures = nlohmann::json::object();
  std::string markdown;
};

using Log = std::function<void(const std::string&)>;

/// vtest.avi's first `frames` frames, jointflowtrack's defaults: distinct and confirmed ids live
/// and offline. `scratch`: a folder for the JSON files (made and removed here).
LiveCase liveVtest(const std::string& vtest, int frames, const std::string& scratch,
                   const Log& log);

/// What the Bonn live case runs.
struct LiveBonnOptions {
  int frames = 121;   ///< forward-backward play of the sequence for this many frames
  double fps = 30.0;  ///< the clip's frame rate (the Bonn data does not record one)
  std::vector<std::string> similarities;
  std::vector<std::string> backends = {"opencv", "openvino"};  ///< jointflowtrack's backend
  std::string properties;        ///< more jointflowtrack properties (the association options)
  float joint_threshold = 0.3f;  ///< joints scoring below are not written (as the other cases)
};

/// The Bonn sequence (`images`, its ground truth `source`) as a live camera; see the file comment.
LiveCase liveBonn(const std::vector<cv::Mat>& images, const posetrack::Sequence& source,
                  const LiveBonnOptions& options, const std::string& scratch, const Log& log);

}  // namespace jointflow::bench
