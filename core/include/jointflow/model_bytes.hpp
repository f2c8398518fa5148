// Reading ONNX files once per process.
//
// Several SpatialModel instances in one process (e.g. one GStreamer element per stream) each
// need their own cv::dnn::Net, which is not thread-safe; they can share the file's bytes, so
// that only the first instance reads the file and later ones parse it from memory.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace jointflow {

using ModelBytes = std::shared_ptr<const std::vector<unsigned char>>;

/// The bytes of a model file, read on first use and kept for the process's lifetime, keyed by
/// canonical path, size and modification time (a rewritten file is read again). Thread-safe.
/// Throws jointflow::Error naming the file when it is missing, not a file or unreadable.
ModelBytes sharedModelBytes(const std::string& path);

}  // namespace jointflow
