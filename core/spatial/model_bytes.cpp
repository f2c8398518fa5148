#include "jointflow/model_bytes.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <tuple>

#include "jointflow/error.hpp"

namespace jointflow {

ModelBytes sharedModelBytes(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (path.empty()) throw Error("model file: no path given");
  if (!fs::exists(path, ec)) throw Error("model file " + path + " does not exist");
  if (!fs::is_regular_file(path, ec)) throw Error("model file " + path + " is not a regular file");
  const auto canonical = fs::canonical(path, ec).string();
  const auto size = fs::file_size(path, ec);
  const auto mtime = fs::last_write_time(path, ec).time_since_epoch().count();
  if (ec) throw Error("model file " + path + " cannot be inspected: " + ec.message());

  using Key = std::tuple<std::string, std::uintmax_t, long long>;
  static std::mutex mutex;
  static std::map<Key, ModelBytes> cache;
  const Key key{canonical, size, static_cast<long long>(mtime)};
  std::lock_guard<std::mutex> lock(mutex);
  if (auto it = cache.find(key); it != cache.end()) return it->second;

  std::ifstream in(path, std::ios::binary);
  auto bytes = std::make_shared<std::vector<unsigned char>>(size);
  if (!in || !in.read(reinterpret_cast<char*>(bytes->data()), static_cast<std::streamsize>(size))) {
    throw Error("model file " + path + " cannot be read");
  }
  cache[key] = bytes;
  return bytes;
}

}  // namespace jointflow
