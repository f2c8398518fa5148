// Test helper: one frame of vtest.avi (opencv-doc), for the cases that run networks on real frames.
// Callers skip first where the file is absent (JF_REQUIRE_PATH_OR_SKIP(test::vtestPath())).
#pragma once

#include <opencv2/videoio.hpp>

#include "test_env.hpp"

namespace jointflow::test {

inline cv::Mat vtestFrame(int index) {
  cv::VideoCapture cap(vtestPath());
  REQUIRE(cap.isOpened());
  cap.set(cv::CAP_PROP_POS_FRAMES, index);
  cv::Mat frame;
  REQUIRE(cap.read(frame));
  return frame;
}

}  // namespace jointflow::test
