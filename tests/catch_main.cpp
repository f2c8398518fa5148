// The one Catch2 main shared by every test executable. Catch2 2.13 has no "skipped" result: a
// case that cannot run records its reason (JF_SKIP in test_env.hpp) and returns, and this main
// turns any recorded skip into exit status 77, which meson reports as SKIP with the reasons in
// the test's log. A failure still wins: its status is returned as Catch2 gives it.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <cstdio>

#include "test_env.hpp"

namespace jointflow::test {

std::vector<std::string>& skipReasons() {
  static std::vector<std::string> reasons;
  return reasons;
}

}  // namespace jointflow::test

int main(int argc, char** argv) {
  const int status = Catch::Session().run(argc, argv);
  const auto& skipped = jointflow::test::skipReasons();
  if (status != 0 || skipped.empty()) return status;
  std::printf("SKIP: %zu test case(s) could not run:\n", skipped.size());
  for (const std::string& reason : skipped) std::printf("SKIP:   %s\n", reason.c_str());
  return 77;
}
