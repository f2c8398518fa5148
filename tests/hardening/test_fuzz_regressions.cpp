// Every input the fuzzer (fuzz/fuzz.sh) found crashing or hanging, kept in fuzz_regressions/, must
// now keep the readers' contract (fuzz/posetrack_contract.hpp). Some are also checked for the
// exact outcome the fix gives.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "jointflow/error.hpp"
#include "jointflow/posetrack.hpp"
#include "posetrack_contract.hpp"
#include "test_env.hpp"

using namespace jointflow;
namespace fs = std::filesystem;

namespace {

fs::path regressions() {
  return fs::path(test::sourceRoot()) / "tests/hardening/fuzz_regressions";
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST_CASE("every input the fuzzer found keeps the PoseTrack readers' contract",
          "[hardening][fuzz]") {
  JF_REQUIRE_PATH_OR_SKIP(regressions().string());
  int count = 0;
  for (const auto& entry : fs::directory_iterator(regressions())) {
    INFO(entry.path().filename().string());
    CHECK_NOTHROW(fuzz::checkPoseTrackContract(slurp(entry.path())));
    ++count;
  }
  CHECK(count > 0);
}

TEST_CASE("fuzz findings give the message the fix gives", "[hardening][fuzz]") {
  JF_REQUIRE_PATH_OR_SKIP(regressions().string());
  // A number beyond double ("21e400") used to escape as nlohmann's out_of_range.
  CHECK_THROWS_WITH(
      posetrack::parseSequence(slurp(regressions() / "number_overflow.json"), "a.json"),
      Catch::Contains("a.json") && Catch::Contains("not valid JSON") && Catch::Contains("21e400"));
  // A head box of finite numbers whose corner x + w overflows used to be read, then written back
  // as null, which the reader refuses (found by the fuzz target's round trip).
  CHECK_THROWS_WITH(
      posetrack::parseSequence(slurp(regressions() / "head_box_overflow.json"), "b.json"),
      Catch::Contains("b.json: annotations[0].bbox_head") && Catch::Contains("finite"));
}
