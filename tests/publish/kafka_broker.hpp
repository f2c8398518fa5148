// A Kafka broker for the publish tests: one process in KRaft mode (broker and controller
// combined) on two free loopback ports, from the jars scripts/fetch-kafka.sh copied into the
// build folder, run with Debian's OpenJDK. Topics are not created on first use
// (auto.create.topics.enable=false): the tests create theirs with librdkafka's admin API, with
// the partitions they need, and an unknown topic is an error they can test.
#pragma once

#include <librdkafka/rdkafka.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "broker_process.hpp"

namespace jointflow::test {

class KafkaBroker {
 public:
  /// @jars: the folder of kafka_2.13-*.jar and its dependencies; @log4j: the log4j2 config.
  KafkaBroker(std::string jars, std::string log4j)
      : jars_(std::move(jars)),
        log4j_(std::move(log4j)),
        dir_("jointflow-kafka"),
        port_(freeLoopbackPort()),
        controller_port_(freeLoopbackPort()) {
    std::ofstream conf(dir_ / "server.properties");
    conf << "process.roles=broker,controller\nnode.id=1\n"
         << "controller.quorum.voters=1@127.0.0.1:" << controller_port_ << "\n"
         << "listeners=PLAINTEXT://127.0.0.1:" << port_
         << ",CONTROLLER://127.0.0.1:" << controller_port_ << "\n"
         << "advertised.listeners=PLAINTEXT://127.0.0.1:" << port_ << "\n"
         << "controller.listener.names=CONTROLLER\ninter.broker.listener.name=PLAINTEXT\n"
         << "listener.security.protocol.map=PLAINTEXT:PLAINTEXT,CONTROLLER:PLAINTEXT\n"
         << "log.dirs=" << (dir_ / "data") << "\nnum.partitions=1\n"
         << "auto.create.topics.enable=false\n"
         << "offsets.topic.replication.factor=1\ntransaction.state.log.replication.factor=1\n"
         << "transaction.state.log.min.isr=1\ngroup.initial.rebalance.delay.ms=0\n";
  }

  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  std::string log() const { return readFile(dir_ / "kafka.log"); }

  /// Formats the log folder (first start only) and starts the broker; waits at most 120 s for
  /// "Kafka Server started". Returns "" or why it failed.
  std::string start() {
    if (!formatted_) {
      ChildProcess format(java({"kafka.tools.StorageTool", "format", "-t", "MkU3OEVBNTcwNTJENDM2Qg",
                                "-c", dir_ / "server.properties"}),
                          dir_ / "format.log");
      if (!waitUntil([&] { return !format.running(); }, std::chrono::seconds(120)))
        return "formatting the KRaft log folder took over 120 s";
      if (!std::filesystem::exists(dir_ / "data/meta.properties"))
        return "formatting the KRaft log folder failed:\n" + readFile(dir_ / "format.log");
      formatted_ = true;
    }
    const std::size_t log_start = log().size();
    process_ = std::make_unique<ChildProcess>(java({"kafka.Kafka", dir_ / "server.properties"}),
                                              dir_ / "kafka.log");
    const bool started = waitUntil(
        [&] {
          return log().find("Kafka Server started", log_start) != std::string::npos ||
                 !process_->running();
        },
        std::chrono::seconds(120));
    if (!started || !process_->running()) {
      process_.reset();
      return "the Kafka broker did not start within 120 s:\n" + tail(log(), 3000);
    }
    return "";
  }
  /// SIGKILL: a crash.
  void kill() { process_.reset(); }

  /// Creates @topic with @partitions (waits at most 60 s); "" or the error.
  std::string createTopic(const std::string& topic, int partitions) {
    char err[512];
    rd_kafka_conf_t* conf = rd_kafka_conf_new();
    rd_kafka_conf_set(conf, "bootstrap.servers", address().c_str(), err, sizeof err);
    rd_kafka_t* rk = rd_kafka_new(RD_KAFKA_PRODUCER, conf, err, sizeof err);
    if (!rk) return err;
    rd_kafka_NewTopic_t* nt = rd_kafka_NewTopic_new(topic.c_str(), partitions, 1, err, sizeof err);
    rd_kafka_queue_t* q = rd_kafka_queue_new(rk);
    rd_kafka_AdminOptions_t* opts = rd_kafka_AdminOptions_new(rk, RD_KAFKA_ADMIN_OP_CREATETOPICS);
    rd_kafka_AdminOptions_set_operation_timeout(opts, 30000, err, sizeof err);
    rd_kafka_CreateTopics(rk, &nt, 1, opts, q);
    std::string result = "no answer within 60 s";
    rd_kafka_event_t* ev = rd_kafka_queue_poll(q, 60000);
    if (ev) {
      const rd_kafka_CreateTopics_result_t* res = rd_kafka_event_CreateTopics_result(ev);
      size_t n = 0;
      const rd_kafka_topic_result_t** topics =
          res ? rd_kafka_CreateTopics_result_topics(res, &n) : nullptr;
      if (rd_kafka_event_error(ev))
        result = rd_kafka_event_error_string(ev);
      else if (n == 1 && rd_kafka_topic_result_error(topics[0]))
        result = rd_kafka_topic_result_error_string(topics[0]);
      else
        result = "";
      rd_kafka_event_destroy(ev);
    }
    rd_kafka_AdminOptions_destroy(opts);
    rd_kafka_NewTopic_destroy(nt);
    rd_kafka_queue_destroy(q);
    rd_kafka_destroy(rk);
    return result;
  }

  struct Record {
    int partition;
    std::string key;
    std::string value;
  };
  /// Reads @topic's @partitions from the beginning until @n records came or @timeout passed.
  std::vector<Record> consume(const std::string& topic, int partitions, std::size_t n,
                              std::chrono::milliseconds timeout) {
    char err[512];
    rd_kafka_conf_t* conf = rd_kafka_conf_new();
    rd_kafka_conf_set(conf, "bootstrap.servers", address().c_str(), err, sizeof err);
    rd_kafka_conf_set(conf, "group.id", ("jointflow-test-" + topic).c_str(), err, sizeof err);
    rd_kafka_conf_set(conf, "enable.auto.commit", "false", err, sizeof err);
    rd_kafka_t* rk = rd_kafka_new(RD_KAFKA_CONSUMER, conf, err, sizeof err);
    rd_kafka_topic_partition_list_t* parts = rd_kafka_topic_partition_list_new(partitions);
    for (int p = 0; p < partitions; ++p)
      rd_kafka_topic_partition_list_add(parts, topic.c_str(), p)->offset =
          RD_KAFKA_OFFSET_BEGINNING;
    rd_kafka_assign(rk, parts);
    rd_kafka_topic_partition_list_destroy(parts);
    std::vector<Record> out;
    auto poll = [&](int ms) {
      rd_kafka_message_t* m = rd_kafka_consumer_poll(rk, ms);
      if (!m) return;
      if (!m->err)
        out.push_back({m->partition,
                       m->key ? std::string(static_cast<const char*>(m->key), m->key_len) : "",
                       std::string(static_cast<const char*>(m->payload), m->len)});
      rd_kafka_message_destroy(m);
    };
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (out.size() < n && std::chrono::steady_clock::now() < deadline) poll(200);
    // Anything beyond @n would be a duplicate: look a little longer for one.
    const auto extra = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
    while (std::chrono::steady_clock::now() < extra) poll(100);
    rd_kafka_consumer_close(rk);
    rd_kafka_destroy(rk);
    return out;
  }

 private:
  std::vector<std::string> java(std::vector<std::string> args) const {
    std::vector<std::string> cmd = {"java", "-Xms64m", "-Xmx512m", "-XX:+UseSerialGC",
                                    // C1 only: the broker starts in half the time on 2 cores
                                    "-XX:TieredStopAtLevel=1", "-XX:-UsePerfData",
                                    "-Dlog4j2.configurationFile=" + log4j_, "-cp", jars_ + "/*"};
    cmd.insert(cmd.end(), args.begin(), args.end());
    return cmd;
  }
  static std::string tail(const std::string& s, std::size_t n) {
    return s.size() > n ? s.substr(s.size() - n) : s;
  }

  std::string jars_;
  std::string log4j_;
  TempDir dir_;
  int port_;
  int controller_port_;
  bool formatted_ = false;
  std::unique_ptr<ChildProcess> process_;
};

}  // namespace jointflow::test
