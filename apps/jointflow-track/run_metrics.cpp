// Prometheus text format of a run's figures (run_metrics.hpp). Names follow Prometheus' rules:
// jointflow_ prefix, _total on counters, base unit seconds.
#include "run_metrics.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace jointflow::cli {
namespace {

class Page {
 public:
  void metric(const char* name, const char* type, const char* help) {
    out_ << "# HELP " << name << " " << help << "\n# TYPE " << name << " " << type << "\n";
  }
  void value(const std::string& name, double v, const std::string& labels = "") {
    out_ << name << (labels.empty() ? "" : "{" + labels + "}") << " " << number(v) << "\n";
  }
  void single(const char* name, const char* type, const char* help, double v) {
    metric(name, type, help);
    value(name, v);
  }
  // A histogram field of the element's message: cumulative buckets by bound, sum and count.
  void histogram(const char* name, const char* help, const GstStructure* stats, const char* field) {
    const GValue* v = gst_structure_get_value(stats, field);
    if (!v || G_VALUE_TYPE(v) != GST_TYPE_STRUCTURE) return;
    const GstStructure* h = gst_value_get_structure(v);
    const GValue* bounds = gst_structure_get_value(h, "bounds");
    const GValue* buckets = gst_structure_get_value(h, "buckets");
    guint64 count = 0;
    double sum = 0;
    if (!bounds || !buckets || !gst_structure_get_uint64(h, "count", &count) ||
        !gst_structure_get_double(h, "sum", &sum))
      return;
    metric(name, "histogram", help);
    const std::string bucket = std::string(name) + "_bucket";
    for (guint i = 0; i < gst_value_array_get_size(bounds); ++i)
      value(bucket, static_cast<double>(g_value_get_uint64(gst_value_array_get_value(buckets, i))),
            "le=\"" + number(g_value_get_double(gst_value_array_get_value(bounds, i))) + "\"");
    value(bucket, static_cast<double>(count), "le=\"+Inf\"");
    value(std::string(name) + "_sum", sum);
    value(std::string(name) + "_count", static_cast<double>(count));
  }
  std::string text() const { return out_.str(); }

  // Counts as integers, the rest with 15 digits (0.005, not 0.0050000000000000001).
  static std::string number(double v) {
    char buffer[32];
    if (v == std::floor(v) && std::fabs(v) < 9e15)
      std::snprintf(buffer, sizeof buffer, "%.0f", v);
    else
      std::snprintf(buffer, sizeof buffer, "%.15g", v);
    return buffer;
  }

 private:
  std::ostringstream out_;
};

// A label value: backslash, quote and newline escaped, as the format asks.
std::string label(const char* name, const char* value) {
  std::string v;
  for (const char* c = value ? value : ""; *c; ++c) {
    if (*c == '\\' || *c == '"') v += '\\';
    v += *c == '\n' ? std::string("\\n") : std::string(1, *c);
  }
  return std::string(name) + "=\"" + v + "\"";
}

guint64 u64(const GstStructure* s, const char* field) {
  guint64 v = 0;
  gst_structure_get_uint64(s, field, &v);
  return v;
}

guint u32(const GstStructure* s, const char* field) {
  guint v = 0;
  gst_structure_get_uint(s, field, &v);
  return v;
}

}  // namespace

RunMetrics::~RunMetrics() {
  if (element_) gst_structure_free(element_);
}

void RunMetrics::setElementStats(const GstStructure* stats) {
  GstStructure* copy = gst_structure_copy(stats);
  std::lock_guard<std::mutex> lock(mutex_);
  if (element_) gst_structure_free(element_);
  element_ = copy;
}

void RunMetrics::setProgram(const ProgramFigures& figures) {
  std::lock_guard<std::mutex> lock(mutex_);
  program_ = figures;
}

std::string RunMetrics::render() const {
  std::lock_guard<std::mutex> lock(mutex_);
  Page p;
  const ProgramFigures& f = program_;
  p.single("jointflow_frames_in_total", "counter", "Decoded frames from the source.",
           static_cast<double>(f.frames_in));
  p.single("jointflow_frames_dropped_total", "counter",
           "Frames dropped before the tracker while it was busy (a live source's leaky queue "
           "keeps the newest frame).",
           static_cast<double>(f.frames_dropped));
  p.single("jointflow_reconnects_total", "counter",
           "Reconnections of the live source that brought frames again.", f.reconnects);
  if (f.publish) {
    p.single("jointflow_publish_queue_depth", "gauge",
             "Messages waiting for the broker (jointflowmetapublish queue-depth).",
             f.publish->queue_depth);
    p.single("jointflow_publish_messages_published_total", "counter",
             "Messages the broker acknowledged (or written to the file).",
             static_cast<double>(f.publish->published));
    p.single("jointflow_publish_messages_dropped_total", "counter",
             "Messages not delivered: queue full, lost in flight, left at the end.",
             static_cast<double>(f.publish->dropped));
    p.single("jointflow_publish_messages_refused_total", "counter",
             "Messages larger than the largest the broker takes.",
             static_cast<double>(f.publish->refused));
  }
  const GstStructure* e = element_;
  p.metric("jointflow_build_info", "gauge",
           "The build and the models of this run (labels; value 1). Model labels appear with "
           "the tracker's first statistics.");
  std::string labels = label("version", JOINTFLOW_VERSION);
  if (e)
    for (const char* field : {"model-type", "spatial-model", "tff-model", "engine", "similarity"}) {
      std::string name = field;
      for (char& c : name) c = c == '-' ? '_' : c;
      labels += "," + label(name.c_str(), gst_structure_get_string(e, field));
    }
  p.value("jointflow_build_info", 1, labels);
  if (!e) return p.text();
  p.single("jointflow_frames_tracked_total", "counter", "Frames into the tracker.",
           static_cast<double>(u64(e, "frames")));
  p.single("jointflow_frames_inferred_total", "counter", "Frames the networks ran on.",
           static_cast<double>(u64(e, "frames-inferred")));
  p.single("jointflow_frames_predicted_total", "counter",
           "Frames whose poses were predicted (inference-interval, late frames).",
           static_cast<double>(u64(e, "frames-predicted")));
  p.single("jointflow_tracks_active", "gauge", "Tracks matched on the last inferred frame.",
           u32(e, "tracks-active"));
  p.single("jointflow_tracks_lost", "gauge",
           "Tracks not matched since, kept for lost-time (may be re-identified).",
           u32(e, "tracks-lost"));
  p.single("jointflow_tracks_created_total", "counter", "Track ids given out.",
           static_cast<double>(u64(e, "tracks-created")));
  double stream_time = 0;
  gst_structure_get_double(e, "stream-time", &stream_time);
  p.single("jointflow_stream_time_seconds", "gauge",
           "Stream time of the tracker's latest statistics (they are posted every "
           "stats-interval of it).",
           stream_time);
  p.histogram("jointflow_inference_seconds",
              "The streaming thread's time in the tracker per inferred frame (networks, "
              "decoding, association).",
              e, "inference-seconds");
  p.histogram("jointflow_element_seconds",
              "From a frame's arrival in the tracker to its leaving with its poses.", e,
              "element-seconds");
  p.histogram("jointflow_lag_seconds",
              "Live only: from a frame's capture (its running time on the pipeline clock) to its "
              "poses leaving the tracker.",
              e, "lag-seconds");
  p.histogram("jointflow_capture_lag_seconds",
              "Frames that carry the camera's capture time (an RTSP camera's RTCP sender "
              "reports): this host's wall clock when the poses leave the tracker minus that "
              "time; the camera's encoder and the network count too. Needs both clocks "
              "NTP-synchronised.",
              e, "capture-lag-seconds");
  return p.text();
}

}  // namespace jointflow::cli
