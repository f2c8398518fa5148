// The progress line (frames, frames/s, ETA) and the closing summary of jointflow-track.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "run_statistics.hpp"

namespace jointflow::cli {

/// "[#####.....] 120/300 frames  5.1 frames/s  ETA 0:35" on stderr, redrawn in place.
void showProgress(std::uint64_t done, std::uint64_t total, double elapsed_seconds);

/// The summary: frames, detections, tracks, frames/s, and each output written (`outputs` pairs
/// a label with a path). Goes to `out`: stderr when stdout carries the JSON Lines.
void printSummary(std::FILE* out, const RunCounts& counts, double seconds,
                  const std::vector<std::pair<std::string, std::string>>& outputs);

}  // namespace jointflow::cli
