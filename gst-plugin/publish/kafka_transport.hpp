// jointflowmetapublish method=kafka, on librdkafka. The message key is the source id, so that
// one camera's frames land in one partition and stay in order there; the partitioner is the
// Java client's (murmur2), so that a Java producer would pick the same partition for a camera.
// The producer is idempotent: librdkafka's retries after a broker restart neither reorder nor
// duplicate. librdkafka keeps its own connections (and reconnects with its own backoff, capped
// at max-reconnect-interval); connect() only checks, once, that a broker answers.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "transport.hpp"

struct rd_kafka_s;
struct rd_kafka_topic_s;

namespace jointflow::gst {

class KafkaTransport : public PublishTransport {
 public:
  struct Options {
    std::string bootstrap_servers;
    std::string topic;
    std::string key;  ///< the source id; empty: no key
    std::string client_id;
    /// librdkafka's own queue (queue.buffering.max.messages): messages it holds while no
    /// broker takes them, on top of the element's queue.
    std::size_t queue_limit = 300;
    std::chrono::milliseconds max_reconnect_interval{30000};
    /// From the config file, applied last (they may override the above but bootstrap.servers).
    std::vector<std::pair<std::string, std::string>> config;
  };

  KafkaTransport(Options options, std::shared_ptr<PublishCounters> counters, PublishLog log);
  ~KafkaTransport() override;

  std::string prepare() override;
  std::string connect(std::chrono::milliseconds timeout) override;
  bool connected() const override { return connected_; }
  Send send(const std::string& payload) override;
  void service(std::chrono::milliseconds timeout) override;
  std::size_t inFlight() const override { return static_cast<std::size_t>(in_flight_.load()); }
  void abandon() override;
  std::string fatalError() const override;

  /// Why Kafka would refuse @topic as a topic name ("" when it is valid): 1 to 249 characters of
  /// [a-zA-Z0-9._-], and neither "." nor "..". Written here since librdkafka leaves the check to
  /// the broker, and a bad name would only fail at the first message.
  static std::string topicError(const std::string& topic);

 private:
  void serve();
  void setFatal(const std::string& text);

  Options options_;
  std::shared_ptr<PublishCounters> counters_;
  PublishLog log_;
  rd_kafka_s* producer_ = nullptr;
  rd_kafka_topic_s* topic_ = nullptr;
  bool wake_enabled_ = false;
  std::atomic<bool> connected_{false};
  std::atomic<long> in_flight_{0};
  mutable std::mutex fatal_mutex_;
  std::string fatal_;
};

struct TransportRequest;
/// The transport table's factory (transports.cpp).
std::unique_ptr<PublishTransport> makeKafkaTransport(const TransportRequest& request);

}  // namespace jointflow::gst
