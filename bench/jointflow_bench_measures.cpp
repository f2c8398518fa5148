// The measurements of jointflow-bench (jointflow_bench_measures.hpp), moved out of its main as they
// were: pipelines fed from threads, the live source, the end-to-end rounds, the engines on the
// bare ONNX file.
#include "jointflow_bench_measures.hpp"

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
#include <fstream>
#include <iomanip>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

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

namespace jointflow::bench {

using nlohmann::json;

namespace {

using Clock = std::chrono::steady_clock;

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

}  // namespace

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string first;
  return in >> first ? first : "?";
}

std::string fmt(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

std::vector<cv::Mat> readFrames(const std::string& video, int count, int stride) {
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

namespace {

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

}  // namespace

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
    jointflow::EngineOptions engine;
    engine.backend =
        backend == "openvino" ? jointflow::DnnBackend::kOpenVino : jointflow::DnnBackend::kDefault;
    if (backend == "openvino") engine.model_instance_id = "bench-e2e";
    r.model = jointflow::createSpatialModel(jointflow::ModelType::kMoveNet, o, engine);
    if (!tff_path.empty())
      r.tff = std::make_unique<jointflow::TemporalFlowModel>(tff_path, r.model->featureChannels(),
                                                             engine);
    jointflow::TrackerSettings ts;
    ts.model_type = jointflow::ModelType::kMoveNet;
    ts.spatial = o;
    ts.engine = engine;
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

OrtServer::OrtServer(const std::string& python, const std::string& script,
                     const std::string& model) {
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

OrtServer::~OrtServer() {
  if (in_) fclose(in_);
  if (out_) fclose(out_);
  if (pid_ > 0) waitpid(pid_, nullptr, 0);
}

double OrtServer::runMs(cv::Size size, int threads) {
  return reply(std::to_string(size.height) + " " + std::to_string(size.width) + " " +
               std::to_string(threads) + "\n")["ms"]
      .get<double>();
}

json OrtServer::reply(const std::string& request) {
  if (!request.empty()) {
    fputs(request.c_str(), in_);
    fflush(in_);
  }
  char line[4096];
  if (!fgets(line, sizeof line, out_))
    throw jointflow::Error("onnxruntime timing (bench/ort_time.py) stopped answering");
  return json::parse(line);
}

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
    jointflow::EngineOptions d;
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

}  // namespace jointflow::bench
