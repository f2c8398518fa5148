// jointflow-bench: the performance budgets of issues 7 and 13, all measured in one run on one
// machine, for each engine (cv::dnn, and OpenVINO where the build has it).
//
//   1. jointflowtrack end to end against the bare spatial network at the same input size
//      (overhead, target <= 1.05), at 256x256, max:640 and native, with where the time goes
//      (pre-processing, forward, decoding, camera motion, association, GStreamer); OpenVINO's
//      speed-up over cv::dnn end to end; what the held frame (async-inference) gains, with the
//      frames coming raw from another thread and decoded in the element's own thread;
//   2. the TFF network against the spatial network (target <= 0.25);
//   3. cv::dnn, OpenVINO and onnxruntime on the same ONNX file and input shape, with cv::dnn's
//      time per layer type (Net::getPerfProfile) to show where it goes;
//   4. frames/s and memory of 1 and 4 streams; OpenVINO's streams sharing one compiled model
//      (model-instance-id) against streams with a model each;
//   5. the person counts of the two engines on the frames of vtest.avi;
//   6. a live source faster than inference.
// The machine may be shared and loaded: every comparison takes turns between what it compares,
// block by block or run by run, in one process, and reports the median of the per-round ratios,
// so that both sides see the same load. Each pipeline set-up whose memory is reported runs in a
// child process of its own (this program, --child ...). Prints Markdown and writes it to --out.
//
//   jointflow-bench [--block 6] [--rounds 4] [--runs 20] [--threads N] [--python venv/bin/python]
//                   [--ort-script bench/ort_time.py] [--out docs/benchmarks.md]
#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
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
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "resident_memory.hpp"

#include "../core/engine/network.hpp"
#include "../core/tracking/camera_motion.hpp"
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

/// CPU time of the whole process so far (every thread: ours, OpenCV's, OpenVINO's), ms.
double cpuMs() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return (ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) * 1e3 +
         (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) / 1e3;
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

std::string fmt(double v, int digits = 1) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

std::vector<cv::Mat> readFrames(const std::string& video, int count, int stride = 1) {
  cv::VideoCapture capture(video);
  if (!capture.isOpened()) throw jointflow::Error("cannot open the video " + video);
  std::vector<cv::Mat> frames;
  cv::Mat f;
  for (int i = 0; (count <= 0 || static_cast<int>(frames.size()) < count) && capture.read(f); ++i)
    if (i % stride == 0) frames.push_back(f.clone());
  if (frames.size() < 4) throw jointflow::Error(video + " has fewer than 4 frames");
  return frames;
}

// ---- 4, 6: streams and the live source (in child processes) ---------------------------------

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
    // Mean time between two frames at the sink. Not the median: with OpenVINO a stream's frames
    // leave in pairs when their runs, queued behind each other, end together (4 streams on one
    // model: median 28 ms, mean 113 ms), and the median gap then is the short one.
    per_stream_ms.push_back(
        std::chrono::duration<double, std::milli>(st.arrivals.back() - st.arrivals[warmup - 1])
            .count() /
        (n - warmup));
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
  // The child's last line is its JSON (GStreamer or OpenVINO may print before it).
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return json::parse(out.substr(out.rfind('\n') + 1));
}

// ---- 1, 2: the element end to end against the bare network (in a child process per size) ----

/// A pipeline kept PLAYING and fed block by block from a thread of its own, as fast as it takes
/// frames (appsrc block=true). Arrival times at the sink give the time per frame: the median gap
/// between two frames leaving the element, tracking and everything upstream in its thread
/// included.
class FedPipeline {
 public:
  /// `held`: frames the element keeps back (1 with the held frame of async-inference).
  FedPipeline(const std::string& launch, int held) : launch_(launch), held_(held) {
    GError* error = nullptr;
    pipeline_ = gst_parse_launch(launch.c_str(), &error);
    if (!pipeline_)
      throw jointflow::Error("bad pipeline " + launch + ": " + (error ? error->message : "?"));
    src_ = gst_bin_get_by_name(GST_BIN(pipeline_), "src");
    GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline_), "sink");
    GstPad* pad = gst_element_get_static_pad(sink, "sink");
    gst_pad_add_probe(
        pad, GST_PAD_PROBE_TYPE_BUFFER,
        [](GstPad*, GstPadProbeInfo*, gpointer data) {
          auto* self = static_cast<FedPipeline*>(data);
          std::lock_guard<std::mutex> lock(self->mutex_);
          self->arrivals_.push_back(Clock::now());
          self->arrived_.notify_all();
          return GST_PAD_PROBE_OK;
        },
        this, nullptr);
    gst_object_unref(pad);
    gst_object_unref(sink);
    if (gst_element_set_state(pipeline_, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
      throw jointflow::Error("the pipeline does not start: " + launch);
  }
  ~FedPipeline() {
    gst_element_set_state(pipeline_, GST_STATE_NULL);
    gst_object_unref(src_);
    gst_object_unref(pipeline_);
  }
  FedPipeline(const FedPipeline&) = delete;
  FedPipeline& operator=(const FedPipeline&) = delete;

  struct Block {
    std::vector<double> gaps_ms;  ///< between frames leaving, the block's first arrival excluded
    double cpu_ms = 0;            ///< the process's CPU time over the block, per frame
  };

  /// Pushes one buffer per payload (the bytes are wrapped, not copied) and waits until all but
  /// the held frames of everything pushed so far have left.
  Block run(const std::vector<std::pair<const unsigned char*, size_t>>& payloads) {
    const double cpu0 = cpuMs();
    size_t first;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      first = arrivals_.size();
    }
    std::thread feeder([&] {
      for (const auto& [data, bytes] : payloads) {
        GstBuffer* b =
            gst_buffer_new_wrapped_full(GST_MEMORY_FLAG_READONLY, const_cast<unsigned char*>(data),
                                        bytes, 0, bytes, nullptr, nullptr);
        GST_BUFFER_PTS(b) = pushed_ * GST_SECOND / 10;
        GST_BUFFER_DURATION(b) = GST_SECOND / 10;
        ++pushed_;
        gst_app_src_push_buffer(GST_APP_SRC(src_), b);
      }
    });
    const size_t target = pushed_total_ + payloads.size() - held_;
    GstBus* bus = gst_element_get_bus(pipeline_);
    std::unique_lock<std::mutex> lock(mutex_);
    while (arrivals_.size() < target) {
      arrived_.wait_for(lock, std::chrono::milliseconds(200));
      if (GstMessage* m = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR)) {
        gst_message_unref(m);
        lock.unlock();
        // The feeder may be blocked in a full appsrc: stopping the pipeline flushes it.
        gst_element_set_state(pipeline_, GST_STATE_NULL);
        feeder.join();
        gst_object_unref(bus);
        throw jointflow::Error("the pipeline failed: " + launch_);
      }
    }
    lock.unlock();
    feeder.join();
    gst_object_unref(bus);
    pushed_total_ += payloads.size();
    Block block;
    block.cpu_ms = (cpuMs() - cpu0) / static_cast<double>(payloads.size());
    std::lock_guard<std::mutex> relock(mutex_);
    for (size_t k = first + 1; k < arrivals_.size(); ++k)
      block.gaps_ms.push_back(
          std::chrono::duration<double, std::milli>(arrivals_[k] - arrivals_[k - 1]).count());
    return block;
  }

 private:
  std::string launch_;
  int held_;
  GstElement* pipeline_ = nullptr;
  GstElement* src_ = nullptr;
  std::atomic<std::uint64_t> pushed_{0};
  size_t pushed_total_ = 0;
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::vector<Clock::time_point> arrivals_;
};

/// The per-frame samples of one measurement and their per-round medians.
struct Series {
  std::vector<double> samples;
  std::vector<double> rounds;  ///< median of each round
  std::vector<double> cpu;     ///< CPU ms per frame of each round
  void add(const std::vector<double>& block, double cpu_per_frame = -1) {
    samples.insert(samples.end(), block.begin(), block.end());
    rounds.push_back(median(block));
    if (cpu_per_frame >= 0) cpu.push_back(cpu_per_frame);
  }
};

/// Median over the rounds of a / b, each round's medians.
double roundRatio(const Series& a, const Series& b) {
  std::vector<double> r;
  for (size_t i = 0; i < a.rounds.size() && i < b.rounds.size(); ++i)
    if (b.rounds[i] > 0) r.push_back(a.rounds[i] / b.rounds[i]);
  return median(r);
}

/// One engine's rig at one input size: the bare spatial model, the TFF network, the core's
/// Tracker and four elements (raw frames from a thread; JPEG decoded in the element's thread;
/// each with async-inference on and, with an asynchronous engine, off), all on one compiled
/// model per network where the engine shares (model-instance-id).
struct Rig {
  std::string backend;
  std::unique_ptr<jointflow::SpatialModel> model;
  std::unique_ptr<jointflow::TemporalFlowModel> tff;
  std::unique_ptr<jointflow::Tracker> tracker;
  std::map<std::string, std::unique_ptr<FedPipeline>> elements;
  std::map<std::string, Series> series;
  std::vector<jointflow::SpatialResult> last;  ///< the bare model's results of the last block
  double time = 0;                             ///< the tracker's stream time, s
};

/// `--child-e2e SIZE`: the rigs of every engine at one input size, measured in rounds; in each
/// round every measurement runs one block of frames, engine after engine, so that a comparison
/// within a round sees one machine load.
json runEndToEnd(const std::vector<cv::Mat>& frames, const std::vector<std::string>& backends,
                 const std::string& size, int block, int rounds, const std::string& tff_path) {
  const int w = frames[0].cols, h = frames[0].rows;
  std::vector<std::vector<unsigned char>> jpegs;
  for (const cv::Mat& f : frames) {
    jpegs.emplace_back();
    cv::imencode(".jpg", f, jpegs.back(), {cv::IMWRITE_JPEG_QUALITY, 90});
  }
  std::vector<cv::Mat> greys;
  for (const cv::Mat& f : frames) {
    greys.emplace_back();
    cv::cvtColor(f, greys.back(), cv::COLOR_BGR2GRAY);
  }
  std::vector<Rig> rigs;
  for (const std::string& backend : backends) {
    Rig r;
    r.backend = backend;
    jointflow::SpatialOptions o;
    o.input_size = jointflow::InputSize::parse(size);
    o.dnn.backend =
        backend == "openvino" ? jointflow::DnnBackend::kOpenVino : jointflow::DnnBackend::kDefault;
    if (backend == "openvino") o.dnn.model_instance_id = "bench-e2e";
    r.model = jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, o);
    if (!tff_path.empty())
      r.tff = std::make_unique<jointflow::TemporalFlowModel>(tff_path, r.model->featureChannels(),
                                                             o.dnn);
    jointflow::TrackerSettings ts;
    ts.model_type = jointflow::ModelType::kMoveNet;
    ts.spatial = o;
    r.tracker = std::make_unique<jointflow::Tracker>(ts);
    auto propsWith = [&](const std::string& similarity) {
      return "jointflowtrack input-size=" + size + " similarity=" + similarity +
             " backend=" + backend + (backend == "openvino" ? " model-instance-id=bench-e2e" : "");
    };
    const std::string props = propsWith("oks");
    const std::string raw =
        "appsrc name=src format=time block=true max-buffers=2 "
        "caps=video/x-raw,format=BGR,width=" +
        std::to_string(w) + ",height=" + std::to_string(h) + ",framerate=10/1 ! ";
    const std::string jpeg =
        "appsrc name=src format=time block=true max-buffers=2 "
        "caps=image/jpeg,width=" +
        std::to_string(w) + ",height=" + std::to_string(h) +
        ",framerate=10/1 ! jpegdec ! videoconvert ! "
        "video/x-raw,format=BGR ! ";
    const std::string sink = " ! fakesink name=sink sync=false";
    const bool async = r.model->asynchronous();
    r.elements["element"] = std::make_unique<FedPipeline>(raw + props + sink, async ? 1 : 0);
    r.elements["jpeg"] = std::make_unique<FedPipeline>(jpeg + props + sink, async ? 1 : 0);
    // A still camera's setting: no camera-motion estimate, the part of the overhead it costs.
    r.elements["element-still"] = std::make_unique<FedPipeline>(
        raw + props + " camera-compensation=false" + sink, async ? 1 : 0);
    // The paper's similarity end to end: the TFF network on the element's thread, beside the
    // next frame's spatial run where the engine queues it.
    if (!tff_path.empty())
      r.elements["element-tff"] =
          std::make_unique<FedPipeline>(raw + propsWith("tff") + sink, async ? 1 : 0);
    if (async) {
      r.elements["element-sync"] =
          std::make_unique<FedPipeline>(raw + props + " async-inference=false" + sink, 0);
      r.elements["jpeg-sync"] =
          std::make_unique<FedPipeline>(jpeg + props + " async-inference=false" + sink, 0);
    }
    rigs.push_back(std::move(r));
  }

  Series camera;
  const int n = static_cast<int>(frames.size());
  // Round 0 warms everything up (compiled models per shape, caches) and is not counted.
  for (int round = 0; round <= rounds; ++round) {
    const int from = (round * block) % std::max(1, n - block);
    std::vector<int> idx;
    for (int k = 0; k < block; ++k) idx.push_back(from + k);
    auto count = [&](Rig& r, const std::string& what, const std::vector<double>& v, double cpu) {
      if (round > 0) r.series[what].add(v, cpu);
    };
    // The bare network: SpatialModel::estimate (pre-processing, forward, decoding).
    for (Rig& r : rigs) {
      std::vector<double> fwd, est;
      r.last.clear();
      const double cpu0 = cpuMs();
      std::vector<double> pre, dec;
      for (int i : idx) {
        const auto t0 = Clock::now();
        r.last.push_back(r.model->estimate(frames[i]));
        est.push_back(msSince(t0));
        const jointflow::SpatialTimings t = r.model->lastTimings();
        fwd.push_back(t.forward_ms);
        pre.push_back(t.preprocess_ms);
        dec.push_back(t.decode_ms);
      }
      const double cpu = (cpuMs() - cpu0) / block;
      count(r, "forward", fwd, cpu);
      count(r, "estimate", est, cpu);
      count(r, "preprocess", pre, -1);
      count(r, "decoding", dec, -1);
    }
    // The TFF network on the maps of consecutive frames; then again as the Tracker runs it, the
    // previous maps first moved by a camera motion (here 8 px right, 4 px down, 1 % zoom).
    for (Rig& r : rigs) {
      if (!r.tff) continue;
      const cv::Matx23f camera(1.01f, 0.f, 8.f, 0.f, 1.01f, 4.f);
      for (const bool moved : {false, true}) {
        std::vector<double> ms;
        r.tff->reset();
        for (const auto& res : r.last) {
          const auto t0 = Clock::now();
          const cv::Mat field =
              r.tff->predict(res.features, res.beliefs,
                             moved ? jointflow::cameraMotionOnGrid(camera, res.grid_to_frame)
                                   : cv::Matx23f(1, 0, 0, 0, 1, 0));
          if (!field.empty()) ms.push_back(msSince(t0));
        }
        count(r, moved ? "tff_camera" : "tff", ms, -1);
      }
    }
    // Camera motion (every inferred frame since issue 11), on the people of the first engine.
    {
      std::vector<double> ms;
      // As the associator runs it, frame after frame; the block's first frame only starts it.
      jointflow::CameraMotionTracker tracker;
      tracker.update(greys[idx[0]]);
      const double cpu0 = cpuMs();
      for (size_t k = 1; k < idx.size(); ++k) {
        std::vector<jointflow::Box> people;
        for (const auto& p : rigs.front().last[k].poses) people.push_back(p.box);
        const auto t0 = Clock::now();
        tracker.update(greys[idx[k]], people);
        ms.push_back(msSince(t0));
      }
      if (round > 0) camera.add(ms, (cpuMs() - cpu0) / (block - 1));
    }
    // The core's Tracker (spatial model + association, no GStreamer).
    for (Rig& r : rigs) {
      std::vector<double> ms;
      const double cpu0 = cpuMs();
      for (int i : idx) {
        const auto t0 = Clock::now();
        r.tracker->process(frames[i], jointflow::PixelOrder::kBGR, r.time);
        r.time += 0.1;
        ms.push_back(msSince(t0));
      }
      count(r, "tracker", ms, (cpuMs() - cpu0) / block);
    }
    // The elements.
    for (const std::string what :
         {"element", "element-still", "element-tff", "element-sync", "jpeg", "jpeg-sync"}) {
      for (Rig& r : rigs) {
        auto it = r.elements.find(what);
        if (it == r.elements.end()) continue;
        std::vector<std::pair<const unsigned char*, size_t>> payloads;
        for (int i : idx) {
          if (what.rfind("jpeg", 0) == 0)
            payloads.emplace_back(jpegs[i].data(), jpegs[i].size());
          else
            payloads.emplace_back(frames[i].data, frames[i].total() * frames[i].elemSize());
        }
        const FedPipeline::Block b = it->second->run(payloads);
        count(r, what, b.gaps_ms, b.cpu_ms);
      }
    }
  }

  json out = {{"size", size}, {"load_after", loadAverage()}};
  out["camera_ms"] = median(camera.samples);
  out["camera_cpu_ms"] = median(camera.cpu);
  for (Rig& r : rigs) {
    json e;
    e["engine"] = r.model->engine();
    const jointflow::SpatialResult& res = r.last.front();
    e["input"] = std::to_string(static_cast<int>(std::lround(res.beliefs.size[3] * 4.0))) + "x" +
                 std::to_string(static_cast<int>(std::lround(res.beliefs.size[2] * 4.0)));
    for (auto& [what, s] : r.series) {
      e[what + "_ms"] = median(s.samples);
      if (!s.cpu.empty()) e[what + "_cpu_ms"] = median(s.cpu);
    }
    e["overhead"] = roundRatio(r.series["element"], r.series["forward"]);
    e["overhead_cpu"] = median(r.series["element"].cpu) / median(r.series["forward"].cpu);
    e["overhead_still"] = roundRatio(r.series["element-still"], r.series["forward"]);
    if (r.elements.count("element-tff"))
      e["tff_element_ratio"] = roundRatio(r.series["element-tff"], r.series["element"]);
    if (r.elements.count("element-sync")) {
      e["hold_gain_raw"] = roundRatio(r.series["element-sync"], r.series["element"]);
      e["hold_gain_jpeg"] = roundRatio(r.series["jpeg-sync"], r.series["jpeg"]);
    }
    out["engines"][r.backend] = e;
  }
  if (rigs.size() > 1) {
    out["speedup"] = roundRatio(rigs[0].series["element"], rigs[1].series["element"]);
    out["speedup_jpeg"] = roundRatio(rigs[0].series["jpeg"], rigs[1].series["jpeg"]);
    out["speedup_forward"] = roundRatio(rigs[0].series["forward"], rigs[1].series["forward"]);
  }
  return out;
}

// ---- 3: the engines on the same file --------------------------------------------------------

/// bench/ort_time.py in a process of its own, asked for one timed run at a time.
class OrtServer {
 public:
  OrtServer(const std::string& python, const std::string& script, const std::string& model) {
    int to_child[2], from_child[2];
    if (pipe(to_child) != 0 || pipe(from_child) != 0) throw jointflow::Error("pipe() failed");
    pid_ = fork();
    if (pid_ < 0) throw jointflow::Error("fork() failed");
    if (pid_ == 0) {
      dup2(to_child[0], 0);
      dup2(from_child[1], 1);
      close(to_child[1]);
      close(from_child[0]);
      execl(python.c_str(), python.c_str(), script.c_str(), model.c_str(),
            static_cast<char*>(nullptr));
      _exit(127);
    }
    close(to_child[0]);
    close(from_child[1]);
    in_ = fdopen(to_child[1], "w");
    out_ = fdopen(from_child[0], "r");
    version_ = reply("")["ort_version"].get<std::string>();
  }
  ~OrtServer() {
    if (in_) fclose(in_);
    if (out_) fclose(out_);
    if (pid_ > 0) waitpid(pid_, nullptr, 0);
  }
  const std::string& version() const { return version_; }
  double runMs(cv::Size size, int threads) {
    return reply(std::to_string(size.height) + " " + std::to_string(size.width) + " " +
                 std::to_string(threads) + "\n")["ms"]
        .get<double>();
  }

 private:
  json reply(const std::string& request) {
    if (!request.empty()) {
      fputs(request.c_str(), in_);
      fflush(in_);
    }
    char line[4096];
    if (!fgets(line, sizeof line, out_))
      throw jointflow::Error("onnxruntime timing (bench/ort_time.py) stopped answering");
    return json::parse(line);
  }
  pid_t pid_ = -1;
  FILE* in_ = nullptr;
  FILE* out_ = nullptr;
  std::string version_;
};

struct EngineTimes {
  double dnn = 0, ov = -1, ov32 = -1, ort = -1;
  std::vector<std::pair<std::string, double>> by_type;   ///< cv::dnn: type, ms; largest first
  std::vector<std::pair<std::string, double>> by_layer;  ///< "name (type)", ms; largest first
};

/// cv::dnn, OpenVINO (its default precision and f32) and onnxruntime on the same file and input,
/// taking turns run by run (3 warm-up runs each first); a short pause between two runs lets the
/// thread pools of the one before stop spinning. Medians, and cv::dnn's time per layer.
EngineTimes timeEngines(const std::string& path, cv::Size size, int runs, int threads, bool have_ov,
                        OrtServer* ort) {
  cv::setNumThreads(threads);
  cv::dnn::Net net = cv::dnn::readNetFromONNX(path);
  const auto outs = net.getUnconnectedOutLayersNames();
  cv::Mat blob(std::vector<int>{1, 3, size.height, size.width}, CV_32F);
  cv::randu(blob, 0.f, 255.f);
  net.setInput(blob);
  std::unique_ptr<jointflow::detail::Network> ov, ov32;
  if (have_ov) {
    jointflow::DnnOptions d;
    d.backend = jointflow::DnnBackend::kOpenVino;
    d.num_threads = threads;
    ov = jointflow::detail::openNetwork(path, "bench", {}, d);
    d.precision = "f32";
    ov32 = jointflow::detail::openNetwork(path, "bench", {}, d);
  }
  std::vector<cv::Mat> out;
  std::vector<std::string> ov_outs = ov ? ov->outputNames() : std::vector<std::string>{};
  for (int i = 0; i < 3; ++i) {
    net.forward(out, outs);
    if (ov) ov->run(blob, ov_outs), ov32->run(blob, ov_outs);
    if (ort) ort->runMs(size, threads);
  }
  std::vector<double> dnn_ms, ov_ms, ov32_ms, ort_ms;
  std::map<std::string, double> types, layers;
  auto pause = [] { std::this_thread::sleep_for(std::chrono::milliseconds(10)); };
  for (int i = 0; i < runs; ++i) {
    auto t0 = Clock::now();
    net.forward(out, outs);
    dnn_ms.push_back(msSince(t0));
    std::vector<double> layer_ticks;
    net.getPerfProfile(layer_ticks);
    const auto ids = net.getLayerNames();
    for (size_t l = 0; l < layer_ticks.size() && l < ids.size(); ++l) {
      const cv::Ptr<cv::dnn::Layer> layer = net.getLayer(ids[l]);
      const double layer_ms = layer_ticks[l] * 1000.0 / cv::getTickFrequency() / runs;
      types[layer->type] += layer_ms;
      layers[ids[l] + " (" + layer->type + ")"] += layer_ms;
    }
    pause();
    if (ov) {
      t0 = Clock::now();
      ov->run(blob, ov_outs);
      ov_ms.push_back(msSince(t0));
      pause();
      t0 = Clock::now();
      ov32->run(blob, ov_outs);
      ov32_ms.push_back(msSince(t0));
      pause();
    }
    if (ort) {
      ort_ms.push_back(ort->runMs(size, threads));
      pause();
    }
  }
  EngineTimes t;
  t.dnn = median(dnn_ms);
  if (ov) t.ov = median(ov_ms), t.ov32 = median(ov32_ms);
  if (ort) t.ort = median(ort_ms);
  const auto largest_first = [](const auto& a, const auto& b) { return a.second > b.second; };
  t.by_type.assign(types.begin(), types.end());
  std::sort(t.by_type.begin(), t.by_type.end(), largest_first);
  t.by_layer.assign(layers.begin(), layers.end());
  std::sort(t.by_layer.begin(), t.by_layer.end(), largest_first);
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  gst_init(&argc, &argv);
  CLI::App app{"JointFlow performance budgets (issues 7 and 13)"};
  std::string video = JOINTFLOW_VTEST_AVI, out = "docs/benchmarks.md", python, child_size;
  std::string models = jointflow::defaultModelsDir(), ort_script = "bench/ort_time.py";
  // 10 rounds: with 4, the overhead of the same build moved by 0.05-0.1 from run to run (the
  // per-round ratios of a shared 2-core machine), as much as what it is to show.
  int block = 6, rounds = 10, runs = 20, stream_frames = 10, agreement_stride = 2;
  int threads = static_cast<int>(std::thread::hardware_concurrency()), child_streams = 0;
  double live_seconds = 8;
  app.add_option("--video", video, "video file (default: opencv-doc's vtest.avi)");
  app.add_option("--block", block, "frames per block of the end-to-end rounds")
      ->check(CLI::Range(3, 1000));
  app.add_option("--rounds", rounds, "rounds of the end-to-end measurements (plus one warm-up)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--runs", runs, "runs per engine on the bare ONNX file (half at 1 thread)")
      ->check(CLI::Range(2, 100000));
  app.add_option("--stream-frames", stream_frames, "frames per stream (3 of them warm-up)")
      ->check(CLI::Range(6, 100000));
  app.add_option("--threads", threads, "threads of the engines")->check(CLI::Range(1, 256));
  app.add_option("--python", python, "python with onnxruntime (empty: no onnxruntime column)");
  app.add_option("--ort-script", ort_script, "bench/ort_time.py");
  app.add_option("--out", out, "Markdown file to write (empty: none)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);  // bench/run.sh gives a default
  app.add_option("--agreement-stride", agreement_stride,
                 "person counts of the two engines on every Nth frame of the video")
      ->check(CLI::Range(1, 1000));
  app.add_option("--live-seconds", live_seconds, "seconds of each live-source run")
      ->check(CLI::Range(2.0, 3600.0));
  app.add_option("--child", child_streams, "internal: run N pipelines, print JSON");
  app.add_option("--child-size", child_size, "internal: input-size of the child's pipelines");
  std::string child_props, child_live, child_e2e, child_backends = "default";
  app.add_option("--child-props", child_props, "internal: more jointflowtrack properties");
  app.add_option("--child-live", child_live, "internal: run the live test with this policy");
  app.add_option("--child-e2e", child_e2e, "internal: the end-to-end rounds at this input size");
  app.add_option("--child-backends", child_backends, "internal: engines of --child-e2e");
  CLI11_PARSE(app, argc, argv);
  cv::setNumThreads(threads);
  constexpr int kWarmup = 3;
  const std::string movenet = models + "/movenet_multipose.onnx";
  const std::string tff_path = models + "/tff_movenet.onnx";
  const std::string tff_used = std::filesystem::exists(tff_path) ? tff_path : "";

  try {
    if (!child_live.empty()) {
      std::cout << runLive(child_live, child_size, live_seconds).dump() << std::endl;
      return 0;
    }
    if (!child_e2e.empty()) {
      std::vector<std::string> backends;
      std::stringstream list(child_backends);
      for (std::string b; std::getline(list, b, ',');) backends.push_back(b);
      const auto frames = readFrames(video, block * (rounds + 1) + 1);
      std::cout << runEndToEnd(frames, backends, child_e2e, block, rounds, tff_used).dump()
                << std::endl;
      return 0;
    }
    if (child_streams > 0) {
      const auto frames = readFrames(video, stream_frames);
      std::cout << runPipelines(frames, child_streams, child_size, kWarmup, child_props).dump()
                << std::endl;
      return 0;
    }
    const auto run_start = Clock::now();
    const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
    const std::string base = "--video '" + video + "' --threads " + std::to_string(threads);
    const std::string load_before = loadAverage();
    const cv::Size native = readFrames(video, 4).front().size();
    std::vector<std::string> loads;  // load average after each section

    // The engines of this build: cv::dnn always, OpenVINO where it was built with it.
    std::vector<std::pair<std::string, std::string>> engines = {{"default", "cv::dnn"}};
    std::string openvino_name, openvino_missing;
    try {
      jointflow::SpatialOptions o;
      o.dnn.backend = jointflow::DnnBackend::kOpenVino;
      openvino_name = jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, o)->engine();
      engines.emplace_back("openvino", "OpenVINO");
    } catch (const std::exception& e) {
      openvino_missing = e.what();
    }
    const bool have_ov = openvino_missing.empty();
    const std::string backends = have_ov ? "default,openvino" : "default";
    auto met = [](bool ok) { return ok ? "**met**" : "**missed**"; };

    std::ostringstream md;
    // 1: the element end to end, a child per input size.
    const std::vector<std::string> sizes = {"256x256", "max:640", "native"};
    std::map<std::string, json> e2e;
    for (const std::string& size : sizes) {
      std::cerr << "end to end at " << size << " ..." << std::endl;
      e2e[size] = runChild(self, base + " --child-e2e " + size + " --child-backends " + backends +
                                     " --block " + std::to_string(block) + " --rounds " +
                                     std::to_string(rounds));
    }
    loads.push_back(loadAverage());

    md << "## Where the time goes: the element against the bare network\n\n"
          "Each input size in a process of its own, in "
       << rounds << " rounds of " << block
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
          "fixed camera): its overhead, element / forward, in the same rounds.\n\n"
          "| engine | input size | network input | pre-processing (ms) | forward (ms) | decoding "
          "(ms) | camera motion (ms) | tracker (ms) | element (ms) | frames/s | overhead | CPU "
          "overhead | target | overhead, still camera |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& [backend, engine] : engines)
      for (const std::string& size : sizes) {
        const json& e = e2e[size]["engines"][backend];
        const double overhead = e["overhead"];
        md << "| " << engine << " | " << size << " | " << e["input"].get<std::string>() << " | "
           << fmt(e["preprocess_ms"]) << " | " << fmt(e["forward_ms"]) << " | "
           << fmt(e["decoding_ms"]) << " | " << fmt(e2e[size]["camera_ms"]) << " | "
           << fmt(e["tracker_ms"]) << " | " << fmt(e["element_ms"]) << " | "
           << fmt(1000.0 / e["element_ms"].get<double>()) << " | " << fmt(overhead, 2) << " | "
           << fmt(e["overhead_cpu"], 2) << " | <= 1.05: " << met(overhead <= 1.05) << " | "
           << fmt(e["overhead_still"], 2) << " |\n";
      }
    md << "\nLoad average after each size's process: ";
    for (const std::string& size : sizes)
      md << size << " " << e2e[size]["load_after"].get<std::string>()
         << (size == sizes.back() ? ".\n" : ", ");
    if (have_ov) {
      const json& ov640 = e2e["max:640"]["engines"]["openvino"];
      const json& ov256 = e2e["256x256"]["engines"]["openvino"];
      const double speedup = e2e["max:640"]["speedup"];
      md << "\n**OpenVINO against cv::dnn, end to end** (element time, cv::dnn / OpenVINO, per "
            "round; the bare forward pass in brackets): ";
      for (const std::string& size : sizes)
        md << size << " " << fmt(e2e[size]["speedup"], 2) << "x ("
           << fmt(e2e[size]["speedup_forward"], 2) << "x)" << (size == sizes.back() ? ". " : ", ");
      md << "Target at max:640 >= 2.5x: " << met(speedup >= 2.5) << ".\n\n"
         << "**Frames/s with tracking** (OpenVINO element): max:640 "
         << fmt(1000.0 / ov640["element_ms"].get<double>())
         << " (target >= 15: " << met(1000.0 / ov640["element_ms"].get<double>() >= 15)
         << "), 256x256 " << fmt(1000.0 / ov256["element_ms"].get<double>())
         << " (target >= 40: " << met(1000.0 / ov256["element_ms"].get<double>() >= 40)
         << "), on this machine at the load above. The CPU time per frame says what they "
            "would be on "
         << std::thread::hardware_concurrency()
         << " cores of our own if the element used them all: max:640 "
         << fmt(1000.0 * std::thread::hardware_concurrency() /
                ov640["element_cpu_ms"].get<double>())
         << ", 256x256 "
         << fmt(1000.0 * std::thread::hardware_concurrency() /
                ov256["element_cpu_ms"].get<double>())
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
            "round.\n\n"
            "| input size | raw, held (ms) | raw, not held (ms) | gain | decoded, held (ms) | "
            "decoded, not held (ms) | gain | cv::dnn decoded (ms) |\n"
            "|---|---|---|---|---|---|---|---|\n";
      for (const std::string& size : sizes) {
        const json& e = e2e[size]["engines"]["openvino"];
        md << "| " << size << " | " << fmt(e["element_ms"]) << " | " << fmt(e["element-sync_ms"])
           << " | " << fmt(e["hold_gain_raw"], 2) << "x | " << fmt(e["jpeg_ms"]) << " | "
           << fmt(e["jpeg-sync_ms"]) << " | " << fmt(e["hold_gain_jpeg"], 2) << "x | "
           << fmt(e2e[size]["engines"]["default"]["jpeg_ms"]) << " |\n";
      }
    }

    // 2: TFF against spatial.
    md << "\n## TFF network against the spatial network\n\n";
    if (!tff_used.empty()) {
      md << "`tff_movenet.onnx` (the runner's predict(): the maps of a frame and of the one "
            "before in, TFF out) against MoveNet's forward pass on the same engine, in the "
            "rounds above (target <= 0.25). After camera: as the Tracker runs it with camera "
            "compensation on (the default), the previous maps first moved by the camera motion "
            "(bilinear warp of every plane, here for a motion of 8 px and 1 % zoom). Element, "
            "oks / tff: the element above with similarity=oks (what the default, auto, runs "
            "between close frames) and with "
            "similarity=tff, in the same rounds: what the paper's similarity costs end to end "
            "(tff / oks, per round).\n\n"
            "| engine | input size | spatial forward (ms) | TFF (ms) | ratio | target | TFF "
            "after camera (ms) | ratio | element, oks (ms) | element, tff (ms) | tff / oks |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|\n";
      for (const auto& [backend, engine] : engines)
        for (const std::string& size : sizes) {
          const json& e = e2e[size]["engines"][backend];
          const double forward = e["forward_ms"].get<double>();
          const double ratio = e["tff_ms"].get<double>() / forward;
          md << "| " << engine << " | " << size << " | " << fmt(e["forward_ms"]) << " | "
             << fmt(e["tff_ms"]) << " | " << fmt(ratio, 3) << " | <= 0.25: " << met(ratio <= 0.25)
             << " | " << fmt(e["tff_camera_ms"]) << " | "
             << fmt(e["tff_camera_ms"].get<double>() / forward, 3) << " | " << fmt(e["element_ms"])
             << " | " << fmt(e["element-tff_ms"]) << " | " << fmt(e["tff_element_ratio"], 2)
             << "x |\n";
        }
    } else {
      md << "Not measured: " << tff_path << " is absent (the trained TFF network).\n";
    }

    // 3: the engines on the same file.
    std::cerr << "engines on the same file ..." << std::endl;
    std::unique_ptr<OrtServer> ort;
    if (!python.empty()) ort = std::make_unique<OrtServer>(python, ort_script, movenet);
    md << "\n## cv::dnn, OpenVINO and onnxruntime on the same ONNX file\n\n"
          "`movenet_multipose.onnx`, random input of its range, every graph output; the engines "
          "take turns run by run (10 ms apart, so that the thread pool of one has stopped "
          "spinning when the next runs), "
       << threads << " threads each (median of " << runs << " runs), then 1 thread each (median of "
       << std::max(2, runs / 2)
       << " runs), after 3 warm-up runs each; onnxruntime in a Python process of its own "
          "(bench/ort_time.py, timing its own runs). OpenVINO with its default precision ("
       << (have_ov ? openvino_name.substr(openvino_name.rfind(' ') + 1) : "-")
       << " here) and with f32.\n\n"
       << "| input | cv::dnn (ms) | OpenVINO (ms) | OpenVINO f32 (ms) | onnxruntime (ms) | "
          "cv::dnn / OpenVINO | cv::dnn / OpenVINO f32 | cv::dnn / onnxruntime |\n"
          "|---|---|---|---|---|---|---|---|\n";
    const cv::Size max640(
        640, static_cast<int>(std::lround(640.0 * native.height / native.width / 32.0)) * 32);
    std::vector<std::pair<cv::Size, EngineTimes>> profiles;
    for (const int n_threads : {threads, 1}) {
      for (const cv::Size size : {cv::Size(256, 256), max640, native}) {
        const EngineTimes t =
            timeEngines(movenet, size, n_threads == threads ? runs : std::max(2, runs / 2),
                        n_threads, have_ov, ort.get());
        auto ratio = [&](double other) { return other > 0 ? fmt(t.dnn / other, 2) : "n/a"; };
        auto cell = [](double ms) { return ms > 0 ? fmt(ms) : "n/a"; };
        md << "| " << size.width << "x" << size.height << ", " << n_threads << " thread"
           << (n_threads > 1 ? "s" : "") << " | " << fmt(t.dnn) << " | " << cell(t.ov) << " | "
           << cell(t.ov32) << " | "
           << (ort ? fmt(t.ort) + " (" + ort->version() + ")" : "n/a (no --python)") << " | "
           << ratio(t.ov) << " | " << ratio(t.ov32) << " | " << ratio(t.ort) << " |\n";
        if (n_threads == threads && size != max640) profiles.emplace_back(size, t);
      }
    }
    ort.reset();
    cv::setNumThreads(threads);
    loads.push_back(loadAverage());
    md << "\ncv::dnn's time by layer type (getPerfProfile, mean per forward pass, " << threads
       << " threads):\n\n| input | layer type | ms | share |\n|---|---|---|---|\n";
    for (const auto& [size, t] : profiles) {
      double total = 0;
      for (const auto& [type, ms] : t.by_type) total += ms;
      for (size_t i = 0; i < t.by_type.size() && i < 6; ++i)
        md << "| " << size.width << "x" << size.height << " | " << t.by_type[i].first << " | "
           << fmt(t.by_type[i].second, 2) << " | " << fmt(100.0 * t.by_type[i].second / total)
           << " % |\n";
    }
    md << "\nThe slowest layers at " << profiles[0].first.width << "x" << profiles[0].first.height
       << ":\n\n| layer | ms |\n|---|---|\n";
    for (size_t i = 0; i < profiles[0].second.by_layer.size() && i < 10; ++i)
      md << "| " << profiles[0].second.by_layer[i].first << " | "
         << fmt(profiles[0].second.by_layer[i].second, 2) << " |\n";

    // 4: streams, at the default input size.
    std::cerr << "streams ..." << std::endl;
    md << "\n## Frames/s and memory of 1 and 4 streams\n\n"
          "K pipelines `appsrc ! jointflowtrack input-size=max:640 ! fakesink` in one process "
          "(a process per row), each fed from its own thread as fast as it takes frames ("
       << stream_frames << " frames each, " << kWarmup
       << " of them warm-up). Memory = growth of the process's resident memory from before the "
          "K pipelines were made to after their last frame (one pipeline at 64x64 ran before, "
          "to load the libraries and the model file's bytes). ms/frame per stream = mean time "
          "between two frames of a stream (the median over the streams); frames/s = all streams' "
          "frames after warm-up over "
          "the time they took.\n\n"
          "| engine | streams | ms/frame per stream | frames/s, all streams | memory (MiB) | per "
          "stream (MiB) |\n|---|---|---|---|---|---|\n";
    auto streams = [&](int k, const std::string& props) {
      return runChild(self, base + " --stream-frames " + std::to_string(stream_frames) +
                                " --child " + std::to_string(k) +
                                " --child-size max:640 --child-props '" + props + "'");
    };
    auto streamRow = [&](const std::string& engine, const json& r, const std::string& note) {
      md << "| " << engine << " | " << r["streams"].get<int>() << note << " | "
         << fmt(r["ms_per_frame"].get<double>()) << " | " << fmt(r["fps_total"].get<double>(), 2)
         << " | " << fmt(r["rss_mib"].get<double>()) << " | "
         << fmt(r["rss_per_stream_mib"].get<double>()) << " |\n";
    };
    streamRow("cv::dnn", streams(1, "backend=default"), "");
    streamRow("cv::dnn", streams(4, "backend=default"), "");
    if (have_ov) {
      streamRow("OpenVINO", streams(1, "backend=openvino"), "");
      const json shared = streams(4, "backend=openvino model-instance-id=bench");
      streamRow("OpenVINO", shared, " (one shared model)");
      const json separate2 = streams(2, "backend=openvino");
      streamRow("OpenVINO", separate2, " (a model each)");
      streamRow("OpenVINO", streams(4, "backend=openvino"), " (a model each)");
      md << "\nMemory target: 4 streams sharing one model (" << fmt(shared["rss_mib"].get<double>())
         << " MiB) take less than 2 streams with a model "
         << "each (" << fmt(separate2["rss_mib"].get<double>())
         << " MiB): " << met(shared["rss_mib"].get<double>() < separate2["rss_mib"].get<double>())
         << ".\n";
    }
    loads.push_back(loadAverage());

    // 5: person counts of the two engines (tests/engine checks every 6th frame of a few).
    if (have_ov) {
      std::cerr << "person counts ..." << std::endl;
      jointflow::SpatialOptions o;  // max:640
      auto dnn = jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, o);
      o.dnn.backend = jointflow::DnnBackend::kOpenVino;
      auto ov = jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, o);
      cv::VideoCapture capture(video);
      int n = 0, within = 0, equal = 0, people = 0, total = 0;
      cv::Mat f;
      for (int i = 0; capture.read(f); ++i) {
        ++total;
        if (i % agreement_stride) continue;
        const int a = static_cast<int>(dnn->estimate(f).poses.size());
        const int b = static_cast<int>(ov->estimate(f).poses.size());
        n++;
        people += a;
        within += std::abs(a - b) <= 1;
        equal += a == b;
      }
      const double share = 100.0 * within / std::max(n, 1);
      md << "\n## Person counts of the two engines\n\nMoveNet at max:640 (the default options) on "
         << (agreement_stride == 1 ? "every frame"
                                   : "one frame in " + std::to_string(agreement_stride))
         << " of vtest.avi (" << n << " of its " << total << " frames, " << fmt(1.0 * people / n)
         << " people per frame on cv::dnn), cv::dnn against " << openvino_name
         << ": the counts agree within 1 on " << within << " frames (" << fmt(share)
         << " %, target >= 95 %: " << met(share >= 95) << ") and are equal on " << equal << " ("
         << fmt(100.0 * equal / std::max(n, 1)) << " %).\n";
      loads.push_back(loadAverage());
    }

    // 6: a live source faster than inference.
    std::cerr << "live source ..." << std::endl;
    md << "\n## Live source faster than inference\n\n"
          "`videotestsrc is-live=true` at 60 frames/s (320x240) into jointflowtrack "
          "(input-size=native, cv::dnn) into `fakesink sync=true qos=true`, "
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
    loads.push_back(loadAverage());

    std::ostringstream doc;
    doc << "# Benchmarks\n\nWritten by `make bench` (bench/run.sh -> build/bench/jointflow-bench, "
           "bench/jointflow_bench.cpp) in one run on one machine ("
        << fmt(std::chrono::duration<double>(Clock::now() - run_start).count() / 60.0)
        << " minutes): frames of vtest.avi (" << native.width << "x" << native.height << "), "
        << threads << " threads for every engine, " << std::thread::hardware_concurrency()
        << " hardware threads. Load average " << load_before << " before the run, then ";
    for (size_t i = 0; i < loads.size(); ++i)
      doc << loads[i] << (i + 1 < loads.size() ? ", " : " ");
    doc << "after its sections: the machine is shared, absolute times move with its load, so "
           "compare the ratios, each taken within one round of one process. Engines: OpenCV "
        << CV_VERSION << " dnn (cv::dnn, the default) and "
        << (have_ov ? openvino_name + " (backend=openvino, its default precision)"
                    : "no OpenVINO (" + openvino_missing + ")")
        << ". The spatial model is MoveNet MultiPose, similarity oks.\n\n"
        << md.str();
    std::cout << doc.str();
    if (!out.empty()) {
      std::ofstream file(out);
      if (!file) throw jointflow::Error("cannot write " + out);
      file << doc.str();
      std::cout << "\nwritten to " << out << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "jointflow-bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
