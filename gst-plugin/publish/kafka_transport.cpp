#include "kafka_transport.hpp"

#include <librdkafka/rdkafka.h>

#include <cstdint>

#include "transports.hpp"

namespace jointflow::gst {
namespace {

KafkaTransport* self(void* opaque) {
  return static_cast<KafkaTransport*>(opaque);
}

}  // namespace

KafkaTransport::KafkaTransport(Options options, std::shared_ptr<PublishCounters> counters,
                               PublishLog log)
    : options_(std::move(options)), counters_(std::move(counters)), log_(std::move(log)) {}

KafkaTransport::~KafkaTransport() {
  abandon();
}

std::string KafkaTransport::topicError(const std::string& topic) {
  if (topic.empty()) return "the topic is empty";
  if (topic.size() > 249) return "a Kafka topic has at most 249 characters";
  if (topic == "." || topic == "..") return "\"" + topic + "\" is not a Kafka topic name";
  for (const char c : topic) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '.' || c == '_' || c == '-';
    if (!ok) return "\"" + topic + "\": a Kafka topic has only letters, digits, '.', '_' and '-'";
  }
  return "";
}

std::unique_ptr<PublishTransport> makeKafkaTransport(const TransportRequest& request) {
  KafkaTransport::Options options;
  options.bootstrap_servers = bootstrapServers(request.endpoints);
  options.topic = request.topic;
  options.key = request.source_id;
  options.client_id = request.client_id;
  options.queue_limit = request.queue_capacity;
  options.max_reconnect_interval = request.max_reconnect_interval;
  options.config = request.config.kafka;
  return std::make_unique<KafkaTransport>(std::move(options), request.counters, request.log);
}

std::string KafkaTransport::fatalError() const {
  std::lock_guard<std::mutex> lock(fatal_mutex_);
  return fatal_;
}

void KafkaTransport::setFatal(const std::string& text) {
  std::lock_guard<std::mutex> lock(fatal_mutex_);
  if (fatal_.empty()) fatal_ = text;
}

std::string KafkaTransport::prepare() {
  char err[512];
  rd_kafka_conf_t* conf = rd_kafka_conf_new();
  auto set = [&](const std::string& key, const std::string& value, const std::string& origin) {
    if (rd_kafka_conf_set(conf, key.c_str(), value.c_str(), err, sizeof err) == RD_KAFKA_CONF_OK)
      return std::string();
    return origin + ": " + err;
  };
  const std::vector<std::pair<std::string, std::string>> ours = {
      {"bootstrap.servers", options_.bootstrap_servers},
      {"client.id", options_.client_id},
      {"enable.idempotence", "true"},
      {"partitioner", "murmur2_random"},
      {"queue.buffering.max.messages",
       std::to_string(std::max<std::size_t>(options_.queue_limit, 1))},
      {"reconnect.backoff.max.ms",
       std::to_string(
           std::max<long>(10, static_cast<long>(options_.max_reconnect_interval.count())))},
      {"reconnect.backoff.ms", "100"},
  };
  std::string error;
  for (const auto& [key, value] : ours)
    if (error.empty()) error = set(key, value, "librdkafka setting " + key);
  for (const auto& [key, value] : options_.config) {
    if (!error.empty()) break;
    if (key == "bootstrap.servers") {
      error = "config-file [kafka] bootstrap.servers: the brokers come from the address property";
      break;
    }
    error = set(key, value, "config-file [kafka] " + key);
  }
  if (!error.empty()) {
    rd_kafka_conf_destroy(conf);
    return error;
  }
  rd_kafka_conf_set_opaque(conf, this);
  rd_kafka_conf_set_dr_msg_cb(conf, [](rd_kafka_t*, const rd_kafka_message_t* m, void* opaque) {
    KafkaTransport* t = self(opaque);
    t->in_flight_--;
    if (m->err == RD_KAFKA_RESP_ERR_NO_ERROR) {
      t->counters_->delivered++;
      return;
    }
    t->counters_->lost++;
    if (m->err == RD_KAFKA_RESP_ERR__UNKNOWN_TOPIC ||
        m->err == RD_KAFKA_RESP_ERR_UNKNOWN_TOPIC_OR_PART)
      t->setFatal("topic \"" + t->options_.topic +
                  "\" does not exist on the broker, which does not create topics (property topic)");
    else if (m->err == RD_KAFKA_RESP_ERR_MSG_SIZE_TOO_LARGE)
      t->log_(GST_LEVEL_WARNING, "the broker refused a message as too large (" +
                                     std::to_string(m->len) + " bytes): lower max-message-size");
    else
      t->log_(GST_LEVEL_INFO, std::string("message not delivered: ") + rd_kafka_err2str(m->err));
  });
  rd_kafka_conf_set_error_cb(conf, [](rd_kafka_t* rk, int code, const char* reason, void* opaque) {
    KafkaTransport* t = self(opaque);
    if (code == RD_KAFKA_RESP_ERR__FATAL) {
      char text[512];
      rd_kafka_fatal_error(rk, text, sizeof text);
      t->setFatal(std::string("Kafka producer failed: ") + text);
      return;
    }
    t->log_(code == RD_KAFKA_RESP_ERR__ALL_BROKERS_DOWN ? GST_LEVEL_WARNING : GST_LEVEL_INFO,
            std::string("librdkafka: ") + rd_kafka_err2str(static_cast<rd_kafka_resp_err_t>(code)) +
                ": " + (reason ? reason : ""));
  });
  rd_kafka_conf_set_log_cb(
      conf, [](const rd_kafka_t* rk, int level, const char* fac, const char* buf) {
        KafkaTransport* t = self(rd_kafka_opaque(rk));
        t->log_(level <= 4 ? GST_LEVEL_INFO : GST_LEVEL_DEBUG,
                std::string("librdkafka ") + (fac ? fac : "") + ": " + (buf ? buf : ""));
      });
  producer_ = rd_kafka_new(RD_KAFKA_PRODUCER, conf, err, sizeof err);
  if (!producer_) {
    rd_kafka_conf_destroy(conf);  // not taken over on failure
    return std::string("could not create the Kafka producer: ") + err;
  }
  topic_ = rd_kafka_topic_new(producer_, options_.topic.c_str(), nullptr);
  if (!topic_) {
    return "topic \"" + options_.topic + "\": " + rd_kafka_err2str(rd_kafka_last_error());
  }
  return "";
}

std::string KafkaTransport::connect(std::chrono::milliseconds timeout) {
  if (!producer_) return "the Kafka producer was not created";
  if (!wake_enabled_ && wakeFd() >= 0) {
    // Delivery reports wake the publishing thread: librdkafka writes to the eventfd when its
    // main queue (served by rd_kafka_poll) gets an event. An eventfd takes 8-byte writes.
    static const std::uint64_t one = 1;
    rd_kafka_queue_t* main_queue = rd_kafka_queue_get_main(producer_);
    rd_kafka_queue_io_event_enable(main_queue, wakeFd(), &one, sizeof one);
    rd_kafka_queue_destroy(main_queue);
    wake_enabled_ = true;
  }
  const rd_kafka_metadata_t* metadata = nullptr;
  const rd_kafka_resp_err_t err =
      rd_kafka_metadata(producer_, 0, topic_, &metadata, static_cast<int>(timeout.count()));
  if (err != RD_KAFKA_RESP_ERR_NO_ERROR)
    return options_.bootstrap_servers + ": " + rd_kafka_err2str(err) +
           (err == RD_KAFKA_RESP_ERR__TRANSPORT || err == RD_KAFKA_RESP_ERR__TIMED_OUT
                ? " (no broker answered within connect-timeout)"
                : "");
  // A broker that does not create topics answers for an unknown one with this error. It is a
  // failed attempt, not yet a fatal error: a topic created just before may not have reached
  // every broker's metadata yet. After max-connect-attempts the element stops naming the topic.
  if (metadata->topic_cnt == 1 &&
      metadata->topics[0].err == RD_KAFKA_RESP_ERR_UNKNOWN_TOPIC_OR_PART) {
    rd_kafka_metadata_destroy(metadata);
    return "topic \"" + options_.topic +
           "\" does not exist on the broker, which does not create topics (property topic)";
  }
  rd_kafka_metadata_destroy(metadata);
  connected_ = true;
  return "";
}

PublishTransport::Send KafkaTransport::send(const std::string& payload) {
  in_flight_++;
  const rd_kafka_resp_err_t err = rd_kafka_producev(
      producer_, RD_KAFKA_V_RKT(topic_), RD_KAFKA_V_MSGFLAGS(RD_KAFKA_MSG_F_COPY),
      RD_KAFKA_V_KEY(options_.key.empty() ? nullptr : options_.key.data(), options_.key.size()),
      RD_KAFKA_V_VALUE(const_cast<char*>(payload.data()), payload.size()), RD_KAFKA_V_END);
  if (err == RD_KAFKA_RESP_ERR_NO_ERROR) return Send::Sent;
  in_flight_--;
  switch (err) {
    case RD_KAFKA_RESP_ERR__QUEUE_FULL:
      return Send::Busy;
    case RD_KAFKA_RESP_ERR_MSG_SIZE_TOO_LARGE:
      counters_->refused++;
      return Send::Refused;
    case RD_KAFKA_RESP_ERR__FATAL: {
      char text[512];
      rd_kafka_fatal_error(producer_, text, sizeof text);
      setFatal(std::string("Kafka producer failed: ") + text);
      counters_->lost++;
      return Send::Sent;
    }
    default:
      log_(GST_LEVEL_WARNING, std::string("Kafka produce failed: ") + rd_kafka_err2str(err));
      counters_->lost++;
      return Send::Sent;
  }
}

void KafkaTransport::serve() {
  while (producer_ && rd_kafka_poll(producer_, 0) > 0) {
  }
}

void KafkaTransport::service(std::chrono::milliseconds timeout) {
  waitReadable(wakeFd(), timeout);
  serve();
}

void KafkaTransport::abandon() {
  if (!producer_) return;
  // Whatever librdkafka still holds gets a delivery report with a purge error: counted lost.
  rd_kafka_purge(producer_, RD_KAFKA_PURGE_F_QUEUE | RD_KAFKA_PURGE_F_INFLIGHT);
  rd_kafka_flush(producer_, 1000);
  serve();
  if (topic_) rd_kafka_topic_destroy(topic_);
  topic_ = nullptr;
  rd_kafka_destroy(producer_);
  producer_ = nullptr;
  connected_ = false;
}

}  // namespace jointflow::gst
