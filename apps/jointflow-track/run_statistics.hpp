// What a jointflow-track run saw, for the progress bar and the summary: counted in the streaming
// thread, read by the main loop.
#pragma once

#include <cstdint>
#include <mutex>
#include <set>

#include "jointflowmeta.h"

namespace jointflow::cli {

struct RunCounts {
  std::uint64_t frames = 0;
  std::uint64_t detections = 0;
  std::size_t tracks = 0;     ///< distinct track ids
  std::size_t confirmed = 0;  ///< of which reached min-track-length
};

class RunStatistics {
 public:
  /// One frame out of the tracker (meta may be null: no person).
  void record(const GstJointFlowMeta* meta);
  RunCounts counts() const;

 private:
  mutable std::mutex mutex_;
  std::uint64_t frames_ = 0;
  std::uint64_t detections_ = 0;
  std::set<std::int64_t> tracks_, confirmed_;
};

}  // namespace jointflow::cli
