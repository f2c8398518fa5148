// Internal: constructors of the spatial model implementations (createSpatialModel picks one).
#pragma once

#include <memory>

#include "jointflow/spatial_model.hpp"
#include "net_spatial_model.hpp"

namespace jointflow::detail {

std::unique_ptr<SpatialModel> createMoveNet(const SpatialOptions& options);
std::unique_ptr<SpatialModel> createPoseNet(const SpatialOptions& options);
std::unique_ptr<SpatialModel> createOpenPose(const SpatialOptions& options);

}  // namespace jointflow::detail
