// Internal: constructors of the spatial model implementations (createSpatialModel picks one).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "jointflow/error.hpp"
#include "jointflow/spatial_model.hpp"
#include "net_spatial_model.hpp"

namespace jointflow::detail {

std::unique_ptr<SpatialModel> createMoveNet(const SpatialOptions& options,
                                            const EngineOptions& engine);
std::unique_ptr<SpatialModel> createPoseNet(const SpatialOptions& options,
                                            const EngineOptions& engine);
std::unique_ptr<SpatialModel> createOpenPose(const SpatialOptions& options,
                                             const EngineOptions& engine);
std::unique_ptr<SpatialModel> createYoloPose(const SpatialOptions& options,
                                             const EngineOptions& engine);

/// The opt-in YOLO pose model that `make models-yolo` writes, opt-in/yolo11n_pose.onnx in the
/// models folders (model_files.hpp). Throws jointflow::Error saying how to install it, and under
/// which licence, where it is absent: it is never shipped (its weights are AGPL-3.0).
std::string yoloOptInModelOrThrow();

/// The type whose outputs `outs` holds; kAuto for none.
ModelType modelTypeOfOutputs(const std::vector<std::string>& outs);

/// `e`, the failure to load options.model_path as a `chosen` model, with the type that the
/// file's outputs say it is where that is another one, and how to choose it.
Error withModelTypeHint(const Error& e, ModelType chosen, const SpatialOptions& options,
                        const EngineOptions& engine);

}  // namespace jointflow::detail
