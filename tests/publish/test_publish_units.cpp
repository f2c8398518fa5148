// jointflowmetapublish without a broker: the bounded queue, the backoff schedule, addresses and
// URIs, the config file, the publishing thread (with a scripted transport, for exact counts and
// timings), and the element with method=file: byte for byte jointflowjsonwriter's output, clear
// errors for bad settings, refused oversize messages, EOS flushing.
#include <catch2/catch.hpp>

#include <poll.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "broker_process.hpp"  // waitUntil
#include "publish/config.hpp"
#include "publish/kafka_transport.hpp"
#include "publish/queue.hpp"
#include "publish/reconnect_backoff.hpp"
#include "publish/transports.hpp"
#include "publish/worker.hpp"
#include "publish_test_util.hpp"

using namespace jointflow::test;
using namespace jointflow::gst;
using std::chrono::milliseconds;

namespace {

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("jointflow-publish-" + name)).string();
}

// A transport whose broker is scripted by the test: refuses connections while `reachable` is
// false, delivers each message at once while it is true, and records what it was given.
class ScriptedTransport : public PublishTransport {
 public:
  explicit ScriptedTransport(std::shared_ptr<PublishCounters> counters) : counters_(counters) {}
  std::string prepare() override { return ""; }
  std::string connect(milliseconds) override {
    attempts++;
    attempt_times.push_back(std::chrono::steady_clock::now());
    if (!reachable) return "refused (scripted)";
    up = true;
    return "";
  }
  bool connected() const override { return up && reachable; }
  Send send(const std::string& payload) override {
    if (!reachable) {
      up = false;
      return Send::Disconnected;
    }
    std::lock_guard<std::mutex> lock(mutex);
    sent.push_back(payload);
    counters_->delivered++;
    return Send::Sent;
  }
  void service(milliseconds timeout) override { waitReadableFd(timeout); }
  std::size_t inFlight() const override { return 0; }
  void abandon() override {}

  std::atomic<bool> reachable{false};
  std::atomic<bool> up{false};
  std::atomic<int> attempts{0};
  std::vector<std::chrono::steady_clock::time_point> attempt_times;
  std::mutex mutex;
  std::vector<std::string> sent;

 private:
  void waitReadableFd(milliseconds timeout) {
    pollfd p{wakeFd(), POLLIN, 0};
    poll(&p, 1, static_cast<int>(timeout.count()));
  }
  std::shared_ptr<PublishCounters> counters_;
};

}  // namespace

TEST_CASE("the queue drops the oldest message when full and counts it", "[publish][queue]") {
  PublishQueue q(3);
  CHECK_FALSE(q.push("a"));
  CHECK_FALSE(q.push("b"));
  CHECK_FALSE(q.push("c"));
  CHECK(q.push("d"));  // "a" goes
  CHECK(q.push("e"));  // "b" goes
  CHECK(q.size() == 3);
  CHECK(q.dropped() == 2);
  CHECK(*q.pop() == "c");
  CHECK(*q.pop() == "d");
  CHECK(q.push("f") == false);
  CHECK(q.clear() == 2);
  CHECK(q.dropped() == 4);
  CHECK_FALSE(q.pop().has_value());
  CHECK(PublishQueue(0).capacity() == 1);
}

TEST_CASE("reconnect waits double from the first up to the cap, with jitter in [1/2, 1]",
          "[publish][backoff]") {
  const ReconnectBackoff b(milliseconds(100), milliseconds(1000));
  CHECK(b.nominal(1) == milliseconds(100));
  CHECK(b.nominal(2) == milliseconds(200));
  CHECK(b.nominal(3) == milliseconds(400));
  CHECK(b.nominal(4) == milliseconds(800));
  CHECK(b.nominal(5) == milliseconds(1000));
  CHECK(b.nominal(1000000) == milliseconds(1000));
  CHECK(b.delay(3, 0.0) == milliseconds(200));
  CHECK(b.delay(3, 1.0) == milliseconds(400));
  CHECK(b.delay(3, 0.5) == milliseconds(300));
  CHECK(b.delay(3, 7.0) == milliseconds(400));  // clamped
  const ReconnectBackoff odd(milliseconds(100), milliseconds(50));
  CHECK(odd.max() == milliseconds(100));  // a cap below the first wait is the first wait
}

TEST_CASE("publish URIs name method, broker and topic", "[publish][address]") {
  std::string error;
  auto t = parsePublishUri("mqtt://broker.local:1884/poses/cam1", &error);
  REQUIRE(t);
  CHECK(t->transport == findTransport("mqtt"));
  CHECK(t->address == "broker.local:1884");
  CHECK(t->topic == "poses/cam1");
  t = parsePublishUri("kafka://127.0.0.1/poses", &error);
  REQUIRE(t);
  CHECK(t->transport == findTransport("kafka"));
  CHECK(t->address == "127.0.0.1:9092");
  CHECK(t->topic == "poses");
  t = parsePublishUri("mqtt://[::1]:1883/a%20b", &error);
  REQUIRE(t);
  CHECK(t->address == "[::1]:1883");
  CHECK(t->topic == "a b");
  t = parsePublishUri("out/poses.jsonl", &error);
  REQUIRE(t);
  CHECK(t->transport == findTransport("file"));
  CHECK(t->address == "out/poses.jsonl");
  t = parsePublishUri("file:///tmp/x.jsonl", &error);
  REQUIRE(t);
  CHECK(t->address == "/tmp/x.jsonl");

  CHECK_FALSE(parsePublishUri("mqtt://host:1883", &error));
  CHECK_THAT(error, Catch::Contains("names no topic"));
  CHECK_FALSE(parsePublishUri("amqp://host/q", &error));
  CHECK_THAT(error, Catch::Contains("unknown scheme \"amqp\""));
  CHECK_FALSE(parsePublishUri("kafka://host:99999/t", &error));
  CHECK_FALSE(parsePublishUri("", &error));
}

// The transport table is the one list: each row is a value of the element's `method` (its index
// the value, its name the nick), a scheme of --publish's URIs with the row's default port, and
// what the element builds.
TEST_CASE("every transport row is a method value and a --publish scheme", "[publish][address]") {
  initGst();
  GstElement* element = gst_element_factory_make("jointflowmetapublish", nullptr);
  REQUIRE(element);
  GParamSpec* spec = g_object_class_find_property(G_OBJECT_GET_CLASS(element), "method");
  REQUIRE(G_IS_PARAM_SPEC_ENUM(spec));
  GEnumClass* values = G_PARAM_SPEC_ENUM(spec)->enum_class;
  const auto& rows = publishTransports();
  CHECK(values->n_values == rows.size());
  CHECK(G_PARAM_SPEC_ENUM(spec)->default_value == 0);  // the first row, a file
  for (size_t i = 0; i < rows.size(); ++i) {
    const TransportRow& row = rows[i];
    INFO(row.name);
    const GEnumValue* value = g_enum_get_value_by_nick(values, row.name);
    REQUIRE(value);
    CHECK(value->value == static_cast<gint>(i));
    CHECK(std::string(value->value_name) == row.description);
    std::string error;
    const std::string scheme = row.scheme;
    const auto target = parsePublishUri(
        scheme + (row.broker() ? "://broker.local/poses" : ":///tmp/poses.jsonl"), &error);
    REQUIRE(target);
    CHECK(target->transport == &row);
    CHECK(target->address ==
          (row.broker() ? "broker.local:" + std::to_string(row.default_port) : "/tmp/poses.jsonl"));
    CHECK(target->topic == (row.broker() ? "poses" : ""));
    // The element takes the name the row's target carries (as jointflow-track sets it).
    gst_util_set_object_arg(G_OBJECT(element), "method", target->transport->name);
    gint method = -1;
    g_object_get(element, "method", &method, nullptr);
    CHECK(method == static_cast<gint>(i));
  }
  gst_object_unref(element);
  CHECK(findTransport("file") == &rows.front());  // a plain path is a file
  CHECK(findTransport("amqp") == nullptr);
}

TEST_CASE("broker addresses: host:port, IPv6, Kafka lists, clear failures", "[publish][address]") {
  const TransportRow& mqtt = *findTransport("mqtt");
  const TransportRow& kafka = *findTransport("kafka");
  std::string error;
  auto e = parseBrokerAddress(mqtt, "localhost", &error);
  REQUIRE(e);
  CHECK(e->at(0).host == "localhost");
  CHECK(e->at(0).port == 1883);
  e = parseBrokerAddress(kafka, "k1:9093, [::1]:9094", &error);
  REQUIRE(e);
  REQUIRE(e->size() == 2);
  CHECK(e->at(1).host == "::1");
  CHECK(bootstrapServers(*e) == "k1:9093,[::1]:9094");
  CHECK_FALSE(parseBrokerAddress(mqtt, "a:1,b:2", &error));
  CHECK_THAT(error, Catch::Contains("one broker"));
  CHECK_FALSE(parseBrokerAddress(mqtt, "", &error));
  CHECK_FALSE(parseBrokerAddress(kafka, "host:notaport", &error));
  CHECK_FALSE(parseBrokerAddress(kafka, "host:0", &error));
  CHECK_FALSE(parseBrokerAddress(kafka, "host:70000", &error));

  CHECK(KafkaTransport::topicError("poses.camera-1_x").empty());
  CHECK_FALSE(KafkaTransport::topicError("").empty());
  CHECK_FALSE(KafkaTransport::topicError("..").empty());
  CHECK_FALSE(KafkaTransport::topicError("has space").empty());
  CHECK_FALSE(KafkaTransport::topicError("poses/cam1").empty());
  CHECK_FALSE(KafkaTransport::topicError(std::string(250, 'a')).empty());
}

TEST_CASE("the config file: MQTT credentials and TLS, librdkafka properties, clear errors",
          "[publish][config]") {
  const std::string path = tempPath("config.ini");
  {
    std::ofstream f(path);
    f << "# camera 1\n[mqtt]\nusername=cam1\npassword=p=ss;#word\nca-file=/etc/ca.pem\n"
         "tls-insecure=true\n[kafka]\nsecurity.protocol=SASL_SSL\nsasl.username=cam1\n";
  }
  std::string error;
  auto c = loadPublishConfig(path, &error);
  REQUIRE(c);
  CHECK(c->mqtt.username == "cam1");
  CHECK(c->mqtt.password == "p=ss;#word");
  CHECK(c->mqtt.tls());
  CHECK(c->mqtt.tls_insecure);
  REQUIRE(c->kafka.size() == 2);
  CHECK(c->kafka[0] == std::make_pair(std::string("security.protocol"), std::string("SASL_SSL")));

  {
    std::ofstream f(path);
    f << "[mqtt]\nusername=a\npasword=typo\n";
  }
  CHECK_FALSE(loadPublishConfig(path, &error));
  CHECK_THAT(error, Catch::Contains("unknown key \"pasword\""));
  {
    std::ofstream f(path);
    f << "[amqp]\nx=1\n";
  }
  CHECK_FALSE(loadPublishConfig(path, &error));
  CHECK_THAT(error, Catch::Contains("unknown group [amqp]"));
  {
    std::ofstream f(path);
    f << "[mqtt]\ncert-file=/a.pem\n";
  }
  CHECK_FALSE(loadPublishConfig(path, &error));
  CHECK_THAT(error, Catch::Contains("cert-file and key-file go together"));
  {
    std::ofstream f(path);
    f << "not a key file\n";
  }
  CHECK_FALSE(loadPublishConfig(path, &error));
  CHECK_THAT(error, Catch::Contains(path));
  CHECK_FALSE(loadPublishConfig("/nonexistent/jf.ini", &error));
  CHECK_THAT(error, Catch::Contains("/nonexistent/jf.ini"));
  std::filesystem::remove(path);
}

TEST_CASE("the publishing thread gives up after max-connect-attempts, waiting with backoff",
          "[publish][worker]") {
  auto counters = std::make_shared<PublishCounters>();
  auto transport = std::make_unique<ScriptedTransport>(counters);
  ScriptedTransport* t = transport.get();
  PublishWorkerSettings s;
  s.max_connect_attempts = 4;
  s.first_retry = milliseconds(40);
  s.max_reconnect_interval = milliseconds(100);
  std::atomic<int> fatal_calls{0};
  std::string fatal;
  std::mutex fatal_mutex;
  PublishWorker w(
      std::move(transport), counters, s, [](GstDebugLevel, const std::string&) {},
      [&](const std::string& why) {
        std::lock_guard<std::mutex> lock(fatal_mutex);
        fatal = why;
        fatal_calls++;
      });
  REQUIRE(waitUntil([&] { return w.failed(); }, milliseconds(5000)));
  CHECK(t->attempts == 4);
  CHECK(fatal_calls == 1);
  CHECK_THAT(fatal, Catch::Contains("4 attempts") && Catch::Contains("max-connect-attempts=4"));
  // Waits of [20, 40], [40, 80] and [50, 100] ms between the four attempts.
  REQUIRE(t->attempt_times.size() == 4);
  const milliseconds lows[] = {milliseconds(20), milliseconds(40), milliseconds(50)};
  for (int k = 0; k < 3; ++k) {
    const auto gap =
        std::chrono::duration_cast<milliseconds>(t->attempt_times[k + 1] - t->attempt_times[k]);
    INFO("wait " << k + 1 << ": " << gap.count() << " ms");
    CHECK(gap >= lows[k]);
    CHECK(gap < lows[k] * 2 + milliseconds(200));
  }
  CHECK(w.offer("x") == PublishWorker::Offer::Failed);
}

TEST_CASE("while the broker is away the newest max-queue-size messages are kept, in order",
          "[publish][worker]") {
  auto counters = std::make_shared<PublishCounters>();
  auto transport = std::make_unique<ScriptedTransport>(counters);
  ScriptedTransport* t = transport.get();
  PublishWorkerSettings s;
  s.max_connect_attempts = 0;  // without end
  s.first_retry = milliseconds(10);
  s.max_reconnect_interval = milliseconds(20);
  s.queue_capacity = 5;
  s.max_message_size = 10;
  PublishWorker w(
      std::move(transport), counters, s, [](GstDebugLevel, const std::string&) {},
      [](const std::string&) {});
  for (int i = 0; i < 12; ++i) w.offer(std::to_string(i));
  CHECK(w.offer("far too long a message") == PublishWorker::Offer::Refused);
  CHECK(w.dropped() == 7);
  CHECK(w.refused() == 1);
  CHECK(w.flush(milliseconds(100)) == 5);  // bounded: nothing can be delivered yet
  t->reachable = true;
  CHECK(w.flush(milliseconds(5000)) == 0);
  w.offer("12");
  CHECK(w.flush(milliseconds(5000)) == 0);
  std::lock_guard<std::mutex> lock(t->mutex);
  CHECK(t->sent == std::vector<std::string>{"7", "8", "9", "10", "11", "12"});
  CHECK(w.delivered() == 6);
}

TEST_CASE("method=file writes byte for byte what jointflowjsonwriter writes, source_id included",
          "[publish][file]") {
  const std::string published = tempPath("file-published.jsonl");
  const std::string written = tempPath("file-written.jsonl");
  initGst();
  GstHarness* h = gst_harness_new_parse(
      ("jointflowjsonwriter source-id=cam-7 location=" + written +
       " ! jointflowmetapublish method=file source-id=cam-7 address=" + published)
          .c_str());
  gst_harness_set_src_caps_str(h, capsFor("RGB", kSynthW, kSynthH).c_str());
  for (int i = 0; i < 25; ++i) {
    REQUIRE(gst_harness_push(h, syntheticFrame(i)) == GST_FLOW_OK);
    gst_buffer_unref(gst_harness_pull(h));
  }
  GstBuffer* plain = blackFrame("RGB", kSynthW, kSynthH, GST_CLOCK_TIME_NONE);  // no meta
  REQUIRE(gst_harness_push(h, plain) == GST_FLOW_OK);
  gst_buffer_unref(gst_harness_pull(h));
  gst_harness_push_event(h, gst_event_new_eos());
  gst_harness_teardown(h);

  const auto a = readLines(written);
  const auto b = readLines(published);
  REQUIRE(a.size() == 26);
  CHECK(a == b);
  const auto first = nlohmann::json::parse(a[3]);
  CHECK(first.at("source_id") == "cam-7");
  CHECK(first.at("frame") == 3);
  CHECK(first.at("objects").size() == 2);
  CHECK(first.at("objects")[0].at("keypoints").at("nose").at("x") == 8);
  CHECK(nlohmann::json::parse(a[25]).at("objects").empty());
  std::filesystem::remove(published);
  std::filesystem::remove(written);
}

TEST_CASE("without source-id the writer's record has no source_id field", "[publish][file]") {
  const std::string path = tempPath("no-source.jsonl");
  initGst();
  GstHarness* h = gst_harness_new_parse(("jointflowjsonwriter location=" + path).c_str());
  gst_harness_set_src_caps_str(h, capsFor("RGB", kSynthW, kSynthH).c_str());
  REQUIRE(gst_harness_push(h, syntheticFrame(0)) == GST_FLOW_OK);
  gst_buffer_unref(gst_harness_pull(h));
  gst_harness_teardown(h);
  const auto lines = readLines(path);
  REQUIRE(lines.size() == 1);
  CHECK_FALSE(nlohmann::json::parse(lines[0]).contains("source_id"));
  std::filesystem::remove(path);
}

TEST_CASE("an oversize message is refused with a warning; the others are published",
          "[publish][file]") {
  const std::string path = tempPath("oversize.jsonl");
  std::string small;
  {
    PublishHarness h("method=file max-message-size=200 address=" + path);
    REQUIRE(h.push(0, 3) == GST_FLOW_OK);  // two people: ~1.5 kB each
    GstBuffer* empty = blackFrame("RGB", kSynthW, kSynthH, 0);
    REQUIRE(gst_harness_push(h.harness(), empty) == GST_FLOW_OK);
    gst_buffer_unref(gst_harness_pull(h.harness()));
    h.eos();
    CHECK(h.counter("messages-refused") == 3);
    CHECK(h.counter("messages-published") == 1);
    CHECK(h.counter("messages-dropped") == 0);
    const auto warnings = busMessages(h.element(), GST_MESSAGE_WARNING);
    REQUIRE(warnings.size() == 1);  // rate-limited: one per second
    CHECK_THAT(warnings[0],
               Catch::Contains("max-message-size (200 bytes)") && Catch::Contains("Frame 0"));
  }
  const auto lines = readLines(path);
  REQUIRE(lines.size() == 1);
  CHECK(frameOf(lines[0]) == 3);
  std::filesystem::remove(path);
}

namespace {

std::string startError(const std::string& properties) {
  initGst();
  GstElement* pipeline = gst_parse_launch(
      ("videotestsrc num-buffers=1 ! jointflowmetapublish " + properties + " ! fakesink").c_str(),
      nullptr);
  REQUIRE(pipeline != nullptr);
  const bool failed = gst_element_set_state(pipeline, GST_STATE_PAUSED) == GST_STATE_CHANGE_FAILURE;
  std::string error = busError(pipeline);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(pipeline);
  return failed ? error : "(started)";
}

}  // namespace

TEST_CASE("bad settings fail the start with an error that names the property",
          "[publish][errors]") {
  CHECK_THAT(startError("method=mqtt address=host:notaport topic=t"),
             Catch::Contains("(property address)") && Catch::Contains("host:notaport"));
  CHECK_THAT(startError("method=mqtt address=\"a:1,b:2\" topic=t"),
             Catch::Contains("(property address)"));
  CHECK_THAT(startError("method=kafka topic=t"), Catch::Contains("(property address)"));
  CHECK_THAT(startError("method=mqtt address=127.0.0.1:1883 topic=poses/#"),
             Catch::Contains("(property topic)") && Catch::Contains("wildcard"));
  CHECK_THAT(startError("method=mqtt address=127.0.0.1:1883"), Catch::Contains("(property topic)"));
  CHECK_THAT(startError("method=kafka address=127.0.0.1:9092 topic=\"bad topic\""),
             Catch::Contains("(property topic)"));
  CHECK_THAT(startError("method=kafka address=127.0.0.1:9092 topic=t config-file=/nonexistent.ini"),
             Catch::Contains("(property config-file)") && Catch::Contains("/nonexistent.ini"));
  CHECK_THAT(startError("method=file address=/nonexistent-dir/x.jsonl"),
             Catch::Contains("/nonexistent-dir/x.jsonl") && Catch::Contains("(property address)"));

  const std::string conf = tempPath("bad-kafka.ini");
  {
    std::ofstream f(conf);
    f << "[kafka]\nno.such.property=1\n";
  }
  CHECK_THAT(startError("method=kafka address=127.0.0.1:9092 topic=t config-file=" + conf),
             Catch::Contains("no.such.property"));
  {
    std::ofstream f(conf);
    f << "[mqtt]\nca-file=/nonexistent/ca.pem\n";
  }
  CHECK_THAT(startError("method=mqtt address=127.0.0.1:1883 topic=t config-file=" + conf),
             Catch::Contains("ca-file \"/nonexistent/ca.pem\""));
  std::filesystem::remove(conf);
}

TEST_CASE("the method is an enum: a nonsense value is refused by GLib", "[publish][errors]") {
  initGst();
  GError* err = nullptr;
  GstElement* pipeline =
      gst_parse_launch("videotestsrc ! jointflowmetapublish method=amqp ! fakesink", &err);
  CHECK((pipeline == nullptr || err != nullptr));
  if (err) g_error_free(err);
  if (pipeline) gst_object_unref(pipeline);
}
