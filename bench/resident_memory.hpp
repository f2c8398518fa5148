// The process's resident memory, for the benchmarks that watch memory (soak, jointflow-bench).
#pragma once

#include <fstream>
#include <string>

namespace jointflow::bench {

/// VmRSS of this process in KiB (Linux /proc/self/status); -1 where unknown.
inline long residentKiB() {
  std::ifstream in("/proc/self/status");
  std::string key;
  while (in >> key) {
    if (key == "VmRSS:") {
      long kib = -1;
      in >> kib;
      return kib;
    }
    in.ignore(1 << 12, '\n');
  }
  return -1;
}

}  // namespace jointflow::bench
