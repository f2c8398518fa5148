// The tests' RTSP camera: jointflow-rtsp-test-server (rtsp_test_server.cpp) in a child process on
// a free loopback port, which a test kills and starts again on the same port to make an outage.
// The scene keeps its place on the wall clock across restarts (the server's --epoch), as a real
// scene goes on while its camera is down. And what follows a run's JSON Lines as they are written.
#pragma once

#include <gst/gst.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "broker_process.hpp"
#include "test_env.hpp"

namespace jointflow::test {

inline double unixNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

inline bool haveElement(const char* name) {
  GstElementFactory* f = gst_element_factory_find(name);
  if (f) gst_object_unref(f);
  return f != nullptr;
}

struct RtspCameraOptions {
  std::string user, password;  ///< Basic authentication when user is set
  int start_frame = 0;         ///< the frame of vtest.avi on air when the camera is made
  double fps = 0;              ///< frames per second on air; 0 = vtest.avi's own 10
};

class RtspCamera {
 public:
  using Options = RtspCameraOptions;

  /// Why the RTSP tests cannot run here ("" when they can): the server, an H.264 encoder and
  /// decoder, rtspsrc and vtest.avi. Call after gst_init.
  static std::string missing() {
    if (envOr("JOINTFLOW_RTSP_TEST_SERVER", "").empty())
      return "jointflow-rtsp-test-server was not built: gst-rtsp-server "
             "(libgstrtspserver-1.0-dev, scripts/install-deps.sh) or gstreamer-app-1.0 was "
             "missing at meson setup";
    if (!haveElement("x264enc") && !haveElement("openh264enc"))
      return "no H.264 encoder: x264enc (gstreamer1.0-plugins-ugly) or openh264enc "
             "(gstreamer1.0-plugins-bad)";
    if (!haveElement("avdec_h264") && !haveElement("openh264dec"))
      return "no H.264 decoder: avdec_h264 (gstreamer1.0-libav) or openh264dec";
    if (!haveElement("rtspsrc") || !haveElement("rtph264depay"))
      return "rtspsrc or rtph264depay is missing (gstreamer1.0-plugins-good)";
    if (!std::filesystem::exists(vtestPath()))
      return vtestPath() + " is absent (opencv-doc, scripts/install-deps.sh)";
    return "";
  }

  explicit RtspCamera(Options options = {})
      : options_(std::move(options)),
        dir_("jointflow-rtsp-camera"),
        port_(freeLoopbackPort()),
        epoch_(unixNow()) {}

  /// Starts the server (again) and waits at most 10 s until it listens.
  bool start() {
    std::vector<std::string> argv{envOr("JOINTFLOW_RTSP_TEST_SERVER", ""),
                                  "--port",
                                  std::to_string(port_),
                                  "--epoch",
                                  std::to_string(epoch_),
                                  "--start-frame",
                                  std::to_string(options_.start_frame)};
    if (!options_.user.empty())
      argv.insert(argv.end(), {"--user", options_.user, "--password", options_.password});
    if (options_.fps > 0) argv.insert(argv.end(), {"--fps", std::to_string(options_.fps)});
    process_ = std::make_unique<ChildProcess>(argv, dir_ / "server.log");
    return waitUntil([&] { return !process_->running() || portAccepts(port_); },
                     std::chrono::milliseconds(10000)) &&
           process_->running();
  }
  /// SIGKILL: the camera is gone at once (a power cut, a crash); its clients' connections drop.
  void kill() {
    if (process_) process_->kill(SIGKILL, std::chrono::milliseconds(2000));
    process_.reset();
  }
  /// SIGSTOP / SIGCONT: the camera hangs with its connections open (and takes new ones into the
  /// kernel's backlog without a word), then wakes up.
  void pause() { process_->signal(SIGSTOP); }
  void resume() { process_->signal(SIGCONT); }
  /// rtsp://[user:password@]127.0.0.1:PORT/stream with @scheme: rtspt (TCP), rtspu (UDP), rtsp.
  std::string uri(const std::string& scheme = "rtsp", const std::string& credentials = "") const {
    return scheme + "://" + (credentials.empty() ? "" : credentials + "@") +
           "127.0.0.1:" + std::to_string(port_) + "/stream";
  }
  int port() const { return port_; }
  std::string log() const { return readFile(dir_ / "server.log"); }

 private:
  Options options_;
  TempDir dir_;
  int port_;
  double epoch_;
  std::unique_ptr<ChildProcess> process_;
};

/// One line of a run's JSON Lines and when the test saw it.
struct SeenRecord {
  nlohmann::json record;
  std::chrono::steady_clock::time_point seen;
  /// Track ids of the confirmed (not tentative) people.
  std::set<std::int64_t> confirmed() const {
    std::set<std::int64_t> ids;
    for (const auto& o : record.at("objects"))
      if (!o.at("tentative").get<bool>()) ids.insert(o.at("id").get<std::int64_t>());
    return ids;
  }
  double timestamp() const { return record.at("timestamp").get<double>() / 1e9; }
};

/// Reads the complete lines a writer appended to @path since the last call (jointflowjsonwriter
/// flushes each line), stamping each with the time it was first seen.
class JsonFollower {
 public:
  explicit JsonFollower(std::string path) : path_(std::move(path)) {}
  /// Reads what is new; returns the number of records so far.
  size_t poll() {
    std::ifstream in(path_);
    if (!in) return records_.size();
    in.seekg(static_cast<std::streamoff>(offset_));
    std::string line;
    while (std::getline(in, line)) {
      if (in.eof()) break;  // a line still being written
      offset_ += line.size() + 1;
      records_.push_back({nlohmann::json::parse(line), std::chrono::steady_clock::now()});
    }
    return records_.size();
  }
  /// Polls every 20 ms until @ready holds or @timeout passes.
  template <typename F>
  bool waitFor(F ready, std::chrono::milliseconds timeout) {
    return waitUntil(
        [&] {
          poll();
          return ready();
        },
        timeout);
  }
  const std::vector<SeenRecord>& records() const { return records_; }

 private:
  std::string path_;
  size_t offset_ = 0;
  std::vector<SeenRecord> records_;
};

}  // namespace jointflow::test
