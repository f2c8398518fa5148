// Where tests find models and data, and how a test that cannot run says so.
//
// Paths come from the environment: JOINTFLOW_DATA set by the user wins over the folder configured
// at `meson setup` (JOINTFLOW_DATA_CONFIGURED, set by tests/meson.build), so a user can point the
// tests elsewhere without reconfiguring. Data under ../shared/data is not ours to ship: tests that
// need it skip, saying why, when it is absent. A skipped case makes its test program exit 77
// (tests/catch_main.cpp), which meson reports as SKIP, never as passed; cases that need the data
// folder carry the tag [data] and run in the suites named "<suite>-data", so that the cases which
// need nothing still report their own result.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

namespace jointflow::test {

inline std::string envOr(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::string(v) : fallback;
}

inline std::string modelsDir() {
  return envOr("JOINTFLOW_MODELS_DIR", "models");
}
inline std::string dataDir() {
  return envOr("JOINTFLOW_DATA", envOr("JOINTFLOW_DATA_CONFIGURED", "../shared/data"));
}
inline std::string vtestPath() {
  return envOr("JOINTFLOW_VTEST", "/usr/share/doc/opencv-doc/examples/data/vtest.avi");
}
inline std::string sourceRoot() {
  return envOr("JOINTFLOW_SOURCE_ROOT", ".");
}

/// The reasons of the cases skipped so far in this process (read by tests/catch_main.cpp).
std::vector<std::string>& skipReasons();

}  // namespace jointflow::test

namespace jointflow::test {

/// Records that the running case cannot go on, with the reason: the program will exit 77 (SKIP).
inline void recordSkip(const std::string& reason) {
  WARN("SKIPPED: " << reason);
  skipReasons().push_back(reason);
}

/// Whether a data path is there; when not, the skip is recorded (for helpers that return a
/// value, where JF_REQUIRE_PATH_OR_SKIP cannot return from the case).
inline bool pathOrSkip(const std::string& path) {
  if (std::filesystem::exists(path)) return true;
  recordSkip(path +
             " is absent (set JOINTFLOW_DATA to the data folder, or install opencv-doc for "
             "vtest.avi)");
  return false;
}

}  // namespace jointflow::test

/// Skips the rest of a test case with a reason: the program will exit 77 (SKIP).
#define JF_SKIP(reason)                               \
  do {                                                \
    jointflow::test::recordSkip(std::string(reason)); \
    return;                                           \
  } while (0)

/// Skips the rest of a test case when a data path is absent.
#define JF_REQUIRE_PATH_OR_SKIP(path)                            \
  do {                                                           \
    if (!jointflow::test::pathOrSkip(std::string(path))) return; \
  } while (0)
