// The figures of a jointflow-track run for --metrics-port, in Prometheus' text format: those of
// the tracker, from jointflowtrack's "jointflowtrack-stats" messages (the one source of the
// element's figures, which applications embedding the element read the same way), and those of
// the program around it: frames from the source and dropped by the leaky queue before the
// tracker, reconnections, the publisher's queue. The main loop updates it; the HTTP thread reads
// it.
#pragma once

#include <gst/gst.h>

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

namespace jointflow::cli {

/// The program's own figures at one moment.
struct ProgramFigures {
  std::uint64_t frames_in = 0;       ///< decoded frames from the source
  std::uint64_t frames_dropped = 0;  ///< dropped by the leaky queue (newest frame taken)
  std::uint32_t reconnects = 0;      ///< reconnections that brought frames again (live input)
  struct Publish {
    std::uint64_t published = 0, dropped = 0, refused = 0;
    unsigned queue_depth = 0;
  };
  std::optional<Publish> publish;  ///< with --publish
};

class RunMetrics {
 public:
  RunMetrics() = default;
  ~RunMetrics();
  RunMetrics(const RunMetrics&) = delete;
  RunMetrics& operator=(const RunMetrics&) = delete;

  /// A "jointflowtrack-stats" structure (copied): the element's latest figures.
  void setElementStats(const GstStructure* stats);
  void setProgram(const ProgramFigures& figures);

  /// The page of /metrics. The element's figures appear with its first message.
  std::string render() const;

 private:
  mutable std::mutex mutex_;
  GstStructure* element_ = nullptr;
  ProgramFigures program_;
};

}  // namespace jointflow::cli
