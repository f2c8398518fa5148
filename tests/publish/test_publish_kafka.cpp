// jointflowmetapublish method=kafka against a real Kafka broker (KRaft mode, loopback ports),
// started once for the program: every frame arrives once, in order, byte for byte the
// jointflowjsonwriter record, keyed by the source id (real frames of vtest.avi through
// jointflowtrack, and synthetic frames); two cameras on one partitioned topic, each in one
// partition and in order; then the faults: no broker at start, an unknown or bad topic, a
// message larger than the client takes, and the broker killed and restarted mid-stream.
// Without Java or the jars (and no network to fetch them), the program exits 77, saying why.
#include <glib.h>
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "kafka_broker.hpp"
#include "publish_test_util.hpp"

using namespace jointflow::test;
using std::chrono::milliseconds;
using std::chrono::seconds;

namespace {

// The program's broker, started by the first case that needs it and killed at exit. A reason
// to skip when Java or the jars are missing.
struct SharedKafka {
  std::unique_ptr<KafkaBroker> broker;
  std::string skip;
  std::string error;
};

SharedKafka& sharedKafka() {
  static SharedKafka shared = [] {
    SharedKafka k;
    gchar* java = g_find_program_in_path("java");
    g_free(java);
    if (!java) {
      k.skip = "no java on PATH (scripts/install-deps.sh installs openjdk-17-jre-headless)";
      return k;
    }
    const std::string jars = envOr("JOINTFLOW_KAFKA_JARS", "build/kafka-jars");
    auto have_jars = [&] {
      std::error_code ec;
      for (const auto& e : std::filesystem::directory_iterator(jars, ec))
        if (e.path().filename().string().rfind("kafka_2.13-", 0) == 0) return true;
      return false;
    };
    if (!have_jars()) {
      // `make test` fetches them first; a bare `meson test` tries once here.
      const std::string fetch = std::string("bash ") + JOINTFLOW_FETCH_KAFKA + " " +
                                std::filesystem::path(jars).parent_path().string();
      if (std::system(fetch.c_str()) != 0 || !have_jars()) {
        k.skip = "no Kafka jars in " + jars + ", and " + JOINTFLOW_FETCH_KAFKA +
                 " could not fetch them (no network and no Maven cache?)";
        return k;
      }
    }
    k.broker = std::make_unique<KafkaBroker>(
        jars, envOr("JOINTFLOW_KAFKA_LOG4J", "tests/publish/kafka-log4j2.properties"));
    const auto t0 = std::chrono::steady_clock::now();
    k.error = k.broker->start();
    if (!k.error.empty())
      k.broker.reset();
    else
      std::printf("Kafka broker up at %s after %.1f s\n", k.broker->address().c_str(),
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return k;
  }();
  return shared;
}

}  // namespace

/// The program's broker in @var; skips the case without Java or the jars, fails it when the
/// broker does not start.
#define KAFKA_BROKER(var)                                                      \
  KafkaBroker* var = sharedKafka().broker.get();                               \
  do {                                                                         \
    if (!sharedKafka().skip.empty()) JF_SKIP(sharedKafka().skip);              \
    if (!var) FAIL("the Kafka broker did not start: " << sharedKafka().error); \
  } while (0)

namespace {

std::string kafkaProps(const KafkaBroker* broker, const std::string& topic) {
  return "method=kafka address=" + broker->address() + " topic=" + topic;
}

/// jointflowjsonwriter (to @json) ! jointflowmetapublish name=pub (@props) in a harness.
GstHarness* writerAndPublisher(const std::string& json, const std::string& source_id,
                               const std::string& props) {
  initGst();
  GstHarness* h = gst_harness_new_parse(
      ("jointflowjsonwriter source-id=" + source_id + " location=" + json +
       " ! jointflowmetapublish name=pub source-id=" + source_id + " " + props)
          .c_str());
  gst_harness_set_src_caps_str(h, capsFor("RGB", kSynthW, kSynthH).c_str());
  return h;
}

guint64 counterOf(GstHarness* h, const char* name) {
  GstElement* pub = gst_bin_get_by_name(GST_BIN(h->element), "pub");
  guint64 v = 0;
  g_object_get(pub, name, &v, nullptr);
  gst_object_unref(pub);
  return v;
}

}  // namespace

TEST_CASE("real frames: each arrives once, in order, equal to the JSON writer's line, keyed",
          "[publish][kafka][vtest]") {
  KAFKA_BROKER(broker);
  JF_REQUIRE_PATH_OR_SKIP(vtestPath());
  REQUIRE(broker->createTopic("vtest", 1) == "");
  TempDir dir("jointflow-publish-kafka-vtest");
  const int frames = 16;
  REQUIRE(runToEos(vtestLaunch(frames, dir / "poses.jsonl", "camera1", kafkaProps(broker, "vtest")),
                   seconds(240)) == "");
  const auto expected = readLines(dir / "poses.jsonl");
  INFO("frames written: " << framesOf(expected));
  REQUIRE(expected.size() >= static_cast<std::size_t>(frames));
  const auto got = broker->consume("vtest", 1, expected.size(), seconds(30));
  REQUIRE(got.size() == expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    INFO("message " << i);
    CHECK(got[i].value == expected[i]);
    CHECK(got[i].key == "camera1");
  }
  std::size_t people = 0;
  for (const auto& line : expected) people += nlohmann::json::parse(line).at("objects").size();
  CHECK(people >= static_cast<std::size_t>(frames));
}

TEST_CASE("two cameras on one partitioned topic: each camera in one partition, in order",
          "[publish][kafka]") {
  KAFKA_BROKER(broker);
  REQUIRE(broker->createTopic("fleet", 3) == "");
  TempDir dir("jointflow-publish-kafka-fleet");
  const std::vector<std::string> cameras = {"camera-a", "camera-b"};
  std::vector<GstHarness*> hs;
  for (const auto& c : cameras)
    hs.push_back(writerAndPublisher(dir / (c + ".jsonl"), c, kafkaProps(broker, "fleet")));
  const int n = 150;
  for (int i = 0; i < n; ++i)
    for (GstHarness* h : hs) {
      REQUIRE(gst_harness_push(h, syntheticFrame(i)) == GST_FLOW_OK);
      gst_buffer_unref(gst_harness_pull(h));
    }
  for (GstHarness* h : hs) {
    gst_harness_push_event(h, gst_event_new_eos());
    CHECK(counterOf(h, "messages-published") == static_cast<guint64>(n));
    gst_harness_teardown(h);
  }
  const auto got = broker->consume("fleet", 3, 2 * n, seconds(30));
  REQUIRE(got.size() == static_cast<std::size_t>(2 * n));
  for (const auto& c : cameras) {
    INFO(c);
    std::vector<std::string> values;
    std::set<int> partitions;
    for (const auto& r : got)
      if (r.key == c) {
        values.push_back(r.value);
        partitions.insert(r.partition);
      }
    CHECK(partitions.size() == 1);
    CHECK(values == readLines(dir / (c + ".jsonl")));  // in order, once, byte-equal
  }
}

TEST_CASE("no broker at start: an error after max-connect-attempts, the video never blocked",
          "[publish][kafka][faults]") {
  const int port = freeLoopbackPort();
  PublishHarness h("method=kafka topic=t address=127.0.0.1:" + std::to_string(port) +
                   " max-connect-attempts=2 connect-timeout=500 max-reconnect-interval=200");
  const auto [pushed, r] = pushUntilError(h, seconds(15));
  CHECK(r == GST_FLOW_ERROR);
  CHECK(pushed > 3);  // frames went on flowing meanwhile
  const auto errors = busMessages(h.element(), GST_MESSAGE_ERROR);
  REQUIRE(errors.size() == 1);
  CHECK_THAT(errors[0],
             Catch::Contains("127.0.0.1:" + std::to_string(port)) && Catch::Contains("2 attempts"));
}

TEST_CASE("a topic the broker does not have is an error naming the topic property",
          "[publish][kafka][faults]") {
  KAFKA_BROKER(broker);
  PublishHarness h(kafkaProps(broker, "no-such-topic"));
  REQUIRE(waitUntil([&] { return h.push(0, 1) == GST_FLOW_ERROR; }, seconds(30)));
  const auto errors = busMessages(h.element(), GST_MESSAGE_ERROR);
  REQUIRE(errors.size() == 1);
  CHECK_THAT(errors[0], Catch::Contains("no-such-topic") && Catch::Contains("(property topic)"));
}

TEST_CASE("a message larger than the client takes is refused and counted; the rest go",
          "[publish][kafka][faults]") {
  KAFKA_BROKER(broker);
  REQUIRE(broker->createTopic("small", 1) == "");
  TempDir dir("jointflow-publish-kafka-small");
  {
    std::ofstream f(dir / "kafka.ini");
    f << "[kafka]\nmessage.max.bytes=1000\n";  // below one frame of two people (~3 kB)
  }
  PublishHarness h(kafkaProps(broker, "small") + " config-file=" + (dir / "kafka.ini"));
  REQUIRE(h.push(0, 2) == GST_FLOW_OK);
  GstBuffer* empty = blackFrame("RGB", kSynthW, kSynthH, 0);
  REQUIRE(gst_harness_push(h.harness(), empty) == GST_FLOW_OK);
  gst_buffer_unref(gst_harness_pull(h.harness()));
  h.eos();
  CHECK(h.counter("messages-refused") == 2);
  CHECK(h.counter("messages-published") == 1);
  const auto got = broker->consume("small", 1, 1, seconds(20));
  REQUIRE(got.size() == 1);
  CHECK(frameOf(got[0].value) == 2);
  const auto warnings = busMessages(h.element(), GST_MESSAGE_WARNING);
  CHECK(warnings.empty());  // librdkafka's refusal is counted and logged, not per frame on the bus
}

TEST_CASE("examples/consumer.py (a consumer group, pinned confluent-kafka) reads the tracks",
          "[publish][kafka][consumer]") {
  KAFKA_BROKER(broker);
  const std::string python = envOr("JOINTFLOW_CONSUMER_PYTHON", "");
  if (python.empty() || !std::filesystem::exists(python))
    JF_SKIP("no venv for examples/consumer.py (examples/consumer-venv.sh BUILD makes it)");
  REQUIRE(broker->createTopic("consumer-demo", 2) == "");
  for (const std::string camera : {"door", "hall"}) {
    PublishHarness h(kafkaProps(broker, "consumer-demo") + " source-id=" + camera);
    for (int i = 0; i < 20; ++i) {
      REQUIRE(gst_harness_push(h.harness(), leavingFrame(i)) == GST_FLOW_OK);
      gst_buffer_unref(gst_harness_pull(h.harness()));
    }
    h.eos();
    REQUIRE(h.counter("messages-published") == 20);
  }
  TempDir dir("jointflow-publish-consumer");
  const std::string cmd = python + " " + sourceRoot() + "/examples/consumer.py kafka://" +
                          broker->address() +
                          "/consumer-demo --group readers --from-beginning --end-after 5 "
                          "--max-messages 40 --idle-timeout 30 >" +
                          (dir / "out.txt") + " 2>" + (dir / "err.txt");
  const int status = std::system(cmd.c_str());
  INFO(readFile(dir / "err.txt"));
  REQUIRE(status == 0);
  checkConsumerOutput(readFile(dir / "out.txt"));
}

// Last: it restarts the program's broker.
TEST_CASE(
    "broker killed and restarted mid-stream: librdkafka holds the outage's frames and "
    "delivers them in order, once",
    "[publish][kafka][faults]") {
  KAFKA_BROKER(broker);
  REQUIRE(broker->createTopic("restart", 1) == "");
  // librdkafka retries the broker every 100 ms .. 1 s while it is away.
  PublishHarness h(kafkaProps(broker, "restart") +
                   " flush-timeout=60000 max-reconnect-interval=1000 source-id=cam9");
  auto paced = [&](int from, int to) {
    for (int i = from; i < to; ++i) {
      REQUIRE(h.push(i, i + 1) == GST_FLOW_OK);
      std::this_thread::sleep_for(milliseconds(20));
    }
  };
  paced(0, 20);
  REQUIRE(waitUntil([&] { return h.counter("messages-published") == 20; }, seconds(20)));
  broker->kill();
  const auto t0 = std::chrono::steady_clock::now();
  REQUIRE(h.push(20, 40) == GST_FLOW_OK);  // the outage
  // Never blocked (a loose bound, for the sanitizer build on a busy machine).
  CHECK(std::chrono::steady_clock::now() - t0 < milliseconds(3000));
  const std::string restarted = broker->start();
  REQUIRE(restarted == "");
  paced(40, 60);
  h.eos();
  CHECK(h.counter("messages-published") == 60);
  CHECK(h.counter("messages-dropped") == 0);
  const auto got = broker->consume("restart", 1, 60, seconds(30));
  std::vector<long> frames;
  for (const auto& r : got) frames.push_back(frameOf(r.value));
  std::vector<long> expected(60);
  for (long i = 0; i < 60; ++i) expected[i] = i;
  CHECK(frames == expected);
}
