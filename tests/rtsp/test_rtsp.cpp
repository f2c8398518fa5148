// jointflow-track and the documented gst-launch pipelines on a live RTSP camera
// (jointflow-rtsp-test-server: vtest.avi looped as H.264 in real time, rtsp_camera.hpp): poses with
// ids over TCP and UDP, with credentials; malformed addresses end the run with a clear message at
// once.
//
// Every case runs in real time. The figures (time to the first poses) are printed into the test
// log ("figure: ...").
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "gst_test_util.hpp"
#include "rtsp_camera.hpp"

using namespace jointflow::test;
using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;

namespace {

std::string cli() {
  return envOr("JOINTFLOW_TRACK_CLI", "build/apps/jointflow-track");
}

double secondsBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

/// A run of a program in the background, its stdout and stderr in one log, its JSON Lines
/// followed as they are written.
class Run {
 public:
  Run(std::vector<std::string> argv, const std::string& json, const std::string& log)
      : json_(json), log_(log), started_(Clock::now()) {
    process_ = std::make_unique<ChildProcess>(argv, log);
  }
  JsonFollower& json() { return json_; }
  ChildProcess& process() { return *process_; }
  std::string log() const { return readFile(log_); }
  Clock::time_point started() const { return started_; }
  /// SIGTERM (systemd's stop), then the exit status within @grace (-1: it did not exit).
  int stop(milliseconds grace) {
    process_->signal(SIGTERM);
    const int status = process_->wait(grace);
    if (status < 0) process_->kill(SIGKILL, milliseconds(2000));
    return status;
  }

 private:
  JsonFollower json_;
  std::string log_;
  Clock::time_point started_;
  std::unique_ptr<ChildProcess> process_;
};

/// Records with at least one person, each with a track id.
size_t framesWithPeople(const std::vector<SeenRecord>& records, size_t from = 0) {
  size_t n = 0;
  for (size_t i = from; i < records.size(); ++i) {
    const auto& objects = records[i].record.at("objects");
    if (!objects.empty() &&
        std::all_of(objects.begin(), objects.end(), [](const nlohmann::json& o) {
          return o.at("id").get<std::int64_t>() >= 1 && o.at("keypoints").contains("nose");
        }))
      ++n;
  }
  return n;
}

#define REQUIRE_RTSP_CAMERA()                           \
  do {                                                  \
    initGst();                                          \
    const std::string missing_ = RtspCamera::missing(); \
    if (!missing_.empty()) JF_SKIP(missing_);           \
  } while (0)

/// jointflow-track on @uri for @frames frames: exit 0 within 60 s, poses with ids on them.
void tracksLive(const std::string& uri, const std::string& name) {
  TempDir dir("jointflow-rtsp-" + name);
  Run run({cli(), uri, "--max-frames", "6", "--output-json", dir / "poses.jsonl"},
          dir / "poses.jsonl", dir / "run.log");
  REQUIRE(run.json().waitFor([&] { return !run.json().records().empty(); }, milliseconds(60000)));
  const double first = secondsBetween(run.started(), run.json().records().front().seen);
  const int status = run.process().wait(milliseconds(60000));
  INFO(run.log());
  REQUIRE(status == 0);
  run.json().poll();
  const auto& records = run.json().records();
  REQUIRE(records.size() == 6);
  CHECK(framesWithPeople(records) >= 5);
  CHECK(records.back().record.at("resolution").at("width") == 768);
  // Live frames are stamped with the pipeline clock's running time, in order.
  for (size_t i = 1; i < records.size(); ++i)
    CHECK(records[i].timestamp() > records[i - 1].timestamp());
  std::printf("figure: %s: first poses %.2f s after the start (model loading included)\n",
              name.c_str(), first);
}

}  // namespace

TEST_CASE("jointflow-track tracks people on a live RTSP camera over TCP", "[rtsp]") {
  REQUIRE_RTSP_CAMERA();
  RtspCamera camera;
  REQUIRE(camera.start());
  tracksLive(camera.uri("rtspt"), "tcp");
}

TEST_CASE("jointflow-track tracks people over UDP, with credentials", "[rtsp]") {
  REQUIRE_RTSP_CAMERA();
  RtspCamera camera({"alice", "s3cret", 0});
  REQUIRE(camera.start());
  tracksLive(camera.uri("rtspu", "alice:s3cret"), "udp");
}

TEST_CASE("gst-launch-1.0 pipelines with rtspsrc and uridecodebin track the camera", "[rtsp]") {
  REQUIRE_RTSP_CAMERA();
  RtspCamera camera;
  REQUIRE(camera.start());
  TempDir dir("jointflow-rtsp-launch");
  // docs/deploy.md's pipeline (deploy/systemd/camera1.env), and the same from uridecodebin.
  const std::string tail =
      " ! videoconvert ! queue leaky=downstream max-size-buffers=1 max-size-bytes=0 "
      "max-size-time=0 ! jointflowtrack ! jointflowjsonwriter location=" +
      (dir / "poses.jsonl") + " ! fakesink sync=false";
  const std::string source = GENERATE(std::string("rtspsrc location=%s latency=200 ! decodebin"),
                                      std::string("uridecodebin uri=%s"));
  char head[256];
  std::snprintf(head, sizeof head, source.c_str(), camera.uri("rtspt").c_str());
  std::filesystem::remove(dir / "poses.jsonl");
  std::vector<std::string> argv{"gst-launch-1.0", "-e"};
  std::istringstream words(head + tail);
  for (std::string w; words >> w;) argv.push_back(w);
  Run run(argv, dir / "poses.jsonl", dir / "run.log");
  INFO(head);
  const bool tracked = run.json().waitFor(
      [&] { return framesWithPeople(run.json().records()) >= 3; }, milliseconds(60000));
  INFO(run.log());
  CHECK(tracked);
  // -e: SIGINT ends the stream with an EOS, as jointflow-launch@.service stops it.
  run.process().signal(SIGINT);
  CHECK(run.process().wait(milliseconds(20000)) == 0);
}

TEST_CASE("Bad addresses end the run with a clear message in bounded time", "[rtsp]") {
  initGst();
  struct Case {
    std::string uri, extra, message;
    int status;
    double within;  ///< seconds
  };
  std::vector<Case> cases = {
      {"rtsp://", "", "not a valid RTSP address", 1, 5},
      {"rtsp://:554/stream", "", "no host", 1, 5},
      {"rtsp://127.0.0.1:70000/stream", "", "port 70000 is out of range", 1, 5},
      {"rtsp://camera.local/live stream", "", "white space in it", 1, 5},
  };
  for (const Case& c : cases) {
    TempDir dir("jointflow-rtsp-bad");
    const auto start = Clock::now();
    Run run({"sh", "-c", cli() + " '" + c.uri + "' " + c.extra + " -q"}, dir / "none",
            dir / "run.log");
    const int status = run.process().wait(milliseconds(30000));
    const double took = secondsBetween(start, Clock::now());
    INFO(c.uri << ": " << run.log());
    CHECK(status == c.status);
    CHECK(run.log().find(c.message) != std::string::npos);
    CHECK(took < c.within);
  }
}
