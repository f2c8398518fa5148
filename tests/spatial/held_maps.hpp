// A frame's maps stay as they were while the caller holds them: the engines reuse their buffers
// (core/engine/mat_pool.hpp), and a tracker keeps the maps of the frame before. Shared by the
// cv::dnn (real_models_test.cpp) and OpenVINO (tests/engine/test_openvino.cpp) cases.
#pragma once

#include <catch2/catch.hpp>

#include <vector>

#include "jointflow/spatial_model.hpp"

namespace jointflow::test {

/// Runs `frames` (at least 3, different) through submit()/collect() with a frame in flight, as
/// the element does, holding every result; then checks that each result's maps still equal
/// their copies taken when it came, and that they are not one buffer shared between frames.
inline void checkHeldMapsKept(SpatialModel& model, const std::vector<cv::Mat>& frames) {
  REQUIRE(frames.size() >= 3);
  std::vector<SpatialResult> held;
  std::vector<cv::Mat> features, beliefs;
  auto collect = [&] {
    held.push_back(model.collect());
    features.push_back(held.back().features.clone());
    beliefs.push_back(held.back().beliefs.clone());
  };
  for (size_t i = 0; i < frames.size(); ++i) {
    model.submit(frames[i]);
    if (i > 0) collect();
  }
  collect();
  for (size_t i = 0; i < held.size(); ++i) {
    INFO("frame " << i);
    CHECK(cv::norm(held[i].features, features[i], cv::NORM_INF) == 0.0);
    CHECK(cv::norm(held[i].beliefs, beliefs[i], cv::NORM_INF) == 0.0);
    if (i > 0) {
      CHECK(held[i].features.data != held[i - 1].features.data);
      CHECK(cv::norm(held[i].beliefs, held[i - 1].beliefs, cv::NORM_INF) > 0.0);
    }
  }
}

}  // namespace jointflow::test
