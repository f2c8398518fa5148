// jointflowtrack in a gst-launch pipeline, as a user runs it, and the poses its
// jointflowjsonwriter wrote, read back: the live cases of identity-bench. Live = paced in real
// time (`identity sync=true`) with a leaky queue of one buffer before the tracker, as the
// documented camera pipelines do, so that what the tracker cannot take in time is dropped and the
// next buffer comes flagged DISCONT; offline = the same line without pacing and queue.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/tracker.hpp"

namespace jointflow::bench {

/// What a pipeline's jointflowjsonwriter wrote, buffer by buffer.
struct PipelineRun {
  bool ran = false;
  std::string note;           ///< why it did not run (empty when it ran)
  double seconds = 0.0;       ///< wall time, PLAYING to EOS
  std::vector<double> times;  ///< each buffer's stream time (PTS), seconds; NaN without one
  std::vector<std::vector<TrackedPose>> frames;  ///< each buffer's poses (box, keypoints, id)
};

/// Runs `launch` to EOS or an error and reads `jsonl` (the JSON Lines its jointflowjsonwriter
/// wrote) back. An error (no such element, a property the build lacks, a failing engine) is the
/// note, not an exception: a case the machine cannot run reports itself not run.
PipelineRun runPipeline(const std::string& launch, const std::string& jsonl);

/// The gst-launch line: `source` (up to raw video), then for `live` the real-time pacing and the
/// leaky queue, then jointflowtrack with `properties` (may be empty) and the JSON writer.
std::string trackPipeline(const std::string& source, bool live, const std::string& properties,
                          const std::string& jsonl);

/// Writes `frames` (8-bit BGR, one size) as an MJPEG AVI at `fps` frames per second: a clip that
/// GStreamer plays with exact timestamps, frame k at k / fps.
void writeClip(const std::vector<cv::Mat>& frames, double fps, const std::string& path);

}  // namespace jointflow::bench
