// Where the core looks for the shipped models (core/include/jointflow/model_files.hpp): the
// environment variable alone when set, else the install beside the core (none here: the library
// and this program are the build folder's) and the source tree; errors that list every folder.
// The install itself is run by tests/install (a moved prefix, the source tree hidden).
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include <catch2/catch.hpp>

#include "../test_env.hpp"
#include "jointflow/error.hpp"
#include "jointflow/model_files.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow/tracker.hpp"

namespace fs = std::filesystem;
using namespace jointflow;

namespace {

// Sets (or, with nullopt, unsets) JOINTFLOW_MODELS_DIR for one case and puts it back after.
class ModelsDirEnv {
 public:
  explicit ModelsDirEnv(const std::optional<std::string>& value) {
    if (const char* v = std::getenv("JOINTFLOW_MODELS_DIR")) saved_ = v;
    if (value)
      ::setenv("JOINTFLOW_MODELS_DIR", value->c_str(), 1);
    else
      ::unsetenv("JOINTFLOW_MODELS_DIR");
  }
  ~ModelsDirEnv() {
    if (saved_)
      ::setenv("JOINTFLOW_MODELS_DIR", saved_->c_str(), 1);
    else
      ::unsetenv("JOINTFLOW_MODELS_DIR");
  }

 private:
  std::optional<std::string> saved_;
};

// A folder of its own holding @files as links to the shipped models, removed after the case.
struct ModelsFolder {
  fs::path dir;
  explicit ModelsFolder(std::initializer_list<const char*> files)
      : dir(fs::temp_directory_path() /
            ("jf-models-" + std::to_string(::getpid()) + "-" + std::to_string(count()++))) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const char* f : files)
      fs::create_symlink(fs::absolute(fs::path(test::sourceRoot()) / "models" / f), dir / f);
  }
  ~ModelsFolder() { fs::remove_all(dir); }
  static int& count() {
    static int n = 0;
    return n;
  }
};

}  // namespace

TEST_CASE("JOINTFLOW_MODELS_DIR, when set, is the only folder looked in", "[models-dir]") {
  ModelsFolder folder({"movenet_multipose.onnx"});
  ModelsDirEnv env(folder.dir.string());
  const auto folders = modelFolders();
  REQUIRE(folders.size() == 1);
  CHECK(folders[0].path == folder.dir.string());
  CHECK(findShippedModel("movenet_multipose.onnx") == (folder.dir / "movenet_multipose.onnx"));
  CHECK(defaultModelsDir() == folder.dir.string());
  // The source tree has tff_movenet.onnx, but a folder chosen on purpose is not mixed with it.
  CHECK(findShippedModel("tff_movenet.onnx").empty());
  CHECK_THAT(shippedModelMissing("tff_movenet.onnx"),
             Catch::Contains("no models folder has tff_movenet.onnx") &&
                 Catch::Contains(folder.dir.string() + " ($JOINTFLOW_MODELS_DIR"));
}

TEST_CASE("Unset, the build folder's core finds the source tree's models", "[models-dir]") {
  ModelsDirEnv env(std::nullopt);
  const auto folders = modelFolders();
  // The library and this program are in the build folder, which is no install: only the source.
  REQUIRE(folders.size() == 1);
  CHECK(fs::equivalent(folders.back().path, fs::path(test::sourceRoot()) / "models"));
  CHECK_THAT(folders.back().origin, Catch::Contains("source tree"));
  CHECK(fs::equivalent(findShippedModel("movenet_multipose.onnx"),
                       fs::path(test::sourceRoot()) / "models" / "movenet_multipose.onnx"));
  CHECK(findShippedModel("no_such_model.onnx").empty());
}

TEST_CASE("A missing shipped model is an error that lists every folder looked in", "[models-dir]") {
  ModelsFolder folder({"movenet_multipose.onnx"});
  {
    ModelsFolder empty({});
    ModelsDirEnv env(empty.dir.string());
    CHECK_THROWS_WITH(createSpatialModel(ModelType::kMoveNet, {}),
                      Catch::Contains("no models folder has movenet_multipose.onnx (looked in " +
                                      empty.dir.string() + " ($JOINTFLOW_MODELS_DIR") &&
                          Catch::Contains("set JOINTFLOW_MODELS_DIR"));
  }
  // tff needs the TFF network, which this folder lacks; the spatial model is there.
  ModelsDirEnv env(folder.dir.string());
  TrackerSettings s;
  s.similarity = SimilarityType::kTff;
  CHECK_THROWS_WITH(Tracker(s), Catch::Contains("similarity \"tff\" needs a TFF model") &&
                                    Catch::Contains("no models folder has tff_movenet.onnx") &&
                                    Catch::Contains(folder.dir.string()));
  // auto without the network: oks on every frame, no error.
  s.similarity = SimilarityType::kAuto;
  bool has_tff = true;
  CHECK_NOTHROW(has_tff = Tracker(s).hasTff());
  CHECK_FALSE(has_tff);
}
