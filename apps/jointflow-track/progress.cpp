// Progress and summary of jointflow-track (progress.hpp).
#include "progress.hpp"

#include <glib.h>

#include <algorithm>

namespace jointflow::cli {
namespace {

std::string clockText(double seconds) {
  const long s = static_cast<long>(seconds + 0.5);
  char text[32];
  std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
  return text;
}

}  // namespace

void showProgress(std::uint64_t done, std::uint64_t total, double elapsed) {
  const double fps = elapsed > 0 ? done / elapsed : 0;
  constexpr int kWidth = 30;
  std::string line;
  if (total > 0) {
    const double f = std::min(1.0, static_cast<double>(done) / total);
    const int filled = static_cast<int>(f * kWidth);
    line = "[" + std::string(filled, '#') + std::string(kWidth - filled, '.') + "] " +
           std::to_string(done) + "/" + std::to_string(total) + " frames";
  } else {
    line = std::to_string(done) + " frames";
  }
  char rate[96];
  std::snprintf(rate, sizeof rate, "  %.1f frames/s", fps);
  line += rate;
  if (total > done && fps > 0) line += "  ETA " + clockText((total - done) / fps);
  g_printerr("\r%-90s", line.c_str());
}

void printSummary(std::FILE* out, const RunCounts& c, double seconds,
                  const std::vector<std::pair<std::string, std::string>>& outputs) {
  std::fprintf(out, "frames:     %llu\n", static_cast<unsigned long long>(c.frames));
  std::fprintf(out, "people:     %llu detections, %.2f per frame\n",
               static_cast<unsigned long long>(c.detections),
               c.frames ? static_cast<double>(c.detections) / c.frames : 0.0);
  std::fprintf(out, "tracks:     %zu (%zu confirmed)\n", c.tracks, c.confirmed);
  std::fprintf(out, "frames/s:   %.2f (%.1f s)\n", seconds > 0 ? c.frames / seconds : 0.0, seconds);
  for (const auto& [what, file] : outputs)
    std::fprintf(out, "%-11s %s\n", (what + ":").c_str(), file.c_str());
}

}  // namespace jointflow::cli
