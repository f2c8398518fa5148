// Loads the OpenVINO engine module (libjointflow-openvino.so, openvino_network.cpp) on first use.
//
// The core does not link OpenVINO: a program that never asks for backend "openvino" does not pay
// for loading its ~60 MB of libraries, and a machine without them still runs cv::dnn. When the
// module or OpenVINO's own libraries cannot be loaded, the error says which package to install.
#include <dlfcn.h>

#include <filesystem>
#include <mutex>

#include "jointflow/error.hpp"
#include "network.hpp"
#include "openvino_module.hpp"

namespace jointflow::detail {
namespace {

#ifdef JOINTFLOW_HAVE_OPENVINO
constexpr const char* kHowToGet =
    "OpenVINO comes from the PyPI package openvino==" JOINTFLOW_OPENVINO_VERSION
    ", which `make build` installs into the build folder (scripts/openvino-venv.sh BUILD)";

// The module sits beside libjointflow-core.so, in the build tree and once installed.
std::string modulePath() {
  if (const char* env = std::getenv("JOINTFLOW_OPENVINO_MODULE"); env && *env) return env;
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&openOpenVinoNetwork), &info) && info.dli_fname)
    return (std::filesystem::path(info.dli_fname).parent_path() / "libjointflow-openvino.so")
        .string();
  return "libjointflow-openvino.so";
}

OpenVinoOpenFn loadModule() {
  static std::once_flag once;
  static OpenVinoOpenFn open = nullptr;
  static std::string failure;
  std::call_once(once, [] {
    const std::string path = modulePath();
    // RTLD_LOCAL: OpenVINO's symbols stay out of the global namespace of the process.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = dlerror();
      failure = "backend \"openvino\": cannot load the OpenVINO engine " + path + " (" +
                (why ? why : "unknown reason") + "). " + kHowToGet;
      return;
    }
    open = reinterpret_cast<OpenVinoOpenFn>(dlsym(handle, kOpenVinoOpenSymbol));
    if (!open) failure = "backend \"openvino\": " + path + " lacks " + kOpenVinoOpenSymbol;
  });
  if (!open) throw Error(failure);
  return open;
}
#endif

}  // namespace

std::unique_ptr<Network> openOpenVinoNetwork(const std::string& path, const EngineOptions& dnn) {
#ifdef JOINTFLOW_HAVE_OPENVINO
  return std::unique_ptr<Network>(loadModule()(path, dnn));
#else
  (void)dnn;
  throw Error("backend \"openvino\" (for " + path +
              "): this JointFlow build has no OpenVINO engine. Install the PyPI package openvino "
              "(2026.x) and rebuild: `make build` installs it into the build folder and "
              "configures with it (meson option -Dopenvino=enabled makes it required)");
#endif
}

}  // namespace jointflow::detail
