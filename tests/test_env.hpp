// Where tests find models and data. Paths come from the environment that `meson test` sets
// (tests/meson.build), so a user can point them elsewhere. Data under ../shared/data is not ours
// to ship: tests that need it skip, saying why, when it is absent.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#include <catch2/catch.hpp>

namespace jointflow::test {

inline std::string envOr(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::string(v) : fallback;
}

inline std::string modelsDir() { return envOr("JOINTFLOW_MODELS_DIR", "models"); }
inline std::string dataDir() { return envOr("JOINTFLOW_DATA", "../shared/data"); }
inline std::string vtestPath() {
  return envOr("JOINTFLOW_VTEST", "/usr/share/doc/opencv-doc/examples/data/vtest.avi");
}
inline std::string sourceRoot() { return envOr("JOINTFLOW_SOURCE_ROOT", "."); }

}  // namespace jointflow::test

/// Skips the rest of a test case, with a visible reason, when a data path is absent.
#define JF_REQUIRE_PATH_OR_SKIP(path)                                                     \
  do {                                                                                    \
    if (!std::filesystem::exists(path)) {                                                 \
      WARN("SKIPPED: " << (path) << " is absent (set JOINTFLOW_DATA to the data folder)"); \
      return;                                                                             \
    }                                                                                     \
  } while (0)
