// Where the shipped models (movenet_multipose.onnx, posenet_mobilenetv1.onnx, tff_movenet.onnx)
// are found. This is the one place that decides it; docs/deploy.md ("Where the models are
// found") says the same for users.
//
// A model file named in the settings (SpatialOptions::model_path, TrackerSettings::tff_model: the
// properties spatial-model and tff-model, --spatial-model and --tff-model) is used as it is and
// nothing is looked up. Otherwise the shipped file is looked for in these folders, in order:
//   1. $JOINTFLOW_MODELS_DIR, when set and not empty: then it is the only folder looked in, so
//      that models chosen on purpose are never silently replaced by the shipped ones;
//   2. the install beside the library that holds the core: for <prefix>/<libdir>/
//      libjointflow-core.so, <prefix>/<datadir>/jointflow/models (share/jointflow/models), found
//      with dladdr, so that the core finds its own install wherever the prefix was copied or
//      moved, whichever program or plugin loaded it. In a Python wheel, where the core is linked
//      into jointflow/_jointflow*.so, the folder models/ beside that module;
//   3. the install beside the running program (/proc/self/exe): for <prefix>/<bindir>/program,
//      <prefix>/<datadir>/jointflow/models, where it is not the folder of 2;
//   4. the source tree's models/ the core was built from, for developers running from build/.
// A file that no folder has is an Error that lists every folder looked in, and why each.
#pragma once

#include <string>
#include <vector>

namespace jointflow {

/// A folder looked in for the shipped models, and where it comes from (for messages).
struct ModelFolder {
  std::string path;
  std::string origin;  ///< e.g. "$JOINTFLOW_MODELS_DIR", "installed with /usr/lib/libx.so"
};

/// The folders looked in for a shipped model, in the order above.
std::vector<ModelFolder> modelFolders();

/// The shipped model @file (e.g. "movenet_multipose.onnx") in the first of modelFolders() that
/// has it; "" when none has it.
std::string findShippedModel(const std::string& file);

/// "no models folder has FILE (looked in A (origin), B (origin), ...)": the start of what to say
/// when findShippedModel(@file) is "" (the caller adds what to set).
std::string shippedModelMissing(const std::string& file);

/// The folder of the shipped MoveNet model as findShippedModel finds it; where no folder has it,
/// the first folder looked in.
std::string defaultModelsDir();

}  // namespace jointflow
