// libFuzzer target: the PoseTrack 2017 / 2018 readers, the writer and the evaluation on whatever
// the readers accept (the contract is in posetrack_contract.hpp). Build and run: fuzz/fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <string>

#include "posetrack_contract.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A broken contract throws; libFuzzer reports the uncaught exception as a crash with the input.
  jointflow::fuzz::checkPoseTrackContract(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
