// backend "openvino" where OpenVINO cannot be had: a build without it, or a machine where the
// engine module or OpenVINO's libraries are gone (JOINTFLOW_OPENVINO_MODULE points elsewhere;
// tests/engine/meson.build). Either way the error says which package to install.
#include <catch2/catch.hpp>

#include "../test_env.hpp"
#include "jointflow/error.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow/tracker.hpp"

using namespace jointflow;

TEST_CASE("backend openvino without OpenVINO says how to get it") {
  SpatialOptions o;
  EngineOptions engine;
  engine.backend = DnnBackend::kOpenVino;
  CHECK_THROWS_WITH(createSpatialModel(ModelType::kMoveNet, o, engine),
                    Catch::Contains("PyPI package openvino") && Catch::Contains("make build"));
  // cv::dnn still runs.
  engine.backend = DnnBackend::kDefault;
  CHECK(createSpatialModel(ModelType::kMoveNet, o, engine)->engine().rfind("cv::dnn", 0) == 0);
}
