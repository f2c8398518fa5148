// The jointflow-track pipeline (pipeline.hpp).
#include "pipeline.hpp"

#include <glib-unix.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>

#include "jointflow/error.hpp"

namespace fs = std::filesystem;

namespace jointflow::cli {
namespace {

GstElement* make(const char* factory, const char* name = nullptr) {
  GstElement* e = gst_element_factory_make(factory, name);
  if (!e)
    throw Error(std::string("GStreamer element \"") + factory +
                "\" is missing (install the GStreamer plugins listed in scripts/install-deps.sh)");
  return e;
}

void onPadAdded(GstElement*, GstPad* pad, gpointer data) {
  auto* run = static_cast<Run*>(data);
  GstCaps* caps = gst_pad_get_current_caps(pad);
  if (!caps) caps = gst_pad_query_caps(pad, nullptr);
  const bool video =
      caps && gst_caps_get_size(caps) > 0 &&
      g_str_has_prefix(gst_structure_get_name(gst_caps_get_structure(caps, 0)), "video/");
  if (caps) gst_caps_unref(caps);
  if (!video) return;  // audio and other streams stay unlinked
  GstPad* sink = gst_element_get_static_pad(run->entry, "sink");
  if (!gst_pad_is_linked(sink) && gst_pad_link(pad, sink) != GST_PAD_LINK_OK)
    g_printerr("jointflow-track: could not link the decoded video\n");
  gst_object_unref(sink);
}

// uridecodebin's source-setup for a live input. rtspsrc: each connection attempt and each wait for
// an answer ends after the source timeout (tcp-timeout, 20 s by default), so that a server that
// accepts the connection and never answers is given up on in that time; latency 200 ms bounds
// the jitter buffer's wait for a lost packet (2 s by default) as in examples/rtsp.sh;
// add-reference-timestamp-meta puts the camera's capture time (from its RTCP sender reports) on
// each frame, for the capture lag (gst-plugin/frame_lag.hpp).
void configureLiveSource(GstElement*, GstElement* source, gpointer data) {
  const double timeout = *static_cast<double*>(data);
  GObjectClass* klass = G_OBJECT_GET_CLASS(source);
  if (g_object_class_find_property(klass, "tcp-timeout"))
    g_object_set(source, "tcp-timeout", static_cast<guint64>(timeout * G_USEC_PER_SEC), nullptr);
  if (g_object_class_find_property(klass, "latency") &&
      g_str_has_prefix(G_OBJECT_TYPE_NAME(source), "GstRTSPSrc"))
    g_object_set(source, "latency", 200u, nullptr);
  if (g_object_class_find_property(klass, "add-reference-timestamp-meta"))
    g_object_set(source, "add-reference-timestamp-meta", TRUE, nullptr);
}

// The tracker's lost-time in seconds.
double lostTime(GstElement* track) {
  gfloat seconds = 0;
  g_object_get(track, "lost-time", &seconds, nullptr);
  return seconds;
}

// On the tracker's input: after --max-frames frames the stream ends there (EOS downstream; the
// pad then refuses further data, which stops the decoder), so no further frame is inferred.
GstPadProbeReturn limitFrames(GstPad* pad, GstPadProbeInfo*, gpointer data) {
  auto* run = static_cast<Run*>(data);
  if (run->max_frames == 0 || ++run->frames_in <= run->max_frames) return GST_PAD_PROBE_OK;
  if (run->frames_in == run->max_frames + 1) gst_pad_send_event(pad, gst_event_new_eos());
  return GST_PAD_PROBE_DROP;
}

// On the tracker's output: statistics, PoseTrack frames and MOT lines.
GstPadProbeReturn recordOutput(GstPad* pad, GstPadProbeInfo* info, gpointer data) {
  auto* run = static_cast<Run*>(data);
  GstBuffer* buffer = GST_PAD_PROBE_INFO_BUFFER(info);
  const GstJointFlowMeta* meta = gst_buffer_get_jointflow_meta(buffer);
  run->stats.record(meta);
  if (run->lag_log) run->lag_log->record(pad, buffer, meta && !meta->predicted);
  if (!run->posetrack && !run->mot) return GST_PAD_PROBE_OK;
  // Asked once per buffer: without timestamps the indexer counts the calls.
  const std::int64_t index = run->frame_indexer.index(pad, buffer);
  if (run->posetrack) run->posetrack->addFrame(index, meta);
  if (run->mot) {
    try {
      run->mot->addFrame(index, meta);
    } catch (const std::exception& e) {
      // A full disk must not pass silently: the run ends with the error.
      GST_ELEMENT_ERROR(GST_PAD_PARENT(pad), RESOURCE, WRITE, ("%s", e.what()), (nullptr));
      return GST_PAD_PROBE_DROP;
    }
  }
  return GST_PAD_PROBE_OK;
}

// Decoded frames into the entry (the leaky queue of a live input): the metrics' frames in.
GstPadProbeReturn countSourceFrame(GstPad*, GstPadProbeInfo*, gpointer data) {
  static_cast<Run*>(data)->source_frames++;
  return GST_PAD_PROBE_OK;
}

// The leaky queue is full as a frame comes: it drops the older one (max-size-buffers=1).
void onQueueOverrun(GstElement*, gpointer data) {
  static_cast<Run*>(data)->leaked_frames++;
}

gboolean onBusMessage(GstBus*, GstMessage* msg, gpointer data) {
  auto* run = static_cast<Run*>(data);
  switch (GST_MESSAGE_TYPE(msg)) {
    case GST_MESSAGE_ELEMENT: {
      const GstStructure* s = gst_message_get_structure(msg);
      if (run->metrics && s && gst_structure_has_name(s, "jointflowtrack-stats")) {
        run->metrics->setElementStats(s);
        updateProgramFigures(*run);
      }
      break;
    }
    case GST_MESSAGE_ERROR: {
      std::string fatal;
      if (run->live && run->live->handleError(msg, &fatal)) break;  // reconnecting
      if (!fatal.empty()) {
        if (run->error.empty()) run->error = fatal;
        g_main_loop_quit(run->loop);
        break;
      }
      GError* err = nullptr;
      gchar* debug = nullptr;
      gst_message_parse_error(msg, &err, &debug);
      if (run->error.empty()) {
        run->error = std::string(GST_OBJECT_NAME(GST_MESSAGE_SRC(msg))) + ": " + err->message;
        if (debug && g_getenv("JOINTFLOW_DEBUG")) run->error += std::string("\n  ") + debug;
      }
      g_clear_error(&err);
      g_free(debug);
      g_main_loop_quit(run->loop);
      break;
    }
    case GST_MESSAGE_EOS:
      g_main_loop_quit(run->loop);
      break;
    case GST_MESSAGE_LATENCY:
      // A source that joins a running pipeline (a reconnection) brings its own latency.
      gst_bin_recalculate_latency(GST_BIN(run->pipeline));
      break;
    default:
      break;
  }
  return TRUE;
}

}  // namespace

bool findPlugin(std::vector<std::string>& looked_in) {
  auto found = [] {
    GstElementFactory* f = gst_element_factory_find("jointflowtrack");
    if (f) gst_object_unref(f);
    return f != nullptr;
  };
  if (found()) return true;
  const char* env = g_getenv("GST_PLUGIN_PATH");
  looked_in.push_back(std::string("GST_PLUGIN_PATH (") + (env && *env ? env : "not set") +
                      ") and the system's plugin folders");
  std::vector<std::string> dirs;
  std::error_code ec;
  const fs::path program = fs::read_symlink("/proc/self/exe", ec);
  if (!ec)
    dirs.push_back(
        (program.parent_path() / JOINTFLOW_PLUGIN_FROM_PROGRAM).lexically_normal().string());
  dirs.push_back(JOINTFLOW_PLUGIN_BUILD_DIR);
  dirs.push_back(JOINTFLOW_PLUGIN_INSTALL_DIR);
  for (const std::string& dir : dirs) {
    if (std::find(looked_in.begin(), looked_in.end(), dir) != looked_in.end()) continue;
    looked_in.push_back(dir);
    if (!fs::is_directory(dir, ec)) continue;
    gst_registry_scan_path(gst_registry_get(), dir.c_str());
    if (found()) return true;
  }
  return false;
}

Run::~Run() {
  if (pipeline) {
    gst_element_set_state(pipeline, GST_STATE_NULL);
    live.reset();  // its probes and timers go before the pipeline they point into
    GstBus* bus = gst_element_get_bus(pipeline);
    gst_bus_remove_watch(bus);  // the watch holds a reference to the bus
    gst_object_unref(bus);
    gst_object_unref(pipeline);
  }
  if (loop) g_main_loop_unref(loop);
}

void buildPipeline(Run& run, const Input& input, const Outputs& out, GstElement* track,
                   int framerate, const ReconnectOptions& reconnect) {
  run.pipeline = gst_pipeline_new("jointflow-track");
  const bool live = !input.frames && isLiveUri(input.uri);
  GstElement* decode = nullptr;
  if (input.frames) {
    GstElement* src = make("multifilesrc");
    g_object_set(src, "location", input.frames->pattern.c_str(), "start-index", input.frames->first,
                 "stop-index", input.frames->last, "index", input.frames->first, nullptr);
    const std::string caps = input.frames->caps + ",framerate=" + std::to_string(framerate) + "/1";
    gst_util_set_object_arg(G_OBJECT(src), "caps", caps.c_str());
    run.folder_clock.frame_duration = gst_util_uint64_scale_int(GST_SECOND, 1, framerate);
    GstPad* pad = gst_element_get_static_pad(src, "src");
    gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_BUFFER, stampFolderFrames, &run.folder_clock,
                      nullptr);
    gst_object_unref(pad);
    decode = make("decodebin");
    gst_bin_add_many(GST_BIN(run.pipeline), src, decode, nullptr);
    gst_element_link(src, decode);
  } else if (!live) {
    decode = make("uridecodebin");
    g_object_set(decode, "uri", input.uri.c_str(), nullptr);
    gst_bin_add(GST_BIN(run.pipeline), decode);
  }
  std::vector<GstElement*> chain;
  if (live) {
    // A live source does not wait for us: keep only the newest frame while the tracker is busy,
    // so the delay stays one inference long (docs/gstreamer.md, live sources).
    GstElement* queue = make("queue");
    gst_util_set_object_arg(G_OBJECT(queue), "leaky", "downstream");
    g_object_set(queue, "max-size-buffers", 1u, "max-size-bytes", 0u, "max-size-time", guint64{0},
                 nullptr);
    g_signal_connect(queue, "overrun", G_CALLBACK(onQueueOverrun), &run);
    chain.push_back(queue);
  }
  chain.push_back(make("videoconvert"));
  chain.push_back(track);
  for (GstElement* e : chain) gst_bin_add(GST_BIN(run.pipeline), e);
  run.entry = chain.front();
  if (decode) {
    g_signal_connect(decode, "pad-added", G_CALLBACK(onPadAdded), &run);
  } else {
    // Made now only to throw, before the run, when it is missing.
    gst_object_unref(gst_object_ref_sink(make("uridecodebin")));
    const std::string uri = input.uri;
    const double timeout = reconnect.source_timeout;
    run.live = std::make_unique<LiveSource>(
        run.pipeline, run.entry,
        [&run, uri, timeout] {
          GstElement* source = gst_element_factory_make("uridecodebin", nullptr);
          // The decoder's asynchronous state change stays inside the source: a PLAYING pipeline
          // would otherwise lose its state (back to PAUSED) each time a source joins, and keep
          // it lost when that source fails before its decoder is ready, sinks and all.
          g_object_set(source, "uri", uri.c_str(), "async-handling", TRUE, nullptr);
          g_signal_connect(source, "pad-added", G_CALLBACK(onPadAdded), &run);
          g_signal_connect_data(
              source, "source-setup", G_CALLBACK(configureLiveSource), new double(timeout),
              [](gpointer t, GClosure*) { delete static_cast<double*>(t); }, GConnectFlags(0));
          return source;
        },
        input.description, reconnect, lostTime(track));
    run.live->on_give_up = [&run] {
      run.error = run.live->gaveUp();
      run.error_status = kExitSourceLost;
      g_main_loop_quit(run.loop);
    };
    run.live->addFirst();
  }
  if (!out.lag.empty()) {
    // A file's running time is a position in it, not a capture: it has no lag.
    if (!live) throw Error("--output-lag: only for live inputs (rtsp://, udp://, ...)");
    run.lag_log = std::make_unique<LagLog>(out.lag);
  }
  const size_t first_new = chain.size();
  if (!out.json.empty()) {
    GstElement* writer = make("jointflowjsonwriter");
    g_object_set(writer, "location", out.json.c_str(), nullptr);
    // The same source id as the publisher: the file then holds the published bytes.
    if (!out.publish.source_id.empty())
      g_object_set(writer, "source-id", out.publish.source_id.c_str(), nullptr);
    chain.push_back(writer);
  }
  if (GstElement* publisher = makePublisher(out.publish)) chain.push_back(publisher);
  if (!out.video.empty()) {
    const std::string ext = fs::path(out.video).extension().string();
    if (ext != ".mp4" && ext != ".mkv")
      throw Error("--output-video " + out.video + ": expected a .mp4 or .mkv file");
    GstElement* overlay = make("jointflowoverlay");
    g_object_set(overlay, "draw-boxes", out.draw_boxes, nullptr);
    GstElement* convert = make("videoconvert");
    GstElement* filter = make("capsfilter");
    // 4:2:0 is what players expect from H.264 (x264enc would pick 4:4:4 from RGB otherwise).
    GstCaps* i420 = gst_caps_from_string("video/x-raw,format=I420");
    g_object_set(filter, "caps", i420, nullptr);
    gst_caps_unref(i420);
    GstElement* encoder = make("x264enc");
    gst_util_set_object_arg(G_OBJECT(encoder), "speed-preset", "veryfast");
    GstElement* mux = make(ext == ".mp4" ? "mp4mux" : "matroskamux");
    GstElement* sink = make("filesink");
    g_object_set(sink, "location", out.video.c_str(), nullptr);
    chain.insert(chain.end(), {overlay, convert, filter, encoder, mux, sink});
  } else {
    GstElement* sink = make("fakesink");
    g_object_set(sink, "sync", FALSE, nullptr);
    chain.push_back(sink);
  }
  // A live pipeline goes to PLAYING at once, without waiting for its sink's first buffer (which
  // the encoder of --output-video holds back for dozens of frames): a source that reconnects
  // then always joins a PLAYING pipeline. One joining a pipeline still on its way to PLAYING made
  // it wait for the source's state change, which the source keeps to itself (async-handling),
  // for ever.
  if (live) g_object_set(chain.back(), "async", FALSE, nullptr);
  for (size_t i = first_new; i < chain.size(); ++i) gst_bin_add(GST_BIN(run.pipeline), chain[i]);
  for (size_t i = 0; i + 1 < chain.size(); ++i)
    if (!gst_element_link(chain[i], chain[i + 1]))
      throw Error(std::string("could not link ") + GST_ELEMENT_NAME(chain[i]) + " to " +
                  GST_ELEMENT_NAME(chain[i + 1]));

  GstPad* entry = gst_element_get_static_pad(run.entry, "sink");
  gst_pad_add_probe(entry, GST_PAD_PROBE_TYPE_BUFFER, countSourceFrame, &run, nullptr);
  gst_object_unref(entry);
  GstPad* in = gst_element_get_static_pad(track, "sink");
  gst_pad_add_probe(in, GST_PAD_PROBE_TYPE_BUFFER, limitFrames, &run, nullptr);
  gst_object_unref(in);
  GstPad* outpad = gst_element_get_static_pad(track, "src");
  gst_pad_add_probe(outpad, GST_PAD_PROBE_TYPE_BUFFER, recordOutput, &run, nullptr);
  gst_object_unref(outpad);

  run.loop = g_main_loop_new(nullptr, FALSE);
  GstBus* bus = gst_element_get_bus(run.pipeline);
  gst_bus_add_watch(bus, onBusMessage, &run);
  gst_object_unref(bus);
}

void updateProgramFigures(Run& run) {
  if (!run.metrics) return;
  ProgramFigures f;
  f.frames_in = run.source_frames;
  f.frames_dropped = run.leaked_frames;
  f.reconnects = run.live ? run.live->reconnections() : 0;
  if (GstElement* e = gst_bin_get_by_name(GST_BIN(run.pipeline), "publish")) {
    ProgramFigures::Publish p;
    guint64 published = 0, dropped = 0, refused = 0;
    g_object_get(e, "messages-published", &published, "messages-dropped", &dropped,
                 "messages-refused", &refused, "queue-depth", &p.queue_depth, nullptr);
    p.published = published;
    p.dropped = dropped;
    p.refused = refused;
    f.publish = p;
    gst_object_unref(e);
  }
  run.metrics->setProgram(f);
}

// SIGINT/SIGTERM (Ctrl-C, `systemctl stop`): the first ends the stream with an EOS, so that the
// outputs are completed and jointflowmetapublish flushes its queue; a second one stops at once.
static gboolean onStopSignal(gpointer data) {
  auto* run = static_cast<Run*>(data);
  if (!run->stopping) {
    run->stopping = true;
    g_printerr("jointflow-track: stopping at the end of the current frame\n");
    // A live input's EOS goes in behind its source, which may be gone or hanging in an outage.
    if (run->live) {
      if (!run->live->stop()) g_main_loop_quit(run->loop);
    } else {
      gst_element_send_event(run->pipeline, gst_event_new_eos());
    }
  } else {
    g_main_loop_quit(run->loop);
  }
  return G_SOURCE_CONTINUE;
}

double play(Run& run) {
  const auto start = std::chrono::steady_clock::now();
  const guint sigint = g_unix_signal_add(SIGINT, onStopSignal, &run);
  const guint sigterm = g_unix_signal_add(SIGTERM, onStopSignal, &run);
  // A failed state change posts its error on the bus; the loop ends on it.
  gst_element_set_state(run.pipeline, GST_STATE_PLAYING);
  g_main_loop_run(run.loop);
  g_source_remove(sigint);
  g_source_remove(sigterm);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  gst_element_set_state(run.pipeline, GST_STATE_NULL);
  return seconds;
}

void estimateTotalFrames(Run& run) {
  if (run.total_frames > 0) return;
  gint64 duration = 0;
  GstElement* track = gst_bin_get_by_name(GST_BIN(run.pipeline), "track");
  GstPad* pad = gst_element_get_static_pad(track, "sink");
  GstCaps* caps = gst_pad_get_current_caps(pad);
  gint num = 0, den = 1;
  if (caps &&
      gst_structure_get_fraction(gst_caps_get_structure(caps, 0), "framerate", &num, &den) &&
      num > 0 && gst_element_query_duration(run.pipeline, GST_FORMAT_TIME, &duration) &&
      duration > 0)
    run.total_frames = gst_util_uint64_scale(duration, num, static_cast<guint64>(den) * GST_SECOND);
  if (caps) gst_caps_unref(caps);
  gst_object_unref(pad);
  gst_object_unref(track);
  if (run.max_frames > 0 && (run.total_frames == 0 || run.total_frames > run.max_frames))
    run.total_frames = run.max_frames;
}

}  // namespace jointflow::cli
