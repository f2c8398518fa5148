// jointflowtrack's statistics message (track_stats.hpp).
#include "track_stats.hpp"

#include <algorithm>

namespace jointflow::gst {

const std::vector<double>& SecondsHistogram::bounds() {
  static const std::vector<double> b{0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10};
  return b;
}

void SecondsHistogram::observe(double seconds) {
  const auto& b = bounds();
  const auto it = std::lower_bound(b.begin(), b.end(), seconds);  // le: bound >= seconds
  if (it != b.end()) counts_[static_cast<size_t>(it - b.begin())]++;
  count_++;
  sum_ += seconds;
}

std::vector<std::uint64_t> SecondsHistogram::cumulative() const {
  std::vector<std::uint64_t> c(counts_.size());
  std::uint64_t total = 0;
  for (size_t i = 0; i < counts_.size(); ++i) c[i] = total += counts_[i];
  return c;
}

namespace {

template <typename T>
void setArray(GstStructure* s, const char* field, GType type, const std::vector<T>& values) {
  GValue array = G_VALUE_INIT;
  gst_value_array_init(&array, static_cast<guint>(values.size()));
  for (const T& v : values) {
    GValue item = G_VALUE_INIT;
    g_value_init(&item, type);
    if constexpr (std::is_same_v<T, double>)
      g_value_set_double(&item, v);
    else
      g_value_set_uint64(&item, v);
    gst_value_array_append_and_take_value(&array, &item);
  }
  gst_structure_take_value(s, field, &array);
}

void setHistogram(GstStructure* s, const char* field, const SecondsHistogram& h) {
  GstStructure* sub = h.toStructure();
  gst_structure_set(s, field, GST_TYPE_STRUCTURE, sub, nullptr);
  gst_structure_free(sub);
}

}  // namespace

GstStructure* SecondsHistogram::toStructure() const {
  GstStructure* s =
      gst_structure_new("histogram", "count", G_TYPE_UINT64, static_cast<guint64>(count_), "sum",
                        G_TYPE_DOUBLE, sum_, nullptr);
  setArray(s, "bounds", G_TYPE_DOUBLE, bounds());
  setArray(s, "buckets", G_TYPE_UINT64, cumulative());
  return s;
}

GstStructure* statsStructure(const TrackStats& st) {
  GstStructure* s = gst_structure_new(
      "jointflowtrack-stats", "stream-time", G_TYPE_DOUBLE, st.stream_time, "frames", G_TYPE_UINT64,
      static_cast<guint64>(st.frames), "frames-inferred", G_TYPE_UINT64,
      static_cast<guint64>(st.inferred), "frames-predicted", G_TYPE_UINT64,
      static_cast<guint64>(st.predicted), "tracks-active", G_TYPE_UINT,
      static_cast<guint>(st.tracks.active), "tracks-lost", G_TYPE_UINT,
      static_cast<guint>(st.tracks.lost), "tracks-created", G_TYPE_UINT64,
      static_cast<guint64>(st.tracks.created), "live", G_TYPE_BOOLEAN, st.live, "version",
      G_TYPE_STRING, JOINTFLOW_VERSION, "model-type", G_TYPE_STRING, st.model.model_type.c_str(),
      "spatial-model", G_TYPE_STRING, st.model.spatial_model.c_str(), "tff-model", G_TYPE_STRING,
      st.model.tff_model.c_str(), "engine", G_TYPE_STRING, st.model.engine.c_str(), "similarity",
      G_TYPE_STRING, st.model.similarity.c_str(), nullptr);
  setHistogram(s, "inference-seconds", st.inference);
  setHistogram(s, "element-seconds", st.element);
  if (st.live) setHistogram(s, "lag-seconds", st.lag);
  if (st.capture_lag.count() > 0) setHistogram(s, "capture-lag-seconds", st.capture_lag);
  return s;
}

}  // namespace jointflow::gst
