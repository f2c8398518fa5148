// The pipeline jointflow-track builds in code, on the same elements a gst-launch line would use:
//
//   uridecodebin (or multifilesrc ! decodebin) [! queue leaky] ! videoconvert ! jointflowtrack
//     [! jointflowjsonwriter] [! jointflowmetapublish] [! jointflowoverlay ! videoconvert ! x264enc
//     ! mp4mux|matroskamux ! filesink | fakesink]
#pragma once

#include <gst/gst.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "frame_index.hpp"
#include "input.hpp"
#include "lag_log.hpp"
#include "live_source.hpp"
#include "mot_output.hpp"
#include "posetrack_output.hpp"
#include "publish_output.hpp"
#include "run_metrics.hpp"
#include "run_statistics.hpp"

namespace jointflow::cli {

/// Finds jointflowtrack: the registry first (GST_PLUGIN_PATH, the system's plugins), then the
/// plugin installed beside this program (<prefix>/<libdir>/gstreamer-1.0 for <prefix>/bin, so that
/// an installed program uses its own plugin, wherever the prefix was moved), then the build tree it
/// was built in, then the configured install folder. False, with the folders looked in added to
/// @looked_in, when none has it.
bool findPlugin(std::vector<std::string>& looked_in);

struct Outputs {
  std::string json;           ///< JSON Lines file, "-" = stdout
  std::string posetrack_dir;  ///< PoseTrack 2018 folder
  std::string mot;            ///< MOTChallenge boxes file
  std::string video;          ///< overlay video, .mp4 or .mkv
  std::string lag;            ///< --output-lag: each frame's lag, CSV (live inputs)
  bool draw_boxes = false;
  PublishOptions publish;  ///< --publish, --source-id, --publish-config
};

/// One run: the pipeline and what its probes and bus handler share with the main loop.
struct Run {
  GstElement* pipeline = nullptr;
  GstElement* entry = nullptr;  ///< where the decoder's video pad is linked
  GMainLoop* loop = nullptr;
  RunStatistics stats;
  std::optional<PoseTrackOutput> posetrack;  ///< written by the streaming thread only
  std::optional<MotOutput> mot;              ///< written by the streaming thread only
  FrameIndexer frame_indexer;
  FolderClock folder_clock;
  std::uint64_t max_frames = 0;      ///< 0 = all
  std::uint64_t frames_in = 0;       ///< frames that reached the tracker's input (streaming thread)
  std::uint64_t total_frames = 0;    ///< estimate for the progress bar; 0 = unknown
  std::string error;                 ///< the first error on the bus
  int error_status = 1;              ///< the exit status for error: kExitSourceLost or 1
  bool stopping = false;             ///< a stop signal came: EOS sent
  std::unique_ptr<LiveSource> live;  ///< a live input's reconnection (isLiveUri)
  std::atomic<std::uint64_t> source_frames{0};  ///< decoded frames into the entry
  std::atomic<std::uint64_t> leaked_frames{0};  ///< dropped by the live input's leaky queue
  std::unique_ptr<RunMetrics> metrics;          ///< --metrics-port: what /metrics serves
  std::unique_ptr<LagLog> lag_log;              ///< --output-lag (streaming thread)

  Run() = default;
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;
  ~Run();
};

/// Builds the pipeline into run.pipeline (which takes `track`'s reference) and its probes; a
/// live input gets run.live, which rebuilds its source as @reconnect says.
/// Throws jointflow::Error when an element is missing or an output cannot be made.
void buildPipeline(Run& run, const Input& input, const Outputs& out, GstElement* track,
                   int framerate, const ReconnectOptions& reconnect);

/// Refreshes run.metrics' program figures (frames from the source and dropped, reconnections, the
/// publisher's queue); main loop only.
void updateProgramFigures(Run& run);

/// Plays until EOS or an error (then run.error is set); returns the seconds it played.
double play(Run& run);

/// Fills run.total_frames from the stream's duration and frame rate when it is still unknown.
void estimateTotalFrames(Run& run);

}  // namespace jointflow::cli
