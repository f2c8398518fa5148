// jointflow-bench's writer (jointflow_bench_document.hpp): a section per case, in the order of
// the document, which is not quite that of the run: the TFF table reads the end-to-end case's
// rounds.
#include "jointflow_bench_document.hpp"

#include <algorithm>
#include <map>
#include <sstream>
#include <thread>

#include <opencv2/core/version.hpp>

#include "markdown_table.hpp"

namespace jointflow::bench {
namespace {

using nlohmann::json;
using E2e = std::map<std::string, json>;  // not const: a missing figure reads as null

const char* met(bool ok) {
  return ok ? "**met**" : "**missed**";
}

// 1: the element end to end.
void endToEndSection(std::ostream& md, const BudgetSettings& s, E2e& e2e) {
  md << "## Where the time goes: the element against the bare network\n\n"
        "Each input size in a process of its own, in "
     << s.rounds << " rounds of " << s.block
     << " frames (after one warm-up round); in each round every column runs one block, engine "
        "after engine, so that a ratio taken within a round sees one machine load. Times are "
        "medians over the frames of all rounds; ratios are medians of the per-round ratios. "
        "Bare network = SpatialModel::estimate: pre-processing (letterbox; the float blob with "
        "cv::dnn, while OpenVINO converts the 8-bit image in its graph), forward pass, "
        "decoding. Camera motion = CameraMotionTracker::update on each frame after the first of "
        "a block "
        "(core/tracking/camera_motion.cpp; on every inferred frame since issue 11). Tracker = "
        "jointflow::Tracker::process (bare network + association with camera motion, no "
        "GStreamer). Element = `appsrc ! jointflowtrack ! fakesink` fed raw BGR frames from "
        "another thread as fast as it takes them: the median time between two frames leaving "
        "it, tracking included (similarity oks); frames/s = 1000 / it. With OpenVINO the "
        "element holds one frame (async-inference=true, the default). Overhead = element / "
        "forward (target <= 1.05); CPU overhead = the process's CPU time per frame, element / "
        "bare network: what the element costs the machine, whatever the load. Still camera = "
        "the same element with camera-compensation=false (no camera-motion estimate, as for a "
        "fixed camera): its overhead, element / forward, in the same rounds.\n\n";
  auto table = MarkdownTable::leftAligned(
      {"engine", "input size", "network input", "pre-processing (ms)", "forward (ms)",
       "decoding (ms)", "camera motion (ms)", "tracker (ms)", "element (ms)", "frames/s",
       "overhead", "CPU overhead", "target", "overhead, still camera"});
  for (const auto& [backend, engine] : s.engines)
    for (const std::string& size : s.sizes) {
      json& e = e2e[size]["engines"][backend];
      const double overhead = e["overhead"];
      table.row({engine, size, e["input"].get<std::string>(), fmt(e["preprocess_ms"]),
                 fmt(e["forward_ms"]), fmt(e["decoding_ms"]), fmt(e2e[size]["camera_ms"]),
                 fmt(e["tracker_ms"]), fmt(e["element_ms"]),
                 fmt(1000.0 / e["element_ms"].get<double>()), fmt(overhead, 2),
                 fmt(e["overhead_cpu"], 2), std::string("<= 1.05: ") + met(overhead <= 1.05),
                 fmt(e["overhead_still"], 2)});
    }
  md << table.str();
  md << "\nLoad average after each size's process: ";
  for (const std::string& size : s.sizes)
    md << size << " " << e2e[size]["load_after"].get<std::string>()
       << (size == s.sizes.back() ? ".\n" : ", ");
}

// 1, with OpenVINO: its speed-up over cv::dnn, and what the held frame gains.
void openVinoSections(std::ostream& md, const BudgetSettings& s, E2e& e2e) {
  const json& ov640 = e2e["max:640"]["engines"]["openvino"];
  const json& ov256 = e2e["256x256"]["engines"]["openvino"];
  const double speedup = e2e["max:640"]["speedup"];
  md << "\n**OpenVINO against cv::dnn, end to end** (element time, cv::dnn / OpenVINO, per "
        "round; the bare forward pass in brackets): ";
  for (const std::string& size : s.sizes)
    md << size << " " << fmt(e2e[size]["speedup"], 2) << "x ("
       << fmt(e2e[size]["speedup_forward"], 2) << "x)" << (size == s.sizes.back() ? ". " : ", ");
  md << "Target at max:640 >= 2.5x: " << met(speedup >= 2.5) << ".\n\n"
     << "**Frames/s with tracking** (OpenVINO element): max:640 "
     << fmt(1000.0 / ov640["element_ms"].get<double>())
     << " (target >= 15: " << met(1000.0 / ov640["element_ms"].get<double>() >= 15) << "), 256x256 "
     << fmt(1000.0 / ov256["element_ms"].get<double>())
     << " (target >= 40: " << met(1000.0 / ov256["element_ms"].get<double>() >= 40)
     << "), on this machine at the load above. The CPU time per frame says what they "
        "would be on "
     << std::thread::hardware_concurrency()
     << " cores of our own if the element used them all: max:640 "
     << fmt(1000.0 * std::thread::hardware_concurrency() / ov640["element_cpu_ms"].get<double>())
     << ", 256x256 "
     << fmt(1000.0 * std::thread::hardware_concurrency() / ov256["element_cpu_ms"].get<double>())
     << " frames/s (an upper bound: cores x 1000 / CPU ms per frame).\n";

  md << "\n## The held frame (async-inference)\n\n"
        "OpenVINO runs asynchronously: with async-inference=true (the default) the element "
        "holds one frame, so that frame N's network runs while frame N-1's outputs are read "
        "and decoded, it is associated and pushed, and upstream brings frame N+1; "
        "async-inference=false runs each frame's "
        "network and association in turn. Raw = BGR frames pushed from another thread (the "
        "element's thread does only the element's work); decoded = JPEG frames (vtest.avi "
        "re-encoded, quality 90) through `jpegdec ! videoconvert` in the element's own "
        "streaming thread, as with `filesrc ! decodebin ! videoconvert ! jointflowtrack` "
        "without a queue. Same rounds as above; gain = time not held / time held, per "
        "round.\n\n";
  auto table = MarkdownTable::leftAligned({"input size", "raw, held (ms)", "raw, not held (ms)",
                                           "gain", "decoded, held (ms)", "decoded, not held (ms)",
                                           "gain", "cv::dnn decoded (ms)"});
  for (const std::string& size : s.sizes) {
    json& e = e2e[size]["engines"]["openvino"];
    table.row({size, fmt(e["element_ms"]), fmt(e["element-sync_ms"]),
               fmt(e["hold_gain_raw"], 2) + "x", fmt(e["jpeg_ms"]), fmt(e["jpeg-sync_ms"]),
               fmt(e["hold_gain_jpeg"], 2) + "x", fmt(e2e[size]["engines"]["default"]["jpeg_ms"])});
  }
  md << table.str();
}

// 2: the TFF network against the spatial network, from the end-to-end rounds.
void tffSection(std::ostream& md, const BudgetSettings& s, E2e& e2e) {
  md << "\n## TFF network against the spatial network\n\n";
  if (s.tff_used.empty()) {
    md << "Not measured: " << s.tff_path << " is absent (the trained TFF network).\n";
    return;
  }
  md << "`tff_movenet.onnx` (the runner's predict(): the maps of a frame and of the one "
        "before in, TFF out) against MoveNet's forward pass on the same engine, in the "
        "rounds above (target <= 0.25). After camera: as the Tracker runs it with camera "
        "compensation on (the default), the previous maps first moved by the camera motion "
        "(bilinear warp of every plane, here for a motion of 8 px and 1 % zoom). Element, "
        "oks / tff: the element above with similarity=oks (what the default, auto, runs "
        "between close frames) and with "
        "similarity=tff, in the same rounds: what the paper's similarity costs end to end "
        "(tff / oks, per round).\n\n";
  auto table = MarkdownTable::leftAligned(
      {"engine", "input size", "spatial forward (ms)", "TFF (ms)", "ratio", "target",
       "TFF after camera (ms)", "ratio", "element, oks (ms)", "element, tff (ms)", "tff / oks"});
  for (const auto& [backend, engine] : s.engines)
    for (const std::string& size : s.sizes) {
      json& e = e2e[size]["engines"][backend];
      const double forward = e["forward_ms"].get<double>();
      const double ratio = e["tff_ms"].get<double>() / forward;
      table.row({engine, size, fmt(e["forward_ms"]), fmt(e["tff_ms"]), fmt(ratio, 3),
                 std::string("<= 0.25: ") + met(ratio <= 0.25), fmt(e["tff_camera_ms"]),
                 fmt(e["tff_camera_ms"].get<double>() / forward, 3), fmt(e["element_ms"]),
                 fmt(e["element-tff_ms"]), fmt(e["tff_element_ratio"], 2) + "x"});
    }
  md << table.str();
}

// 3: the engines on the same file, and where cv::dnn's time goes.
void enginesSection(std::ostream& md, const BudgetSettings& s, const BudgetFigures& f) {
  md << "\n## cv::dnn, OpenVINO and onnxruntime on the same ONNX file\n\n"
        "`movenet_multipose.onnx`, random input of its range, every graph output; the engines "
        "take turns run by run (10 ms apart, so that the thread pool of one has stopped "
        "spinning when the next runs), "
     << s.threads << " threads each (median of " << s.runs
     << " runs), then 1 thread each (median of " << std::max(2, s.runs / 2)
     << " runs), after 3 warm-up runs each; onnxruntime in a Python process of its own "
        "(bench/ort_time.py, timing its own runs). OpenVINO with its default precision ("
     << (s.haveOpenVino() ? s.openvino_name.substr(s.openvino_name.rfind(' ') + 1) : "-")
     << " here) and with f32.\n\n";
  auto table = MarkdownTable::leftAligned(
      {"input", "cv::dnn (ms)", "OpenVINO (ms)", "OpenVINO f32 (ms)", "onnxruntime (ms)",
       "cv::dnn / OpenVINO", "cv::dnn / OpenVINO f32", "cv::dnn / onnxruntime"});
  std::vector<std::pair<cv::Size, EngineTimes>> profiles;
  for (const EngineRow& row : f.engines) {
    const EngineTimes& t = row.times;
    auto ratio = [&](double other) { return other > 0 ? fmt(t.dnn / other, 2) : "n/a"; };
    auto cell = [](double ms) { return ms > 0 ? fmt(ms) : "n/a"; };
    table.row({std::to_string(row.size.width) + "x" + std::to_string(row.size.height) + ", " +
                   std::to_string(row.threads) + " thread" + (row.threads > 1 ? "s" : ""),
               fmt(t.dnn), cell(t.ov), cell(t.ov32),
               f.ort_version ? fmt(t.ort) + " (" + *f.ort_version + ")" : "n/a (no --python)",
               ratio(t.ov), ratio(t.ov32), ratio(t.ort)});
    if (row.threads == s.threads && row.size != s.max640) profiles.emplace_back(row.size, t);
  }
  md << table.str();
  md << "\ncv::dnn's time by layer type (getPerfProfile, mean per forward pass, " << s.threads
     << " threads):\n\n";
  auto types = MarkdownTable::leftAligned({"input", "layer type", "ms", "share"});
  for (const auto& [size, t] : profiles) {
    double total = 0;
    for (const auto& [type, ms] : t.by_type) total += ms;
    for (size_t i = 0; i < t.by_type.size() && i < 6; ++i)
      types.row({std::to_string(size.width) + "x" + std::to_string(size.height), t.by_type[i].first,
                 fmt(t.by_type[i].second, 2), fmt(100.0 * t.by_type[i].second / total) + " %"});
  }
  md << types.str();
  md << "\nThe slowest layers at " << profiles[0].first.width << "x" << profiles[0].first.height
     << ":\n\n";
  auto layers = MarkdownTable::leftAligned({"layer", "ms"});
  for (size_t i = 0; i < profiles[0].second.by_layer.size() && i < 10; ++i)
    layers.row(
        {profiles[0].second.by_layer[i].first, fmt(profiles[0].second.by_layer[i].second, 2)});
  md << layers.str();
}

// 4: streams, at the default input size.
void streamsSection(std::ostream& md, const BudgetSettings& s, const BudgetFigures& f) {
  md << "\n## Frames/s and memory of 1 and 4 streams\n\n"
        "K pipelines `appsrc ! jointflowtrack input-size=max:640 ! fakesink` in one process "
        "(a process per row), each fed from its own thread as fast as it takes frames ("
     << s.stream_frames << " frames each, " << kStreamWarmup
     << " of them warm-up). Memory = growth of the process's resident memory from before the "
        "K pipelines were made to after their last frame (one pipeline at 64x64 ran before, "
        "to load the libraries and the model file's bytes). ms/frame per stream = mean time "
        "between two frames of a stream (the median over the streams); frames/s = all streams' "
        "frames after warm-up over "
        "the time they took.\n\n";
  auto table =
      MarkdownTable::leftAligned({"engine", "streams", "ms/frame per stream",
                                  "frames/s, all streams", "memory (MiB)", "per stream (MiB)"});
  for (const StreamRow& row : f.streams) {
    const json& r = row.figures;
    table.row({row.engine, std::to_string(r["streams"].get<int>()) + row.note,
               fmt(r["ms_per_frame"].get<double>()), fmt(r["fps_total"].get<double>(), 2),
               fmt(r["rss_mib"].get<double>()), fmt(r["rss_per_stream_mib"].get<double>())});
  }
  md << table.str();
  if (s.haveOpenVino()) {
    const json &shared = f.shared_streams, &separate2 = f.separate_streams;
    md << "\nMemory target: 4 streams sharing one model (" << fmt(shared["rss_mib"].get<double>())
       << " MiB) take less than 2 streams with a model "
       << "each (" << fmt(separate2["rss_mib"].get<double>())
       << " MiB): " << met(shared["rss_mib"].get<double>() < separate2["rss_mib"].get<double>())
       << ".\n";
  }
}

// 5: person counts of the two engines.
void personCountsSection(std::ostream& md, const BudgetSettings& s, const PersonCounts& c) {
  const double share = 100.0 * c.within / std::max(c.frames, 1);
  md << "\n## Person counts of the two engines\n\nMoveNet at max:640 (the default options) on "
     << (s.agreement_stride == 1 ? "every frame"
                                 : "one frame in " + std::to_string(s.agreement_stride))
     << " of vtest.avi (" << c.frames << " of its " << c.total << " frames, "
     << fmt(1.0 * c.people / c.frames) << " people per frame on cv::dnn), cv::dnn against "
     << s.openvino_name << ": the counts agree within 1 on " << c.within << " frames ("
     << fmt(share) << " %, target >= 95 %: " << met(share >= 95) << ") and are equal on " << c.equal
     << " (" << fmt(100.0 * c.equal / std::max(c.frames, 1)) << " %).\n";
}

// 6: a live source faster than inference.
void liveSection(std::ostream& md, const BudgetSettings& s, const BudgetFigures& f) {
  md << "\n## Live source faster than inference\n\n"
        "`videotestsrc is-live=true` at 60 frames/s (320x240) into jointflowtrack "
        "(input-size=native, cv::dnn) into `fakesink sync=true qos=true`, "
     << fmt(s.live_seconds, 0)
     << " s per policy (docs/gstreamer.md, live policy). Latency = the clock's running time "
        "when a buffer reaches the sink - the buffer's running time.\n\n";
  const std::map<std::string, std::string> policy_names = {
      {"skip", "skip-late-frames=true (default)"},
      {"leaky", "leaky queue of 1, skip-late-frames=false"},
      {"none", "neither (skip-late-frames=false, no queue)"}};
  auto table = MarkdownTable::leftAligned(
      {"policy", "buffers/s at the sink", "inferred/s", "latency, first quarter (ms)",
       "latency, last quarter (ms)", "max latency, second half (ms)"});
  for (const auto& [policy, r] : f.live)
    table.row({policy_names.at(policy), fmt(r["frames_per_s"].get<double>()),
               fmt(r["inferred_per_s"].get<double>()),
               fmt(r["latency_first_quarter_ms"].get<double>(), 0),
               fmt(r["latency_last_quarter_ms"].get<double>(), 0),
               fmt(r["latency_max_second_half_ms"].get<double>(), 0)});
  md << table.str();
}

}  // namespace

std::string budgetMarkdown(const BudgetSettings& s, const BudgetFigures& f, double minutes,
                           const std::string& load_before) {
  E2e e2e = f.e2e;
  std::ostringstream md;
  endToEndSection(md, s, e2e);
  if (s.haveOpenVino()) openVinoSections(md, s, e2e);
  tffSection(md, s, e2e);
  enginesSection(md, s, f);
  streamsSection(md, s, f);
  if (f.counts) personCountsSection(md, s, *f.counts);
  liveSection(md, s, f);

  std::ostringstream doc;
  doc << "# Benchmarks\n\nWritten by `make bench` (bench/run.sh -> build/bench/jointflow-bench, "
         "bench/jointflow_bench.cpp) in one run on one machine ("
      << fmt(minutes) << " minutes): frames of vtest.avi (" << s.native.width << "x"
      << s.native.height << "), " << s.threads << " threads for every engine, "
      << std::thread::hardware_concurrency() << " hardware threads. Load average " << load_before
      << " before the run, then ";
  for (size_t i = 0; i < f.loads.size(); ++i)
    doc << f.loads[i] << (i + 1 < f.loads.size() ? ", " : " ");
  doc << "after its sections: the machine is shared, absolute times move with its load, so "
         "compare the ratios, each taken within one round of one process. Engines: OpenCV "
      << CV_VERSION << " dnn (cv::dnn, the default) and "
      << (s.haveOpenVino() ? s.openvino_name + " (backend=openvino, its default precision)"
                           : "no OpenVINO (" + s.openvino_missing + ")")
      << ". The spatial model is MoveNet MultiPose, similarity oks.\n\n"
      << md.str();
  return doc.str();
}

}  // namespace jointflow::bench
