// jointflowtrack's statistics: what it counts and times while it runs, and the element message
// "jointflowtrack-stats" it posts every stats-interval seconds of stream time (its fields are
// listed in docs/gstreamer.md, "Statistics message"). jointflow-track builds its Prometheus
// /metrics from these messages, so that an application embedding the element and the program
// report the same figures.
#pragma once

#include <gst/gst.h>

#include <cstdint>
#include <string>
#include <vector>

#include "jointflow/tracker.hpp"

namespace jointflow::gst {

/// Durations in seconds in fixed buckets, as a Prometheus histogram holds them.
class SecondsHistogram {
 public:
  /// The buckets' upper bounds (s): from 5 ms (a fast inference) to 10 s (a stalled pipeline).
  static const std::vector<double>& bounds();

  void observe(double seconds);
  std::uint64_t count() const { return count_; }
  double sum() const { return sum_; }
  /// Observations <= bounds()[i], cumulative as Prometheus' `le` buckets are.
  std::vector<std::uint64_t> cumulative() const;

  /// "histogram, bounds=<...>, buckets=<...>, count=(guint64), sum=(double)": bounds and
  /// cumulative counts as arrays of the same length (the +Inf bucket is `count`).
  GstStructure* toStructure() const;

 private:
  std::vector<std::uint64_t> counts_ = std::vector<std::uint64_t>(bounds().size(), 0);
  std::uint64_t count_ = 0;
  double sum_ = 0.0;
};

/// What the models are, for the message's info fields.
struct ModelInfo {
  std::string model_type, spatial_model, tff_model, engine, similarity;
};

/// The element's figures since it started (READY -> PAUSED); the streaming thread's own.
struct TrackStats {
  std::uint64_t frames = 0;     ///< buffers into the element
  std::uint64_t inferred = 0;   ///< of which the networks ran on
  std::uint64_t predicted = 0;  ///< of which were predicted (inference-interval, late frames)
  TrackCounts tracks;           ///< after the last frame
  /// The streaming thread's time in the tracker per inferred frame (submit + collect).
  SecondsHistogram inference;
  /// From a frame's arrival in the element to its leaving with its poses.
  SecondsHistogram element;
  /// Live pipelines only: clock time at the frame's leaving minus its running time (its capture
  /// on the pipeline clock, as the live source stamped it).
  SecondsHistogram lag;
  /// Frames that carry the camera's capture time (frame_lag.hpp): this host's wall clock at the
  /// frame's leaving minus that time, so the camera's encoder and the network count too.
  SecondsHistogram capture_lag;
  bool live = false;       ///< upstream answered the latency query as live
  double stream_time = 0;  ///< the last frame's, in seconds
  ModelInfo model;
};

/// The element message's structure ("jointflowtrack-stats").
GstStructure* statsStructure(const TrackStats& stats);

}  // namespace jointflow::gst
