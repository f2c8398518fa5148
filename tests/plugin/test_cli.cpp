// jointflow-track end to end with the real models: a clip of vtest.avi to JSON Lines, an overlay
// video and PoseTrack JSON; a folder of frames named as PoseTrack names them; clear failures.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "gst_test_util.hpp"
#include "publish/broker_process.hpp"
#include "test_env.hpp"

namespace fs = std::filesystem;
using namespace jointflow::test;

namespace {

struct Output {
  int status = -1;
  std::string text;  ///< stdout and stderr
};

// Runs jointflow-track; `redirect` says where its stderr goes ("2>&1": into the text).
Output runCli(const std::string& args, const std::string& redirect = "2>&1") {
  const std::string cli = envOr("JOINTFLOW_TRACK_CLI", "build/apps/jointflow-track");
  Output out;
  FILE* pipe = popen((cli + " " + args + " " + redirect).c_str(), "r");
  REQUIRE(pipe != nullptr);
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) out.text.append(buf, n);
  const int status = pclose(pipe);
  out.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("jointflow-cli-test-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Writes the first `n` frames of vtest.avi as numbered JPEG files into `folder`.
void writeVtestFrames(const fs::path& folder, int n) {
  fs::create_directories(folder);
  cv::VideoCapture capture(vtestPath());
  cv::Mat frame;
  for (int i = 0; i < n && capture.read(frame); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "%06d.jpg", i);
    REQUIRE(cv::imwrite((folder / name).string(), frame));
  }
}

}  // namespace

TEST_CASE("jointflow-track on a clip of vtest.avi writes JSON Lines, video and PoseTrack",
          "[plugin][cli]") {
  initGst();
  JF_REQUIRE_PATH_OR_SKIP(vtestPath());
  const fs::path dir = scratch("video");
  const Output out =
      runCli(vtestPath() + " --max-frames 5 --output-json " + (dir / "poses.jsonl").string() +
             " --output-video " + (dir / "tracked.mkv").string() + " --output-posetrack " +
             (dir / "posetrack").string() + " --output-mot " + (dir / "boxes.txt").string() +
             " --similarity oks");
  INFO(out.text);
  REQUIRE(out.status == 0);
  CHECK(out.text.find("frames:     5") != std::string::npos);
  CHECK(out.text.find("tracks:") != std::string::npos);
  CHECK(out.text.find("frames/s:") != std::string::npos);

  std::ifstream jsonl(dir / "poses.jsonl");
  std::string line;
  int lines = 0;
  std::vector<std::string> expected_mot;  // the JSON's boxes as MOT lines
  while (std::getline(jsonl, line)) {
    const auto record = nlohmann::json::parse(line);
    CHECK(record.at("frame") == lines);
    CHECK(record.at("resolution").at("width") == 768);
    CHECK(record.at("timestamp").get<guint64>() == static_cast<guint64>(lines) * GST_SECOND / 10);
    CHECK(!record.at("objects").empty());
    for (const auto& o : record.at("objects")) {
      CHECK(o.at("keypoints").contains("left_ankle"));
      char mot[160];
      std::snprintf(mot, sizeof mot, "%d,%d,%.2f,%.2f,%.2f,%.2f,%.4f,-1,-1,-1", lines + 1,
                    o.at("id").get<int>(), o.at("x").get<double>(), o.at("y").get<double>(),
                    o.at("w").get<double>(), o.at("h").get<double>(),
                    o.at("confidence").get<double>());
      expected_mot.push_back(mot);
    }
    ++lines;
  }
  CHECK(lines == 5);
  // --output-mot: the same people, boxes and ids, frames numbered from 1.
  std::ifstream mot(dir / "boxes.txt");
  std::vector<std::string> mot_lines;
  while (std::getline(mot, line)) mot_lines.push_back(line);
  CHECK(mot_lines == expected_mot);
  CHECK(countVideoFrames((dir / "tracked.mkv").string()) == 5);

  std::ifstream pt(dir / "posetrack" / "vtest.json");
  REQUIRE(pt.good());
  const auto posetrack = nlohmann::json::parse(pt);
  REQUIRE(posetrack.at("images").size() == 5);
  CHECK(posetrack.at("images")[0].at("file_name") == "vtest/000000.jpg");
  CHECK(!posetrack.at("annotations").empty());
  fs::remove_all(dir);
}

TEST_CASE("jointflow-track reads a folder of numbered frames with PoseTrack's file names",
          "[plugin][cli]") {
  initGst();
  JF_REQUIRE_PATH_OR_SKIP(vtestPath());
  const fs::path dir = scratch("frames");
  const fs::path frames = dir / "images" / "val" / "000001_test";
  writeVtestFrames(frames, 3);
  const Output out = runCli(frames.string() + " --output-posetrack " + (dir / "out").string() +
                            " --output-json " + (dir / "poses.jsonl").string());
  INFO(out.text);
  REQUIRE(out.status == 0);
  std::ifstream pt(dir / "out" / "000001_test.json");
  REQUIRE(pt.good());
  const auto posetrack = nlohmann::json::parse(pt);
  REQUIRE(posetrack.at("images").size() == 3);
  CHECK(posetrack.at("images")[2].at("file_name") == "images/val/000001_test/000002.jpg");
  fs::remove_all(dir);
}

TEST_CASE("--prune-short-tracks drops the people of tracks seen on fewer frames", "[plugin][cli]") {
  initGst();
  JF_REQUIRE_PATH_OR_SKIP(vtestPath());
  const fs::path dir = scratch("prune");
  // 3 frames: no track can be seen on 4 of them, so none is left (the run above, unpruned, has
  // people in every frame).
  const Output out = runCli(vtestPath() + " -q --max-frames 3 --prune-short-tracks 4 " +
                            "--output-posetrack " + dir.string());
  INFO(out.text);
  REQUIRE(out.status == 0);
  std::ifstream pt(dir / "vtest.json");
  const auto posetrack = nlohmann::json::parse(pt);
  CHECK(posetrack.at("images").size() == 3);
  CHECK(posetrack.at("annotations").empty());
  fs::remove_all(dir);
}

TEST_CASE("an undecodable frame leaves a gap: later PoseTrack frames keep their own names",
          "[plugin][cli]") {
  initGst();
  JF_REQUIRE_PATH_OR_SKIP(vtestPath());
  const fs::path dir = scratch("gap");
  const fs::path frames = dir / "images" / "val" / "000002_gap";
  writeVtestFrames(frames, 6);
  std::ofstream(frames / "000002.jpg", std::ios::trunc) << "not a JPEG";  // frame 2 is lost
  const Output out = runCli(frames.string() + " --output-posetrack " + (dir / "out").string() +
                            " --output-json " + (dir / "poses.jsonl").string());
  INFO(out.text);
  REQUIRE(out.status == 0);
  std::ifstream pt(dir / "out" / "000002_gap.json");
  REQUIRE(pt.good());
  const auto posetrack = nlohmann::json::parse(pt);
  // Every source frame is listed under its own name; the lost one has no people.
  const auto& images = posetrack.at("images");
  REQUIRE(images.size() == 6);
  std::map<int, int> people;
  for (const auto& a : posetrack.at("annotations")) ++people[a.at("image_id").get<int>()];
  for (int i = 0; i < 6; ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "images/val/000002_gap/%06d.jpg", i);
    CHECK(images[i].at("file_name") == name);
    CHECK(images[i].at("frame_id") == i);
    if (i == 2)
      CHECK(people[i] == 0);
    else
      CHECK(people[i] >= 3);  // vtest's first frames hold several walkers
  }
  // The tracker saw the five decodable frames.
  std::ifstream jsonl(dir / "poses.jsonl");
  int lines = 0;
  for (std::string line; std::getline(jsonl, line);) ++lines;
  CHECK(lines == 5);
  fs::remove_all(dir);
}

TEST_CASE("with --output-json -, stdout carries only JSON Lines; the summary goes to stderr",
          "[plugin][cli]") {
  JF_REQUIRE_PATH_OR_SKIP(vtestPath());
  const fs::path dir = scratch("stdout");
  const Output out =
      runCli(vtestPath() + " --max-frames 3 --output-json -", "2>" + (dir / "stderr.txt").string());
  REQUIRE(out.status == 0);
  std::istringstream lines(out.text);
  int n = 0;
  for (std::string line; std::getline(lines, line); ++n) {
    INFO(line);
    const auto record = nlohmann::json::parse(line);  // throws on anything but JSON
    CHECK(record.at("frame") == n);
  }
  CHECK(n == 3);
  std::ifstream err(dir / "stderr.txt");
  const std::string summary((std::istreambuf_iterator<char>(err)), {});
  CHECK(summary.find("frames:     3") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("the property table of docs/gstreamer.md is the element's own", "[plugin][cli]") {
  const Output out = runCli("--properties-markdown", "2>/dev/null");
  REQUIRE(out.status == 0);
  std::ifstream doc(sourceRoot() + "/docs/gstreamer.md");
  REQUIRE(doc.good());
  const std::string text((std::istreambuf_iterator<char>(doc)), {});
  const std::string begin =
      "<!-- properties:jointflowtrack (jointflow-track --properties-markdown) -->\n";
  const std::string end = "<!-- end properties -->";
  const size_t a = text.find(begin), b = text.find(end);
  REQUIRE(a != std::string::npos);
  REQUIRE(b != std::string::npos);
  INFO("regenerate with: scripts/update-property-docs.sh build");
  CHECK(text.substr(a + begin.size(), b - a - begin.size()) == out.text);
}

TEST_CASE("PoseTrack output pairs with the ground truth's frames (Bonn test sequence)",
          "[plugin][cli][data]") {
  const fs::path data = fs::path(dataDir()) / "bonn-posetrack";
  const fs::path frames = data / "images" / "test" / "060470979_bonn_test";
  const fs::path gt_file = data / "annotations" / "test" / "060470979_bonn_test.json";
  JF_REQUIRE_PATH_OR_SKIP(frames.string());
  JF_REQUIRE_PATH_OR_SKIP(gt_file.string());
  const fs::path dir = scratch("bonn");
  const Output out = runCli(frames.string() + " -q --output-posetrack " + dir.string());
  INFO(out.text);
  REQUIRE(out.status == 0);
  std::ifstream pred_in(dir / "060470979_bonn_test.json");
  std::ifstream gt_in(gt_file);
  REQUIRE(pred_in.good());
  const auto pred = nlohmann::json::parse(pred_in);
  const auto gt = nlohmann::json::parse(gt_in);
  REQUIRE(pred.at("images").size() == gt.at("images").size());
  for (size_t i = 0; i < gt.at("images").size(); ++i)
    CHECK(pred.at("images")[i].at("file_name") == gt.at("images")[i].at("file_name"));
  // The four people on the boards are found in (nearly) every frame.
  CHECK(pred.at("annotations").size() >= 4 * gt.at("images").size() * 9 / 10);
  fs::remove_all(dir);
}

TEST_CASE("jointflow-track fails clearly on bad input", "[plugin][cli]") {
  const Output missing = runCli("/nonexistent/video.mp4");
  CHECK(missing.status != 0);
  CHECK(missing.text.find("/nonexistent/video.mp4") != std::string::npos);

  const Output range = runCli(vtestPath() + " --max-persons 0");
  CHECK(range.status != 0);
  CHECK(range.text.find("--max-persons") != std::string::npos);
  const Output tile = runCli(vtestPath() + " --tiles true --tile-size 8");
  CHECK(tile.status != 0);
  CHECK(tile.text.find("--tile-size") != std::string::npos);

  const Output similarity = runCli(vtestPath() + " --similarity banana");
  CHECK(similarity.status != 0);
  CHECK(similarity.text.find("oks") != std::string::npos);  // lists the valid names

  const Output model = runCli(vtestPath() + " --max-frames 1 --spatial-model /nonexistent/m.onnx");
  CHECK(model.status != 0);
  CHECK(model.text.find("/nonexistent/m.onnx") != std::string::npos);

  const fs::path empty = scratch("empty");
  const Output folder = runCli(empty.string());
  CHECK(folder.status != 0);
  CHECK(folder.text.find("numbered") != std::string::npos);
  fs::remove_all(empty);
}

TEST_CASE("--metrics-port: a port in use, out of range or a bad address is a clear error at start",
          "[plugin][cli]") {
  // A port some other service listens on.
  int port = 0;
  const int fd = boundLoopbackSocket(&port, true);
  const auto start = std::chrono::steady_clock::now();
  const Output busy = runCli(vtestPath() + " --max-frames 1 --metrics-address 127.0.0.1 " +
                             "--metrics-port " + std::to_string(port));
  close(fd);
  INFO(busy.text);
  CHECK(busy.status == 1);
  CHECK(busy.text.find("--metrics-port " + std::to_string(port)) != std::string::npos);
  CHECK(busy.text.find("in use") != std::string::npos);
  // At start: before the pipeline starts (no model is loaded for it).
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(20));

  const Output range = runCli(vtestPath() + " --metrics-port 70000");
  CHECK(range.status != 0);
  CHECK(range.text.find("--metrics-port") != std::string::npos);
  const Output address = runCli(vtestPath() + " --metrics-port 9 --metrics-address banana");
  CHECK(address.status == 1);
  CHECK(address.text.find("banana") != std::string::npos);
}
