// The lookup of the shipped models; model_files.hpp gives the order and why.
#include "jointflow/model_files.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace jointflow {
namespace {

namespace fs = std::filesystem;

// Set by core/meson.build: the installed models relative to the folder of the library holding
// the core and to the folder of an installed program (relative, so that a copied or moved prefix
// works), the source tree's models/, and the build folders whose files are not an install.
#ifndef JOINTFLOW_MODELS_FROM_LIBRARY
#define JOINTFLOW_MODELS_FROM_LIBRARY "../share/jointflow/models"
#endif
#ifndef JOINTFLOW_MODELS_FROM_PROGRAM
#define JOINTFLOW_MODELS_FROM_PROGRAM "../share/jointflow/models"
#endif
#ifndef JOINTFLOW_SOURCE_MODELS_DIR
#define JOINTFLOW_SOURCE_MODELS_DIR "models"
#endif
#ifndef JOINTFLOW_CORE_BUILD_DIR
#define JOINTFLOW_CORE_BUILD_DIR ""
#endif
#ifndef JOINTFLOW_BUILD_ROOT
#define JOINTFLOW_BUILD_ROOT ""
#endif

constexpr const char* kMoveNet = "movenet_multipose.onnx";

// The path with symbolic links resolved where it exists (a program started through a link in
// /usr/local/bin belongs to the prefix the link points into), else as given, made tidy.
fs::path resolved(const fs::path& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(p, ec);
  return ec ? p.lexically_normal() : r;
}

bool inside(const fs::path& path, const std::string& folder) {
  if (folder.empty()) return false;
  const fs::path rel = path.lexically_relative(resolved(folder));
  return !rel.empty() && *rel.begin() != "..";
}

// The file of the library (or the program, where the core is linked in statically) that holds
// this function: the core's own install, whichever program or plugin loaded it.
fs::path coreLibrary() {
  Dl_info info{};
  if (!dladdr(reinterpret_cast<void*>(&modelFolders), &info) || !info.dli_fname || !*info.dli_fname)
    return {};
  return resolved(info.dli_fname);
}

fs::path runningProgram() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe;
}

}  // namespace

std::vector<ModelFolder> modelFolders() {
  if (const char* env = std::getenv("JOINTFLOW_MODELS_DIR"); env && *env)
    return {{env, "$JOINTFLOW_MODELS_DIR; while it is set no other folder is looked in"}};
  std::vector<ModelFolder> folders;
  const fs::path library = coreLibrary();
  // A library or program of the build folder is no install: its models are the source tree's.
  if (!library.empty() && resolved(library.parent_path()) != resolved(JOINTFLOW_CORE_BUILD_DIR))
    folders.push_back(
        {(library.parent_path() / JOINTFLOW_MODELS_FROM_LIBRARY).lexically_normal().string(),
         "installed with " + library.string()});
  const fs::path program = runningProgram();
  if (!program.empty() && program != library && !inside(program, JOINTFLOW_BUILD_ROOT)) {
    const std::string dir =
        (program.parent_path() / JOINTFLOW_MODELS_FROM_PROGRAM).lexically_normal().string();
    if (folders.empty() || folders.front().path != dir)
      folders.push_back({dir, "installed with " + program.string()});
  }
  folders.push_back({JOINTFLOW_SOURCE_MODELS_DIR, "the source tree the core was built from"});
  return folders;
}

std::string findShippedModel(const std::string& file) {
  for (const ModelFolder& folder : modelFolders()) {
    const fs::path path = fs::path(folder.path) / file;
    std::error_code ec;
    if (fs::is_regular_file(path, ec)) return path.string();
  }
  return "";
}

std::string shippedModelMissing(const std::string& file) {
  std::string looked;
  for (const ModelFolder& folder : modelFolders())
    looked += (looked.empty() ? "" : ", ") + folder.path + " (" + folder.origin + ")";
  return "no models folder has " + file + " (looked in " + looked + ")";
}

std::string defaultModelsDir() {
  const std::string movenet = findShippedModel(kMoveNet);
  if (!movenet.empty()) return fs::path(movenet).parent_path().string();
  return modelFolders().front().path;
}

}  // namespace jointflow
