// jointflow-bench: the performance budgets of issues 7 and 13, all measured in one run on one
// machine, for each engine (cv::dnn, and OpenVINO where the build has it).
//
//   1. jointflowtrack in a pipeline against the bare spatial network at the same input size
//      (overhead ratio, target <= 1.05), at 256x256, max:640 and native;
//   2. the TFF network against the spatial network (target <= 0.25);
//   3. cv::dnn, OpenVINO and onnxruntime on the same ONNX file and input shape, with cv::dnn's
//      time per layer type (Net::getPerfProfile) to show where it goes;
//   4. frames/s and memory per stream on vtest.avi, 1 and 4 streams; OpenVINO's streams sharing
//      one compiled model (model-instance-id) against streams with a model each;
//   5. the person counts of the two engines on every frame of vtest.avi.
// Prints Markdown tables and writes them to --out. Each pipeline measurement runs in a child
// process of its own (this program, --child), so that memory figures do not mix.
//
//   jointflow-bench [--frames 30] [--threads N] [--python venv/bin/python] [--out
//   docs/benchmarks.md]
#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "resident_memory.hpp"

#include "../core/engine/network.hpp"
#include "jointflow/error.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow/tff_model.hpp"
#include "jointflow/tracker.hpp"
#include "jointflowmeta.h"

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string first;
  return in >> first ? first : "?";
}

std::vector<cv::Mat> readFrames(const std::string& video, int count) {
  cv::VideoCapture capture(video);
  if (!capture.isOpened()) throw jointflow::Error("cannot open the video " + video);
  std::vector<cv::Mat> frames;
  cv::Mat f;
  while (static_cast<int>(frames.size()) < count && capture.read(f)) frames.push_back(f.clone());
  if (frames.size() < 4) throw jointflow::Error(video + " has fewer than 4 frames");
  return frames;
}

// ---- 1, 4: pipelines (in a child process) ----------------------------------------------------

/// K pipelines appsrc ! jointflowtrack ! fakesink, fed from K threads as fast as they take
/// frames. Time per frame from the sink's arrival times after `warmup` frames; memory from RSS
/// before the pipelines exist and after the frames went through.
json runPipelines(const std::vector<cv::Mat>& frames, int streams, const std::string& input_size,
                  int warmup, const std::string& props) {
  const int w = frames[0].cols, h = frames[0].rows, n = static_cast<int>(frames.size());
  auto launch = [&](int i, const std::string& size) {
    return "appsrc name=src" + std::to_string(i) +
           " format=time block=true max-buffers=2 caps=video/x-raw,format=BGR,width=" +
           std::to_string(w) + ",height=" + std::to_string(h) +
           ",framerate=10/1 ! jointflowtrack input-size=" + size + " similarity=oks " + props +
           " ! fakesink name=sink" + std::to_string(i) + " sync=false";
  };
  // A first pipeline, run and dropped, pays the process's one-time costs (plugin loading, OpenCV
  // and OpenVINO set-up, the model file's bytes, which every further instance shares). At a tiny
  // input size, so that the memory its compiled model freed does not hide the measured ones'.
  {
    GstElement* p = gst_parse_launch(launch(0, "64x64").c_str(), nullptr);
    gst_element_set_state(p, GST_STATE_PLAYING);
    GstElement* src = gst_bin_get_by_name(GST_BIN(p), "src0");
    gst_app_src_push_buffer(GST_APP_SRC(src),
                            gst_buffer_new_wrapped(g_memdup2(frames[0].data, frames[0].total() * 3),
                                                   frames[0].total() * 3));
    gst_app_src_end_of_stream(GST_APP_SRC(src));
    GstBus* bus = gst_element_get_bus(p);
    gst_message_unref(gst_bus_timed_pop_filtered(
        bus, GST_CLOCK_TIME_NONE,
        static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR)));
    gst_object_unref(bus);
    gst_object_unref(src);
    gst_element_set_state(p, GST_STATE_NULL);
    gst_object_unref(p);
  }
  const long rss_before = jointflow::bench::residentKiB();

  struct Stream {
    GstElement* pipeline = nullptr;
    std::vector<Clock::time_point> arrivals;
  };
  std::vector<Stream> s(streams);
  std::mutex mutex;
  for (int i = 0; i < streams; ++i) {
    GError* error = nullptr;
    s[i].pipeline = gst_parse_launch(launch(i, input_size).c_str(), &error);
    if (!s[i].pipeline) throw jointflow::Error(error ? error->message : "bad pipeline");
    GstElement* sink =
        gst_bin_get_by_name(GST_BIN(s[i].pipeline), ("sink" + std::to_string(i)).c_str());
    GstPad* pad = gst_element_get_static_pad(sink, "sink");
    gst_pad_add_probe(
        pad, GST_PAD_PROBE_TYPE_BUFFER,
        [](GstPad*, GstPadProbeInfo*, gpointer data) {
          static_cast<Stream*>(data)->arrivals.push_back(Clock::now());
          return GST_PAD_PROBE_OK;
        },
        &s[i], nullptr);
    gst_object_unref(pad);
    gst_object_unref(sink);
    if (gst_element_set_state(s[i].pipeline, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
      throw jointflow::Error("the pipeline does not start: " + launch(i, input_size));
  }
  std::vector<std::thread> feeders;
  for (int i = 0; i < streams; ++i) {
    feeders.emplace_back([&, i] {
      GstElement* src =
          gst_bin_get_by_name(GST_BIN(s[i].pipeline), ("src" + std::to_string(i)).c_str());
      for (int k = 0; k < n; ++k) {
        const size_t bytes = frames[k].total() * frames[k].elemSize();
        GstBuffer* b = gst_buffer_new_allocate(nullptr, bytes, nullptr);
        gst_buffer_fill(b, 0, frames[k].data, bytes);
        GST_BUFFER_PTS(b) = k * GST_SECOND / 10;
        GST_BUFFER_DURATION(b) = GST_SECOND / 10;
        gst_app_src_push_buffer(GST_APP_SRC(src), b);
      }
      gst_app_src_end_of_stream(GST_APP_SRC(src));
      gst_object_unref(src);
    });
  }
  for (auto& t : feeders) t.join();
  for (auto& st : s) {
    GstBus* bus = gst_element_get_bus(st.pipeline);
    GstMessage* m = gst_bus_timed_pop_filtered(
        bus, GST_CLOCK_TIME_NONE, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
    const bool failed = GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR;
    gst_message_unref(m);
    gst_object_unref(bus);
    if (failed) throw jointflow::Error("a pipeline failed: " + launch(0, input_size));
  }
  const long rss_after = jointflow::bench::residentKiB();
  // Aggregate rate: frames after warm-up of all streams over the span they arrived in.
  Clock::time_point first = Clock::time_point::max(), last = Clock::time_point::min();
  std::vector<double> per_stream_ms;
  for (auto& st : s) {
    if (static_cast<int>(st.arrivals.size()) != n) throw jointflow::Error("frames lost");
    first = std::min(first, st.arrivals[warmup - 1]);
    last = std::max(last, st.arrivals.back());
    // Median time between two frames at the sink: robust to a busy machine's pauses.
    std::vector<double> gaps;
    for (int k = warmup; k < n; ++k)
      gaps.push_back(
          std::chrono::duration<double, std::milli>(st.arrivals[k] - st.arrivals[k - 1]).count());
    per_stream_ms.push_back(median(gaps));
  }
  for (auto& st : s) {
    gst_element_set_state(st.pipeline, GST_STATE_NULL);
    gst_object_unref(st.pipeline);
  }
  const double span_s = std::chrono::duration<double>(last - first).count();
  return {{"streams", streams},
          {"input_size", input_size},
          {"ms_per_frame", median(per_stream_ms)},
          {"fps_total", streams * (n - warmup) / span_s},
          {"rss_per_stream_mib", (rss_after - rss_before) / 1024.0 / streams},
          {"rss_mib", (rss_after - rss_before) / 1024.0}};
}

/// A live source faster than inference: videotestsrc is-live at 60 frames/s into jointflowtrack,
/// into a sink that syncs to the clock and reports lateness (QoS). Latency of each buffer at the
/// sink = clock running time when it arrives - its own running time. `policy`: "skip" (the
/// element's default, skip-late-frames=true), "none" (skip-late-frames=false) or "leaky" (a leaky
/// queue of one buffer in front, skip-late-frames=false).
json runLive(const std::string& policy, const std::string& input_size, double seconds) {
  const std::string queue = policy == "leaky"
                                ? "queue leaky=downstream max-size-buffers=1 max-size-bytes=0 "
                                  "max-size-time=0 ! "
                                : "";
  const std::string launch =
      "videotestsrc is-live=true pattern=ball ! video/x-raw,format=BGR,width=320,height=240,"
      "framerate=60/1 ! " +
      queue + "jointflowtrack input-size=" + input_size +
      " skip-late-frames=" + (policy == "skip" ? "true" : "false") +
      " ! fakesink name=sink sync=true qos=true";
  GstElement* pipeline = gst_parse_launch(launch.c_str(), nullptr);
  if (!pipeline) throw jointflow::Error("bad pipeline: " + launch);
  struct Sample {
    double at_s, latency_ms;
    bool predicted;
  };
  struct State {
    GstElement* pipeline;
    std::vector<Sample> samples;
  } state{pipeline, {}};
  GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline), "sink");
  GstPad* pad = gst_element_get_static_pad(sink, "sink");
  gst_pad_add_probe(
      pad, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad* pad, GstPadProbeInfo* info, gpointer data) {
        auto* st = static_cast<State*>(data);
        GstBuffer* buffer = GST_PAD_PROBE_INFO_BUFFER(info);
        GstClock* clock = gst_element_get_clock(st->pipeline);
        GstEvent* seg_event = gst_pad_get_sticky_event(pad, GST_EVENT_SEGMENT, 0);
        if (clock && seg_event) {
          const GstSegment* segment = nullptr;
          gst_event_parse_segment(seg_event, &segment);
          const GstClockTime now =
              gst_clock_get_time(clock) - gst_element_get_base_time(st->pipeline);
          const GstClockTime running =
              gst_segment_to_running_time(segment, GST_FORMAT_TIME, GST_BUFFER_PTS(buffer));
          const GstJointFlowMeta* meta = gst_buffer_get_jointflow_meta(buffer);
          st->samples.push_back(
              {now / 1e9, (static_cast<double>(now) - running) / 1e6, meta && meta->predicted});
        }
        if (seg_event) gst_event_unref(seg_event);
        if (clock) gst_object_unref(clock);
        return GST_PAD_PROBE_OK;
      },
      &state, nullptr);
  gst_object_unref(pad);
  gst_object_unref(sink);
  if (gst_element_set_state(pipeline, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
    throw jointflow::Error("the pipeline does not start: " + launch);
  g_usleep(static_cast<gulong>(seconds * 1e6));
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(pipeline);
  const auto& v = state.samples;
  if (v.size() < 8) throw jointflow::Error("too few buffers reached the sink: " + launch);
  // Latency in the first and the last quarter of the run, and its maximum over the second half.
  auto mean = [&](size_t from, size_t to) {
    double sum = 0;
    for (size_t i = from; i < to; ++i) sum += v[i].latency_ms;
    return sum / static_cast<double>(to - from);
  };
  double max_second_half = 0;
  for (size_t i = v.size() / 2; i < v.size(); ++i)
    max_second_half = std::max(max_second_half, v[i].latency_ms);
  const auto predicted =
      std::count_if(v.begin(), v.end(), [](const Sample& x) { return x.predicted; });
  return {{"policy", policy},
          {"buffers", v.size()},
          {"inferred_per_s", (v.size() - predicted) / seconds},
          {"frames_per_s", v.size() / seconds},
          {"latency_first_quarter_ms", mean(0, v.size() / 4)},
          {"latency_last_quarter_ms", mean(3 * v.size() / 4, v.size())},
          {"latency_max_second_half_ms", max_second_half}};
}

json runChild(const std::string& self, const std::string& args) {
  const std::string command = self + " " + args;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) throw jointflow::Error("cannot run " + command);
  std::string out;
  char buf[4096];
  while (fgets(buf, sizeof buf, pipe)) out += buf;
  if (pclose(pipe) != 0) throw jointflow::Error(command + " failed: " + out);
  return json::parse(out.substr(out.rfind('{')));
}

// ---- 1, 2: networks ------------------------------------------------------------------------

/// The element against the bare network, measured frame by frame in turn so that both see the
/// same machine load: for each frame, (a) the frame through appsrc ! jointflowtrack ! appsink
/// (push to pull), (b) SpatialModel::estimate of that frame (its forward pass timed on its own),
/// (c) jointflow::Tracker::process of that frame (spatial model + association, no GStreamer).
struct SpatialTime {
  double forward_ms = 0, estimate_ms = 0, tracker_ms = 0, pipeline_ms = 0;
  double tff_ms = -1;  ///< the TFF runner on this frame's and the previous frame's maps; -1 = none
  cv::Size input;
  jointflow::SpatialResult last;
};

SpatialTime timeSpatial(const std::vector<cv::Mat>& frames, const std::string& input_size,
                        int warmup, const std::string& tff_path, const std::string& backend) {
  jointflow::SpatialOptions o;
  o.input_size = jointflow::InputSize::parse(input_size);
  auto model = jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, o);
  jointflow::TrackerSettings ts;
  ts.model_type = jointflow::ModelType::kMoveNet;
  ts.spatial = o;
  jointflow::Tracker tracker(ts);
  const int w = frames[0].cols, h = frames[0].rows;
  const std::string launch =
      "appsrc name=src format=time caps=video/x-raw,format=BGR,width=" + std::to_string(w) +
      ",height=" + std::to_string(h) +
      ",framerate=10/1 ! jointflowtrack similarity=oks input-size=" + input_size +
      " backend=" + backend + " ! appsink name=out sync=false";
  GstElement* pipeline = gst_parse_launch(launch.c_str(), nullptr);
  if (!pipeline || gst_element_set_state(pipeline, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
    throw jointflow::Error("the pipeline does not start: " + launch);
  GstElement* src = gst_bin_get_by_name(GST_BIN(pipeline), "src");
  GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline), "out");
  std::vector<double> fwd, all, tracked, piped, tffs;
  SpatialTime t;
  std::unique_ptr<jointflow::TemporalFlowModel> tff;
  for (size_t i = 0; i < frames.size(); ++i) {
    const size_t bytes = frames[i].total() * frames[i].elemSize();
    GstBuffer* buffer = gst_buffer_new_allocate(nullptr, bytes, nullptr);
    gst_buffer_fill(buffer, 0, frames[i].data, bytes);
    GST_BUFFER_PTS(buffer) = i * GST_SECOND / 10;
    auto t0 = Clock::now();
    gst_app_src_push_buffer(GST_APP_SRC(src), buffer);
    // OpenVINO: the element holds a frame while its network runs, so frame i brings out frame
    // i - 1 (the first brings out none; EOS brings out the last).
    const bool held = backend == "openvino";
    if (held && i + 1 == frames.size()) gst_app_src_end_of_stream(GST_APP_SRC(src));
    GstSample* sample = held && i == 0 ? nullptr : gst_app_sink_pull_sample(GST_APP_SINK(sink));
    const double pipeline_ms = msSince(t0);
    if (!sample && !(held && i == 0)) throw jointflow::Error("the pipeline stopped: " + launch);
    if (sample) gst_sample_unref(sample);
    t0 = Clock::now();
    t.last = model->estimate(frames[i]);
    const double estimate_ms = msSince(t0);
    t0 = Clock::now();
    tracker.process(frames[i]);
    const double tracker_ms = msSince(t0);
    // The TFF network on the maps of this frame and the last, in turn with the spatial network.
    double tff_ms = -1;
    if (!tff_path.empty()) {
      if (!tff)
        tff = std::make_unique<jointflow::TemporalFlowModel>(tff_path, t.last.features.size[1],
                                                             o.dnn);
      t0 = Clock::now();
      const cv::Mat field = tff->predict(t.last.features, t.last.beliefs);
      tff_ms = field.empty() ? -1 : msSince(t0);
    }
    if (static_cast<int>(i) < warmup) continue;
    if (tff_ms >= 0) tffs.push_back(tff_ms);
    piped.push_back(pipeline_ms);
    all.push_back(estimate_ms);
    tracked.push_back(tracker_ms);
    fwd.push_back(model->lastTimings().forward_ms);
  }
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(src);
  gst_object_unref(sink);
  gst_object_unref(pipeline);
  t.forward_ms = median(fwd);
  t.estimate_ms = median(all);
  t.tracker_ms = median(tracked);
  t.pipeline_ms = median(piped);
  if (!tffs.empty()) t.tff_ms = median(tffs);
  t.input = {static_cast<int>(std::lround(t.last.beliefs.size[3] * 4.0)),
             static_cast<int>(std::lround(t.last.beliefs.size[2] * 4.0))};
  return t;
}

/// cv::dnn alone on the ONNX file: random input of the model's range, every graph output; the
/// median forward time and the share of each layer type in it (getPerfProfile).
struct DnnTime {
  double ms = 0;
  std::vector<std::pair<std::string, double>> by_type;   ///< type, ms; largest first
  std::vector<std::pair<std::string, double>> by_layer;  ///< "name (type)", ms; largest first
};

DnnTime timeDnn(const std::string& path, cv::Size size, int runs, bool fuse = true) {
  cv::dnn::Net net = cv::dnn::readNetFromONNX(path);
  net.enableFusion(fuse);
  const auto outs = net.getUnconnectedOutLayersNames();
  cv::Mat blob(std::vector<int>{1, 3, size.height, size.width}, CV_32F);
  cv::randu(blob, 0.f, 255.f);
  net.setInput(blob);
  std::vector<cv::Mat> out;
  for (int i = 0; i < 3; ++i) net.forward(out, outs);
  std::vector<double> ms;
  std::map<std::string, double> types, layers;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = Clock::now();
    net.forward(out, outs);
    ms.push_back(msSince(t0));
    std::vector<double> layer_ticks;
    net.getPerfProfile(layer_ticks);
    const auto ids = net.getLayerNames();
    for (size_t l = 0; l < layer_ticks.size() && l < ids.size(); ++l) {
      const cv::Ptr<cv::dnn::Layer> layer = net.getLayer(ids[l]);
      const double layer_ms = layer_ticks[l] * 1000.0 / cv::getTickFrequency() / runs;
      types[layer->type] += layer_ms;
      layers[ids[l] + " (" + layer->type + ")"] += layer_ms;
    }
  }
  DnnTime t;
  t.ms = median(ms);
  const auto largest_first = [](const auto& a, const auto& b) { return a.second > b.second; };
  t.by_type.assign(types.begin(), types.end());
  std::sort(t.by_type.begin(), t.by_type.end(), largest_first);
  t.by_layer.assign(layers.begin(), layers.end());
  std::sort(t.by_layer.begin(), t.by_layer.end(), largest_first);
  return t;
}

/// The bare network on an engine (DnnOptions): the same kind of input as timeDnn, every graph
/// output, median of `runs` after 3 warm-up runs.
double timeEngine(const std::string& path, cv::Size size, int runs,
                  const jointflow::DnnOptions& dnn) {
  auto net = jointflow::detail::openNetwork(path, "bench", {}, dnn);
  const auto outs = net->outputNames();
  cv::Mat blob(std::vector<int>{1, 3, size.height, size.width}, CV_32F);
  cv::randu(blob, 0.f, 255.f);
  for (int i = 0; i < 3; ++i) net->run(blob, outs);
  std::vector<double> ms;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = Clock::now();
    net->run(blob, outs);
    ms.push_back(msSince(t0));
  }
  return median(ms);
}

std::string fmt(double v, int digits = 1) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

}  // namespace

int main(int argc, char** argv) {
  gst_init(&argc, &argv);
  CLI::App app{"JointFlow performance budgets (issues 7 and 13)"};
  std::string video = JOINTFLOW_VTEST_AVI, out = "docs/benchmarks.md", python, child_size;
  std::string models = jointflow::defaultModelsDir(), ort_script;
  int frames = 30, threads = static_cast<int>(std::thread::hardware_concurrency()),
      child_streams = 0;
  app.add_option("--video", video, "video file (default: opencv-doc's vtest.avi)");
  app.add_option("--frames", frames, "frames per measurement (3 of them warm-up)")
      ->check(CLI::Range(6, 100000));
  app.add_option("--threads", threads, "threads of cv::dnn and onnxruntime")
      ->check(CLI::Range(1, 256));
  app.add_option("--python", python, "python with onnxruntime (empty: no onnxruntime column)");
  app.add_option("--ort-script", ort_script, "bench/ort_time.py");
  app.add_option("--out", out, "Markdown file to write (empty: none)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);  // bench/run.sh gives a default
  app.add_option("--child", child_streams, "internal: run N pipelines, print JSON");
  app.add_option("--child-size", child_size, "internal: input-size of the child's pipelines");
  std::string child_props;
  app.add_option("--child-props", child_props, "internal: more jointflowtrack properties");
  int agreement_stride = 1;
  app.add_option("--agreement-stride", agreement_stride,
                 "person counts of the two engines on every Nth frame of the video")
      ->check(CLI::Range(1, 1000));
  std::string child_live;
  double live_seconds = 12;
  app.add_option("--child-live", child_live, "internal: run the live test with this policy");
  app.add_option("--live-seconds", live_seconds, "seconds of each live-source run")
      ->check(CLI::Range(2.0, 3600.0));
  CLI11_PARSE(app, argc, argv);
  cv::setNumThreads(threads);
  constexpr int kWarmup = 3;

  try {
    if (!child_live.empty()) {
      std::cout << runLive(child_live, child_size, live_seconds).dump() << std::endl;
      return 0;
    }
    const std::vector<cv::Mat> images = readFrames(video, frames);
    if (child_streams > 0) {
      std::cout << runPipelines(images, child_streams, child_size, kWarmup, child_props).dump()
                << std::endl;
      return 0;
    }
    const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
    const std::string base = "--video '" + video + "' --frames " + std::to_string(frames) +
                             " --threads " + std::to_string(threads);
    const std::string load_before = loadAverage();
    const std::string movenet = models + "/movenet_multipose.onnx";
    const std::string tff_path = models + "/tff_movenet.onnx";
    const cv::Size native = images[0].size();

    // The engines of this build: cv::dnn always, OpenVINO where it was built with it.
    std::vector<std::pair<std::string, std::string>> engines = {{"default", "cv::dnn"}};
    std::string openvino_name, openvino_missing;
    try {
      jointflow::DnnOptions d;
      d.backend = jointflow::DnnBackend::kOpenVino;
      jointflow::SpatialOptions o;
      o.dnn = d;
      openvino_name = jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, o)->engine();
      engines.emplace_back("openvino", "OpenVINO");
    } catch (const std::exception& e) {
      openvino_missing = e.what();
    }
    const bool have_ov = openvino_missing.empty();

    std::ostringstream md;
    md << "# Benchmarks\n\nWritten by `make bench` (bench/run.sh -> build/bench/jointflow-bench, "
          "bench/jointflow_bench.cpp) in one run on one machine: "
       << images.size() << " frames of vtest.avi (" << native.width << "x" << native.height << ", "
       << kWarmup << " of them warm-up, medians), on the CPU with " << threads << " threads, "
       << std::thread::hardware_concurrency() << " hardware threads, load average " << load_before
       << " before the run. Engines: OpenCV " << CV_VERSION << " dnn (cv::dnn, the default) and "
       << (have_ov ? openvino_name + " (backend=openvino, its default precision)"
                   : "no OpenVINO (" + openvino_missing + ")")
       << ". The spatial model is MoveNet MultiPose, similarity oks. The machine is shared: "
          "absolute times move with its load, so compare the ratios, each taken within this "
          "one run.\n\n";

    // 1 + 4: spatial network and pipelines, per engine and size.
    const std::vector<std::string> sizes = {"256x256", "max:640", "native"};
    md << "## Element pipeline against the bare spatial network\n\n"
          "Forward = the spatial network's forward pass; estimate adds its pre-processing and "
          "decoding; tracker = jointflow::Tracker::process (spatial model + association, no "
          "GStreamer); pipeline in turn = `appsrc ! jointflowtrack ! appsink`, push to pull, one "
          "frame at a time (with OpenVINO frame i brings out frame i - 1: the element holds one "
          "frame while its network runs). These four are measured frame by frame in turn in one "
          "process, so that all see the same load. Pipeline alone = the same element in a "
          "process of its own, fed as fast as it takes frames (median time between two frames "
          "at the sink), tracking included: 1000 / it is the element's frames/s. Overhead = "
          "pipeline alone / forward (target <= 1.05).\n\n"
          "| engine | input size | network input | forward (ms) | estimate (ms) | tracker (ms) "
          "| pipeline in turn (ms) | pipeline alone (ms) | frames/s | overhead | target "
          "|\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::ostringstream streams_md;
    streams_md << "## Frames/s and memory per stream\n\n"
                  "K pipelines in one process, each fed from its own thread as fast as it takes "
                  "frames. Memory = growth of the process's resident memory from before the K "
                  "pipelines were made to after their last frame (one pipeline at 64x64 ran "
                  "before, to load the libraries and the model file's bytes). OpenVINO's "
                  "streams share one compiled model (model-instance-id) unless the row says "
                  "otherwise.\n\n"
                  "| engine | input size | streams | ms/frame per stream | frames/s, all streams "
                  "| memory (MiB) | per stream (MiB) |\n|---|---|---|---|---|---|---|\n";
    auto streamRow = [&](const std::string& engine, const json& r, const std::string& note) {
      streams_md << "| " << engine << " | " << r["input_size"].get<std::string>() << " | "
                 << r["streams"].get<int>() << note << " | " << fmt(r["ms_per_frame"].get<double>())
                 << " | " << fmt(r["fps_total"].get<double>(), 2) << " | "
                 << fmt(r["rss_mib"].get<double>()) << " | "
                 << fmt(r["rss_per_stream_mib"].get<double>()) << " |\n";
    };
    std::map<std::string, std::map<std::string, SpatialTime>> spatial;
    std::map<std::string, std::map<std::string, double>> fps;
    for (const auto& [backend, engine] : engines) {
      const std::string props =
          "backend=" + backend + (backend == "openvino" ? " model-instance-id=bench" : "");
      for (const std::string& size : sizes) {
        spatial[backend][size] = timeSpatial(
            images, size, kWarmup, std::filesystem::exists(tff_path) ? tff_path : "", backend);
        const SpatialTime& st = spatial[backend][size];
        const json one = runChild(
            self, base + " --child 1 --child-size " + size + " --child-props '" + props + "'");
        const double alone_ms = one["ms_per_frame"];
        fps[backend][size] = 1000.0 / alone_ms;
        md << "| " << engine << " | " << size << " | " << st.input.width << "x" << st.input.height
           << " | " << fmt(st.forward_ms) << " | " << fmt(st.estimate_ms) << " | "
           << fmt(st.tracker_ms) << " | " << fmt(st.pipeline_ms) << " | " << fmt(alone_ms) << " | "
           << fmt(1000.0 / alone_ms) << " | " << fmt(alone_ms / st.forward_ms, 2)
           << " | <= 1.05 |\n";
        streamRow(engine, one, "");
        streamRow(engine,
                  runChild(self, base + " --child 4 --child-size " + size + " --child-props '" +
                                     props + "'"),
                  "");
      }
    }
    if (have_ov) {
      md << "\nOpenVINO against cv::dnn, end to end (pipeline alone, frames/s ratio; target at "
            "max:640 >= 2.5): ";
      for (const std::string& size : sizes)
        md << size << " " << fmt(fps["openvino"][size] / fps["default"][size], 2) << "x"
           << (size == sizes.back() ? ".\n" : ", ");
      md << "Targets with tracking: >= 15 frames/s at max:640 (measured "
         << fmt(fps["openvino"]["max:640"]) << "), >= 40 frames/s at 256x256 (measured "
         << fmt(fps["openvino"]["256x256"]) << ").\n";
      // Sharing: 4 streams on one compiled model against 2 streams with a model each.
      const json separate =
          runChild(self, base + " --child 2 --child-size max:640 --child-props 'backend=openvino'");
      const json shared = runChild(self, base +
                                             " --child 4 --child-size max:640 --child-props "
                                             "'backend=openvino model-instance-id=bench'");
      streamRow("OpenVINO", separate, " (a model each)");
      streamRow("OpenVINO", shared, " (one shared model)");
      streams_md << "\nMemory target: 4 streams sharing one model (" << fmt(shared["rss_mib"])
                 << " MiB) take less than 2 streams with a model each (" << fmt(separate["rss_mib"])
                 << " MiB): "
                 << (shared["rss_mib"].get<double>() < separate["rss_mib"].get<double>() ? "met"
                                                                                         : "missed")
                 << ".\n";
    }

    // 2: TFF against spatial.
    md << "\n## TFF network against the spatial network\n\n";
    if (std::filesystem::exists(tff_path)) {
      md << "`" << tff_path.substr(tff_path.rfind('/') + 1)
         << "` (the runner's predict(): the maps of a frame and of the one before in, TFF out) "
            "against MoveNet's forward pass on the same engine, on the same frames in turn "
            "(target <= 0.25).\n\n"
            "| engine | input size | spatial forward (ms) | TFF (ms) | ratio | target "
            "|\n|---|---|---|---|---|---|\n";
      for (const auto& [backend, engine] : engines)
        for (const std::string& size : sizes) {
          const SpatialTime& st = spatial[backend][size];
          md << "| " << engine << " | " << size << " | " << fmt(st.forward_ms) << " | "
             << fmt(st.tff_ms) << " | " << fmt(st.tff_ms / st.forward_ms, 3) << " | <= 0.25 |\n";
        }
    } else {
      md << "Not measured: " << tff_path << " is absent (the trained TFF network).\n";
    }

    // 3: the engines on the same file.
    md << "\n## cv::dnn, OpenVINO and onnxruntime on the same ONNX file\n\n"
          "`movenet_multipose.onnx`, random input of its range, every graph output, "
       << threads << " threads each, then 1 thread each; median of " << frames
       << " runs after 3 warm-up runs, all in this process but onnxruntime (a Python process "
          "of its own). OpenVINO with its default precision ("
       << (have_ov ? openvino_name.substr(openvino_name.rfind(' ') + 1) : "-")
       << " here) and with f32.\n\n"
       << "| input | cv::dnn (ms) | OpenVINO (ms) | OpenVINO f32 (ms) | onnxruntime (ms) | "
          "cv::dnn / OpenVINO | cv::dnn / onnxruntime |\n|---|---|---|---|---|---|---|\n";
    std::vector<std::pair<cv::Size, DnnTime>> profiles;
    auto ortMs = [&](cv::Size size, int n_threads) -> std::pair<double, std::string> {
      const std::string cmd = python + " " + ort_script + " " + movenet + " " +
                              std::to_string(size.height) + " " + std::to_string(size.width) + " " +
                              std::to_string(n_threads) + " " + std::to_string(frames);
      FILE* pipe = popen(cmd.c_str(), "r");
      std::string text;
      char buf[4096];
      while (pipe && fgets(buf, sizeof buf, pipe)) text += buf;
      if (!pipe || pclose(pipe) != 0 || text.find('{') == std::string::npos)
        throw jointflow::Error("onnxruntime timing failed: " + cmd + "\n" + text);
      const json r = json::parse(text.substr(text.rfind('{')));
      return {r["ort_ms"].get<double>(), r["ort_version"].get<std::string>()};
    };
    const cv::Size max640(
        640, static_cast<int>(std::lround(640.0 * native.height / native.width / 32.0)) * 32);
    for (const int n_threads : {threads, 1}) {
      cv::setNumThreads(n_threads);
      for (const cv::Size size : {cv::Size(256, 256), max640, native}) {
        const DnnTime dnn = timeDnn(movenet, size, frames);
        std::string ov_cell = "n/a", ov32_cell = "n/a", ratio_ov = "n/a";
        if (have_ov) {
          jointflow::DnnOptions d;
          d.backend = jointflow::DnnBackend::kOpenVino;
          d.num_threads = n_threads;
          const double ov = timeEngine(movenet, size, frames, d);
          d.precision = "f32";
          const double ov32 = timeEngine(movenet, size, frames, d);
          ov_cell = fmt(ov);
          ov32_cell = fmt(ov32);
          ratio_ov = fmt(dnn.ms / ov, 2);
        }
        std::string ort_cell = "n/a (no --python)", ratio_cell = "n/a";
        if (!python.empty()) {
          const auto [ort, version] = ortMs(size, n_threads);
          ort_cell = fmt(ort) + " (" + version + ")";
          ratio_cell = fmt(dnn.ms / ort, 2);
        }
        md << "| " << size.width << "x" << size.height << ", " << n_threads << " thread"
           << (n_threads > 1 ? "s" : "") << " | " << fmt(dnn.ms) << " | " << ov_cell << " | "
           << ov32_cell << " | " << ort_cell << " | " << ratio_ov << " | " << ratio_cell << " |\n";
        if (n_threads == threads && size != max640) profiles.emplace_back(size, dnn);
      }
    }
    cv::setNumThreads(threads);
    md << "\ncv::dnn's time by layer type (getPerfProfile, mean per forward pass):\n\n"
          "| input | layer type | ms | share |\n|---|---|---|---|\n";
    for (const auto& [size, dnn] : profiles) {
      double total = 0;
      for (const auto& [type, ms] : dnn.by_type) total += ms;
      for (size_t i = 0; i < dnn.by_type.size() && i < 6; ++i) {
        md << "| " << size.width << "x" << size.height << " | " << dnn.by_type[i].first << " | "
           << fmt(dnn.by_type[i].second, 2) << " | " << fmt(100.0 * dnn.by_type[i].second / total)
           << " % |\n";
      }
    }
    md << "\nThe slowest layers at " << profiles[0].first.width << "x" << profiles[0].first.height
       << ":\n\n| layer | ms |\n|---|---|\n";
    for (size_t i = 0; i < profiles[0].second.by_layer.size() && i < 10; ++i)
      md << "| " << profiles[0].second.by_layer[i].first << " | "
         << fmt(profiles[0].second.by_layer[i].second, 2) << " |\n";
    md << "\n" << streams_md.str();

    // Person counts of the two engines on the whole video (tests/engine checks every 6th frame).
    if (have_ov) {
      jointflow::SpatialOptions o;  // max:640
      auto dnn = jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, o);
      o.dnn.backend = jointflow::DnnBackend::kOpenVino;
      auto ov = jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, o);
      cv::VideoCapture capture(video);
      int n = 0, within = 0, equal = 0;
      cv::Mat f;
      for (int i = 0; capture.read(f); ++i) {
        if (i % agreement_stride) continue;
        const int a = static_cast<int>(dnn->estimate(f).poses.size());
        const int b = static_cast<int>(ov->estimate(f).poses.size());
        n++;
        within += std::abs(a - b) <= 1;
        equal += a == b;
      }
      md << "\n## Person counts of the two engines\n\nMoveNet at max:640 on "
         << (agreement_stride == 1 ? "every frame"
                                   : "every " + std::to_string(agreement_stride) + "th frame")
         << " of vtest.avi (" << n << " frames), cv::dnn against " << openvino_name
         << ": the counts agree within 1 on " << within << " frames ("
         << fmt(100.0 * within / std::max(n, 1)) << " %, target >= 95 %) and are equal on " << equal
         << " (" << fmt(100.0 * equal / std::max(n, 1)) << " %).\n";
    }

    // 5: a live source faster than inference.
    md << "\n## Live source faster than inference\n\n"
          "`videotestsrc is-live=true` at 60 frames/s (320x240) into jointflowtrack "
          "(input-size=native) into `fakesink sync=true qos=true`, "
       << fmt(live_seconds, 0)
       << " s per policy (docs/gstreamer.md, live policy). Latency = the clock's running time "
          "when a buffer reaches the sink - the buffer's running time.\n\n"
          "| policy | buffers/s at the sink | inferred/s | latency, first quarter (ms) | "
          "latency, last quarter (ms) | max latency, second half (ms) |\n"
          "|---|---|---|---|---|---|\n";
    const std::map<std::string, std::string> policy_names = {
        {"skip", "skip-late-frames=true (default)"},
        {"leaky", "leaky queue of 1, skip-late-frames=false"},
        {"none", "neither (skip-late-frames=false, no queue)"}};
    for (const std::string policy : {"skip", "leaky", "none"}) {
      const json r =
          runChild(self, "--child-live " + policy + " --child-size native --live-seconds " +
                             fmt(live_seconds, 1) + " --threads " + std::to_string(threads));
      md << "| " << policy_names.at(policy) << " | " << fmt(r["frames_per_s"].get<double>())
         << " | " << fmt(r["inferred_per_s"].get<double>()) << " | "
         << fmt(r["latency_first_quarter_ms"].get<double>(), 0) << " | "
         << fmt(r["latency_last_quarter_ms"].get<double>(), 0) << " | "
         << fmt(r["latency_max_second_half_ms"].get<double>(), 0) << " |\n";
    }
    std::cout << md.str();
    if (!out.empty()) {
      std::ofstream file(out);
      if (!file) throw jointflow::Error("cannot write " + out);
      file << md.str();
      std::cout << "\nwritten to " << out << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "jointflow-bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
