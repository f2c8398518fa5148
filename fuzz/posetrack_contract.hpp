// What the PoseTrack readers promise for any input, checked by the fuzz target
// (fuzz/posetrack_fuzz.cpp) and by the regression tests of the inputs it found
// (tests/hardening/test_fuzz_regressions.cpp).
//
// Any text either parses or throws jointflow::Error (jointflow/posetrack.hpp); anything else
// (another exception, a crash, a sanitizer report, a hang) is a bug. A parsed sequence survives
// being written in both formats and read back (or is refused by the writer with jointflow::Error),
// and scoring it against itself does not crash.
#pragma once

#include <stdexcept>
#include <string>

#include "jointflow/error.hpp"
#include "jointflow/evaluation.hpp"
#include "jointflow/posetrack.hpp"

namespace jointflow::fuzz {

/// Throws std::logic_error when the contract is broken; other exceptions escape as they are.
/// Returns whether the text was read as a sequence.
inline bool checkPoseTrackContract(const std::string& text) {
  posetrack::Sequence seq;
  try {
    seq = posetrack::parseSequence(text, "fuzz.json");
  } catch (const Error&) {
    return false;
  }
  for (const auto format : {posetrack::Format::k2017, posetrack::Format::k2018}) {
    std::string written;
    try {
      written = posetrack::toJson(seq, format);
    } catch (const Error&) {
      continue;  // the writer refuses ids poseval would refuse: a documented outcome
    }
    try {
      if (posetrack::parseSequence(written, seq.source).frames.size() != seq.frames.size())
        throw std::logic_error("a written sequence reads back with another number of frames");
    } catch (const Error& e) {
      throw std::logic_error(std::string("the reader refuses what the writer wrote: ") + e.what());
    }
  }
  try {
    (void)evaluatePoseTrack({seq}, {seq});
  } catch (const Error&) {
  }
  return true;
}

}  // namespace jointflow::fuzz
