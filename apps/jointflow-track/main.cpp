// jointflow-track: tracks the poses of every person in a video, a URI or a folder of numbered
// frames, headless, on the same GStreamer elements a pipeline would use (pipeline.hpp). The
// options that configure the tracker are jointflowtrack's own properties (property_options.hpp).
//
// stdout carries data only when asked to (--output-json -, --properties-markdown); the summary
// then goes to stderr with the progress line and the messages.
#include <gst/gst.h>
#include <malloc.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>

#include "input.hpp"
#include "jointflow/error.hpp"
#include "metrics_server.hpp"
#include "pipeline.hpp"
#include "progress.hpp"
#include "property_options.hpp"

namespace fs = std::filesystem;
using namespace jointflow::cli;

namespace {

struct Progress {
  Run* run;
  std::chrono::steady_clock::time_point start;
};

// glibc gives each thread that allocates while another does an arena of its own (up to 8 per
// core) and keeps the memory those arenas held after the threads end. A live input builds its
// source again at each reconnection, with new threads (rtspsrc's, the decoder's), which took new
// arenas: resident memory grew by about 7 MiB per reconnection, with no object left alive
// (docs/soak-live.md). One arena keeps it flat; MALLOC_ARENA_MAX, when set, has the last word.
void boundMallocArenas() {
#ifdef __GLIBC__
  if (!g_getenv("MALLOC_ARENA_MAX")) mallopt(M_ARENA_MAX, 1);
#endif
}

gboolean onMetricsTimer(gpointer data) {
  updateProgramFigures(*static_cast<Run*>(data));
  return G_SOURCE_CONTINUE;
}

gboolean onProgressTimer(gpointer data) {
  auto* p = static_cast<Progress*>(data);
  estimateTotalFrames(*p->run);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - p->start).count();
  showProgress(p->run->stats.counts().frames, p->run->total_frames, elapsed);
  return G_SOURCE_CONTINUE;
}

}  // namespace

int main(int argc, char** argv) {
  gst_init(&argc, &argv);
  std::vector<std::string> looked_in;
  if (!findPlugin(looked_in)) {
    std::string where;
    for (const std::string& dir : looked_in) where += "\n  " + dir;
    g_printerr(
        "jointflow-track: the JointFlow GStreamer plugin was not found; set GST_PLUGIN_PATH to "
        "the folder holding libgstjointflow.so (build/gst-plugin, or <prefix>/%s of an install). "
        "Looked in:%s\n",
        JOINTFLOW_PLUGIN_FROM_PROGRAM, where.c_str());
    return 2;
  }
  GstElement* track = gst_element_factory_make("jointflowtrack", "track");
  gst_object_ref_sink(track);

  CLI::App app{
      "Tracks the 2D poses of every person in a video (JointFlow). INPUT is a video "
      "file, a URI (file://, rtsp://, http://, ...) or a folder of numbered frames."};
  std::string input_text;
  Outputs out;
  std::uint64_t max_frames = 0;
  int framerate = 25;
  bool quiet = false, properties_markdown = false;
  float posetrack_threshold = 0.2f;
  int prune_short_tracks = 0;
  app.add_option("INPUT", input_text, "Video file, URI or folder of numbered frames");
  app.add_option("--max-frames", max_frames, "Stop after this many frames (0 = all)");
  app.add_option("--output-json", out.json,
                 "Write the poses as JSON Lines to this file (\"-\" = stdout; the summary then "
                 "goes to stderr)");
  app.add_option("--output-posetrack", out.posetrack_dir,
                 "Write PoseTrack 2018 JSON (<sequence>.json) into this folder");
  app.add_option("--output-mot", out.mot,
                 "Write the person boxes and ids as a MOTChallenge file "
                 "(frame,id,x,y,w,h,score,-1,-1,-1; jointflow-eval --mot-gt scores it)");
  app.add_option("--output-video", out.video, "Write the video with the poses drawn (.mp4|.mkv)");
  app.add_flag("--draw-boxes", out.draw_boxes, "Draw person boxes in --output-video");
  app.add_option("--output-lag", out.lag,
                 "Live inputs: write each frame's lag (from its capture to its poses leaving the "
                 "tracker; docs/latency.md) to this CSV file: "
                 "unix_time,lag_seconds,inferred,capture_lag_seconds (empty "
                 "where the camera sends no capture time)");
  app.add_option("--framerate", framerate, "Frames per second of a folder of frames")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app.add_option("--posetrack-joint-threshold", posetrack_threshold,
                 "Joints scoring below this are left out of PoseTrack files")
      ->capture_default_str()
      ->check(CLI::Range(0.f, 1.f));
  app.add_option("--prune-short-tracks", prune_short_tracks,
                 "In --output-posetrack, drop the tracks seen on fewer frames than this (the "
                 "paper's offline pruning uses 7; 0 = keep all). Live, hide tentative tracks "
                 "with --output-tentative false instead")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000));
  addPublishOptions(app, out.publish);
  ReconnectOptions reconnect;
  addReconnectOptions(app, reconnect);
  int metrics_port = 0;
  std::string metrics_address = "0.0.0.0";
  app.add_option("--metrics-port", metrics_port,
                 "Serve Prometheus metrics on http://ADDRESS:PORT/metrics while running "
                 "(docs/deploy.md); 0 = off. Sets --stats-interval to 1 unless given")
      ->check(CLI::Range(0, 65535));
  app.add_option("--metrics-address", metrics_address,
                 "IPv4 address --metrics-port listens on (0.0.0.0 = every interface)")
      ->capture_default_str();
  app.add_flag("-q,--quiet", quiet, "No progress bar and no summary");
  app.add_flag("--properties-markdown", properties_markdown,
               "Print the table of jointflowtrack's properties (docs/gstreamer.md) and exit");
  const auto property_options = addPropertyOptions(app, track);

  try {
    app.parse(argc, argv);
    if (!properties_markdown && input_text.empty()) throw CLI::RequiredError("INPUT");
  } catch (const CLI::ParseError& e) {
    gst_object_unref(track);
    return app.exit(e);
  }
  if (properties_markdown) {
    std::fputs(propertyTableMarkdown(track).c_str(), stdout);
    gst_object_unref(track);
    return 0;
  }

  int status = 0;
  {
    Run run;
    try {
      applyPropertyOptions(app, track, property_options);
      // /metrics is built from the element's statistics messages: one a second of stream time.
      if (metrics_port > 0 && app.count("--stats-interval") == 0)
        g_object_set(track, "stats-interval", 1.0f, nullptr);
      const Input input = resolveInput(input_text);
      if (!input.frames && isLiveUri(input.uri)) boundMallocArenas();
      if (!out.posetrack_dir.empty()) {
        fs::create_directories(out.posetrack_dir);
        run.posetrack.emplace(input.sequence_name, input.file_prefix,
                              input.frames ? input.frames->names : std::vector<std::string>{},
                              posetrack_threshold);
      }
      for (const std::string& file : {out.json, out.video, out.mot})
        if (!file.empty() && file != "-" && fs::path(file).has_parent_path())
          fs::create_directories(fs::path(file).parent_path());
      if (!out.mot.empty()) run.mot.emplace(out.mot);
      run.max_frames = max_frames;
      if (input.frames) run.total_frames = input.frames->names.size();
      buildPipeline(run, input, out, track, framerate, reconnect);
      std::unique_ptr<MetricsServer> metrics_server;  // stopped before run goes
      guint metrics_timer = 0;
      if (metrics_port > 0) {
        run.metrics = std::make_unique<RunMetrics>();
        updateProgramFigures(run);
        RunMetrics* metrics = run.metrics.get();
        metrics_server = std::make_unique<MetricsServer>(metrics_address, metrics_port,
                                                         [metrics] { return metrics->render(); });
        // The program's own figures move also while no frame comes (an outage).
        metrics_timer = g_timeout_add(1000, onMetricsTimer, &run);
      }

      Progress progress{&run, std::chrono::steady_clock::now()};
      const bool show = !quiet && isatty(STDERR_FILENO);
      const guint timer = show ? g_timeout_add(250, onProgressTimer, &progress) : 0;
      const double seconds = play(run);
      if (metrics_timer) g_source_remove(metrics_timer);
      if (timer) {
        onProgressTimer(&progress);
        g_source_remove(timer);
        g_printerr("\n");
      }
      if (!run.error.empty()) {
        status = run.error_status;
        throw jointflow::Error(run.error);
      }

      std::vector<std::pair<std::string, std::string>> outputs;
      if (!out.json.empty()) outputs.emplace_back("json", out.json);
      if (!out.mot.empty()) outputs.emplace_back("mot", out.mot);
      if (!out.video.empty()) outputs.emplace_back("video", out.video);
      if (!out.publish.target.empty())
        outputs.emplace_back("publish",
                             out.publish.target + " (" + publishSummary(run.pipeline) + ")");
      if (run.live) outputs.emplace_back("reconnects", std::to_string(run.live->reconnections()));
      if (run.posetrack) {
        // A folder lists every frame, also those after the last one the decoder gave us.
        if (input.frames)
          run.posetrack->fillTo(static_cast<std::int64_t>(
              max_frames ? std::min<std::uint64_t>(max_frames, input.frames->names.size())
                         : input.frames->names.size()));
        run.posetrack->pruneShortTracks(prune_short_tracks);
        run.posetrack->write(out.posetrack_dir);
        outputs.emplace_back("posetrack", run.posetrack->path(out.posetrack_dir));
      }
      if (!quiet)
        printSummary(out.json == "-" ? stderr : stdout, run.stats.counts(), seconds, outputs);
    } catch (const std::exception& e) {
      g_printerr("jointflow-track: error: %s\n", e.what());
      if (status == 0) status = 1;
    }
  }
  gst_object_unref(track);
  gst_deinit();  // lets GST_TRACERS=leaks report what was not released
  return status;
}
