// publish-bench: jointflowmetapublish against local brokers (issue 14), started here as in the
// tests (mosquitto; Kafka in KRaft mode from the fetched jars):
//   - messages per second sustained (synthetic frames of two people, as fast as they are taken,
//     until EOS has flushed them all), against the tracker's own frames per second on vtest.avi;
//   - latency added per frame on the streaming thread (push time through the element against
//     the same push through `identity`);
//   - resident memory and frame flow while the broker is down for --outage-seconds with 30 fps
//     of video going through.
// Writes Markdown to stdout, one --part at a time (bench/publish.sh puts them together in
// docs/publish-bench.md).
#include <gst/check/gstharness.h>
#include <gst/gst.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "broker_process.hpp"
#include "gst_test_util.hpp"
#include "kafka_broker.hpp"
#include "resident_memory.hpp"

using namespace jointflow::test;
using Clock = std::chrono::steady_clock;

namespace {

GstBuffer* frame(int i) {
  GstBuffer* b = blackFrame("RGB", 64, 48, static_cast<GstClockTime>(i) * GST_SECOND / 30);
  GstJointFlowMeta* meta = gst_buffer_add_jointflow_meta(b, 64, 48);
  for (int k = 0; k < 2; ++k) {
    JointFlowPerson p = person(1 + k, 2.f + (i % 20) + 10 * k, 3.f + k, 20, 30);
    gst_jointflow_meta_add_person(meta, &p);
  }
  return b;
}

GstHarness* harness(const std::string& description) {
  GstElement* e = gst_parse_launch(description.c_str(), nullptr);
  GstHarness* h = gst_harness_new_with_element(e, "sink", "src");
  gst_object_unref(e);
  gst_harness_set_src_caps_str(h, capsFor("RGB", 64, 48).c_str());
  return h;
}

guint64 counter(GstHarness* h, const char* name) {
  guint64 v = 0;
  g_object_get(h->element, name, &v, nullptr);
  return v;
}

double seconds(Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

// The tracker's frames per second on vtest.avi with the default settings (frames 10..N, after
// the models are loaded).
double trackerFps(int frames) {
  GstElement* p = gst_parse_launch(
      ("filesrc location=/usr/share/doc/opencv-doc/examples/data/vtest.avi ! decodebin ! "
       "videoconvert ! identity eos-after=" +
       std::to_string(frames) + " ! jointflowtrack ! fakesink name=sink sync=false")
          .c_str(),
      nullptr);
  struct Times {
    std::vector<Clock::time_point> t;
  } times;
  GstElement* sink = gst_bin_get_by_name(GST_BIN(p), "sink");
  GstPad* pad = gst_element_get_static_pad(sink, "sink");
  gst_pad_add_probe(
      pad, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad*, GstPadProbeInfo*, gpointer data) {
        static_cast<Times*>(data)->t.push_back(Clock::now());
        return GST_PAD_PROBE_OK;
      },
      &times, nullptr);
  gst_object_unref(pad);
  gst_object_unref(sink);
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstBus* bus = gst_element_get_bus(p);
  GstMessage* m = gst_bus_timed_pop_filtered(
      bus, 600 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  if (m) gst_message_unref(m);
  gst_object_unref(bus);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(p);
  if (times.t.size() < 12) return 0;
  return (times.t.size() - 11) / seconds(times.t.back() - times.t[10]);
}

struct Throughput {
  double per_second = 0;
  guint64 published = 0;
};

Throughput throughput(const std::string& props, int n) {
  GstHarness* h =
      harness("jointflowmetapublish max-queue-size=1000000 flush-timeout=600000 " + props);
  // Connected before timing.
  gst_harness_push(h, frame(0));
  gst_buffer_unref(gst_harness_pull(h));
  waitUntil([&] { return counter(h, "messages-published") == 1; }, std::chrono::seconds(30));
  const auto t0 = Clock::now();
  for (int i = 1; i <= n; ++i) {
    gst_harness_push(h, frame(i));
    gst_buffer_unref(gst_harness_pull(h));
  }
  gst_harness_push_event(h, gst_event_new_eos());
  const double s = seconds(Clock::now() - t0);
  Throughput r{n / s, counter(h, "messages-published") - 1};
  gst_harness_teardown(h);
  return r;
}

struct Latency {
  double median_us = 0, p99_us = 0;
};

// Push + pull of one frame every 2 ms (a fast camera), @n times.
Latency pushLatency(const std::string& description, int n) {
  GstHarness* h = harness(description);
  std::vector<double> us;
  for (int i = 0; i < n + 50; ++i) {
    GstBuffer* b = frame(i);
    const auto t0 = Clock::now();
    gst_harness_push(h, b);
    gst_buffer_unref(gst_harness_pull(h));
    const double t = seconds(Clock::now() - t0) * 1e6;
    if (i >= 50) us.push_back(t);  // after warm-up
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  gst_harness_teardown(h);
  std::sort(us.begin(), us.end());
  return {us[us.size() / 2], us[us.size() * 99 / 100]};
}

struct Outage {
  std::vector<std::pair<int, long>> rss;  // (second, KiB)
  int frames = 0, frames_ok = 0;
  double max_push_ms = 0;
  guint64 dropped = 0, published_after = 0;
};

// Video at 30 fps through the element for @secs with the broker down (killed by @kill after the
// element connected); then @restart, and the element reconnects.
template <typename Kill, typename Restart>
Outage outage(const std::string& props, int secs, Kill kill, Restart restart) {
  GstHarness* h =
      harness("jointflowmetapublish max-connect-attempts=0 max-reconnect-interval=2000 " + props);
  gst_harness_push(h, frame(0));
  gst_buffer_unref(gst_harness_pull(h));
  waitUntil([&] { return counter(h, "messages-published") == 1; }, std::chrono::seconds(30));
  kill();
  Outage o;
  const auto start = Clock::now();
  int next_sample = 0;
  for (int i = 1; seconds(Clock::now() - start) < secs; ++i) {
    const auto due = start + std::chrono::microseconds(static_cast<long>(i * 1e6 / 30));
    std::this_thread::sleep_until(due);
    const auto t0 = Clock::now();
    const GstFlowReturn r = gst_harness_push(h, frame(i));
    o.max_push_ms = std::max(o.max_push_ms, seconds(Clock::now() - t0) * 1e3);
    o.frames++;
    if (r == GST_FLOW_OK) {
      o.frames_ok++;
      gst_buffer_unref(gst_harness_pull(h));
    }
    const int s = static_cast<int>(seconds(Clock::now() - start));
    if (s >= next_sample) {
      o.rss.emplace_back(s, jointflow::bench::residentKiB());
      next_sample = s + 5;
    }
  }
  o.rss.emplace_back(secs, jointflow::bench::residentKiB());
  o.dropped = counter(h, "messages-dropped");
  const guint64 before = counter(h, "messages-published");
  restart();
  // Until every message is settled: delivered, or dropped while the queue was full.
  const guint64 total = 1 + static_cast<guint64>(o.frames_ok);
  waitUntil(
      [&] { return counter(h, "messages-published") + counter(h, "messages-dropped") >= total; },
      std::chrono::seconds(60));
  o.published_after = counter(h, "messages-published") - before;
  o.dropped = counter(h, "messages-dropped");
  gst_harness_teardown(h);
  return o;
}

// @full_after: seconds of 30 fps video after which the bounded queues are full (the element's
// 300; for Kafka also librdkafka's 300), from when on memory must stay flat.
void report(const char* method, const Throughput& t, double fps, const Latency& with,
            const Latency& without, const Outage& o, int secs, int full_after) {
  std::printf("\n## %s\n\n", method);
  std::printf("| measure | value | target |\n|---|---|---|\n");
  std::printf(
      "| messages/s sustained (to EOS, all acknowledged: %llu) | %.0f | >= 10 x tracker = %.0f: %s "
      "|\n",
      static_cast<unsigned long long>(t.published), t.per_second, 10 * fps,
      t.per_second >= 10 * fps ? "met" : "MISSED");
  const double added = (with.median_us - without.median_us) / 1000.0;
  std::printf("| push+pull per frame, median / p99 (us): jointflowmetapublish | %.1f / %.1f | |\n",
              with.median_us, with.p99_us);
  std::printf("| push+pull per frame, median / p99 (us): identity | %.1f / %.1f | |\n",
              without.median_us, without.p99_us);
  std::printf("| latency added per frame, median (ms) | %.3f | < 1 ms: %s |\n", added,
              added < 1.0 ? "met" : "MISSED");
  std::printf("| broker down %d s at 30 fps: frames through / pushed | %d / %d | all: %s |\n", secs,
              o.frames_ok, o.frames, o.frames_ok == o.frames ? "met" : "MISSED");
  std::printf("| broker down: slowest push (ms) | %.2f | |\n", o.max_push_ms);
  std::printf("| messages dropped in all (the queues were full) | %llu | |\n",
              static_cast<unsigned long long>(o.dropped));
  std::printf("| after the broker is back: messages delivered (the queue's) | %llu | |\n",
              static_cast<unsigned long long>(o.published_after));
  std::printf("\nResident memory of the process while the broker is down (KiB):\n\n| s | ");
  for (const auto& [s, kib] : o.rss) std::printf("%d | ", s);
  std::printf("\n|---|");
  for (std::size_t i = 0; i < o.rss.size(); ++i) std::printf("---|");
  std::printf("\n| RSS | ");
  for (const auto& [s, kib] : o.rss) std::printf("%ld | ", kib);
  // Flat: once the queues are full, no growth beyond 1 MiB.
  long at_full = 0, last = o.rss.back().second, first = o.rss.front().second;
  for (const auto& [s, kib] : o.rss)
    if (s >= full_after && at_full == 0) at_full = kib;
  std::printf(
      "\n\nGrowth over the outage: %ld KiB while the queues filled (%d messages held at most, "
      "full after %d s), then %ld KiB from %d s to %d s (flat = under 1024 KiB: %s)\n",
      at_full - first, full_after * 30, full_after, last - at_full, full_after, secs,
      last - at_full < 1024 ? "met" : "MISSED");
}

}  // namespace

int main(int argc, char** argv) {
  gst_init(&argc, &argv);
  CLI::App app{"jointflowmetapublish against local brokers"};
  std::string part = "mqtt", jars, log4j;
  int messages = 20000, outage_s = 60, latency_frames = 2000;
  double fps = 0;
  app.add_option("--part", part,
                 "tracker (its frames/s), mqtt or kafka; each in a process of its own, so that "
                 "the memory of one part is not reused by the next")
      ->check(CLI::IsMember({"tracker", "mqtt", "kafka"}));
  app.add_option("--tracker-fps", fps, "the tracker's frames/s (from --part tracker)");
  app.add_option("--kafka-jars", jars, "folder of the Kafka jars (scripts/fetch-kafka.sh)");
  app.add_option("--log4j", log4j, "log4j2 config of the broker");
  app.add_option("--messages", messages, "messages for the throughput run");
  app.add_option("--outage-seconds", outage_s, "how long the broker is down");
  app.add_option("--latency-frames", latency_frames, "frames for the latency run");
  CLI11_PARSE(app, argc, argv);

  if (part == "tracker") {
    std::printf("%.2f\n", trackerFps(60));
    return 0;
  }
  // The outage first, on a fresh heap: memory freed by the other runs would hide growth.
  if (part == "mqtt") {
    Mosquitto m;
    if (!m.start()) {
      std::printf("\nmosquitto did not start\n");
      return 1;
    }
    const std::string props = "method=mqtt topic=bench address=" + m.address();
    const Outage o = outage(
        props, outage_s, [&] { m.kill(); }, [&] { m.start(); });
    const Throughput t = throughput(props, messages);
    const Latency with = pushLatency("jointflowmetapublish " + props, latency_frames);
    const Latency identity = pushLatency("identity", latency_frames);
    report("MQTT (mosquitto 2.0, QoS 1)", t, fps, with, identity, o, outage_s, 10);
    return 0;
  }
  if (jars.empty() || !std::filesystem::exists(jars)) {
    std::printf("\n## Kafka\n\nNo jars (scripts/fetch-kafka.sh): not measured.\n");
    return 0;
  }
  KafkaBroker k(jars, log4j);
  const std::string error = k.start();
  if (!error.empty() || k.createTopic("bench", 1) != "") {
    std::printf("\nKafka did not start: %s\n", error.c_str());
    return 1;
  }
  const std::string props = "method=kafka topic=bench source-id=cam1 address=" + k.address();
  const Outage o = outage(
      props, outage_s, [&] { k.kill(); }, [&] { k.start(); });
  const Throughput t = throughput(props, messages);
  const Latency with = pushLatency("jointflowmetapublish " + props, latency_frames);
  const Latency identity = pushLatency("identity", latency_frames);
  report("Kafka (KRaft broker 4.4, librdkafka 2.0, idempotent producer)", t, fps, with, identity, o,
         outage_s, 20);
  return 0;
}
