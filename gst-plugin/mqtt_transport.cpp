#include "mqtt_transport.hpp"

#include <mosquitto.h>
#include <pthread.h>

#include <cerrno>
#include <cstring>
#include <mutex>
#include <utility>

#include "file_transport.hpp"  // waitReadable

namespace jointflow::gst {
namespace {

constexpr int kKeepAliveSeconds = 30;

// libmosquitto's loop thread runs the callbacks below; a forced stop (destroyClient) cancels
// that thread, which must not happen inside them (a lock of ours or of GLib's logging would
// stay held).
class CancelGuard {
 public:
  CancelGuard() { pthread_setcancelstate(PTHREAD_CANCEL_DISABLE, &previous_); }
  ~CancelGuard() { pthread_setcancelstate(previous_, nullptr); }
  CancelGuard(const CancelGuard&) = delete;
  CancelGuard& operator=(const CancelGuard&) = delete;

 private:
  int previous_ = PTHREAD_CANCEL_ENABLE;
};

void initLibrary() {
  static std::once_flag once;
  std::call_once(once, [] { mosquitto_lib_init(); });
}

std::string reason(int rc) {
  if (rc == MOSQ_ERR_ERRNO) return g_strerror(errno);
  return mosquitto_strerror(rc);
}

}  // namespace

MqttTransport::MqttTransport(BrokerEndpoint endpoint, std::string topic, std::string client_id,
                             MqttSecurity security, std::shared_ptr<PublishCounters> counters,
                             PublishLog log)
    : endpoint_(std::move(endpoint)),
      topic_(std::move(topic)),
      client_id_(std::move(client_id)),
      security_(std::move(security)),
      counters_(std::move(counters)),
      log_(std::move(log)) {
  initLibrary();
}

MqttTransport::~MqttTransport() {
  abandon();
}

std::string MqttTransport::topicError(const std::string& topic) {
  initLibrary();
  if (topic.empty()) return "the topic is empty";
  switch (mosquitto_pub_topic_check2(topic.c_str(), topic.size())) {
    case MOSQ_ERR_SUCCESS:
      return "";
    case MOSQ_ERR_INVAL:
      return "\"" + topic + "\" has a wildcard ('+' or '#'), or is too long";
    case MOSQ_ERR_MALFORMED_UTF8:
      return "\"" + topic + "\" is not valid UTF-8";
    default:
      return "\"" + topic + "\" is not an MQTT topic to publish to";
  }
}

mosquitto* MqttTransport::newClient(std::string* error) {
  mosquitto* m = mosquitto_new(client_id_.c_str(), true, this);
  if (!m) {
    *error = std::string("could not create the MQTT client: ") + g_strerror(errno);
    return nullptr;
  }
  mosquitto_int_option(m, MOSQ_OPT_PROTOCOL_VERSION, MQTT_PROTOCOL_V311);
  // libmosquitto would queue messages beyond its in-flight window without bound; send() never
  // goes past it, so the window is also the most that a lost connection can take with it.
  mosquitto_int_option(m, MOSQ_OPT_SEND_MAXIMUM, kMaxInFlight);
  // A lost connection is handled by the publishing thread (backoff, a fresh client), which
  // destroys this client at once. The library's loop thread would reconnect by itself after the
  // reconnect delay, and mosquitto_loop_stop() cannot interrupt that delay when the stop comes
  // just as the thread goes to sleep (libmosquitto 2.0 drains the wake-up byte on entering the
  // sleep: eclipse-mosquitto/mosquitto#1555); with a delay of an hour that hung the stop, and the
  // element with it, on a refused connection. One second bounds that wait.
  mosquitto_reconnect_delay_set(m, 1, 1, false);
  mosquitto_connect_callback_set(m, &MqttTransport::onConnect);
  mosquitto_disconnect_callback_set(m, &MqttTransport::onDisconnect);
  mosquitto_publish_callback_set(m, &MqttTransport::onPublish);
  mosquitto_log_callback_set(m, &MqttTransport::onLog);
  int rc = MOSQ_ERR_SUCCESS;
  if (!security_.username.empty() &&
      (rc = mosquitto_username_pw_set(
           m, security_.username.c_str(),
           security_.password.empty() ? nullptr : security_.password.c_str())) !=
          MOSQ_ERR_SUCCESS) {
    *error = "config-file [mqtt] username: " + reason(rc);
  } else if (security_.tls()) {
    auto opt = [](const std::string& s) { return s.empty() ? nullptr : s.c_str(); };
    rc = mosquitto_tls_set(m, opt(security_.ca_file), opt(security_.ca_path),
                           opt(security_.cert_file), opt(security_.key_file), nullptr);
    if (rc != MOSQ_ERR_SUCCESS) {
      *error = "config-file [mqtt] TLS files (ca-file \"" + security_.ca_file + "\", cert-file \"" +
               security_.cert_file + "\", key-file \"" + security_.key_file +
               "\"): " + (rc == MOSQ_ERR_INVAL ? "a file cannot be read" : reason(rc));
    } else if ((rc = mosquitto_tls_insecure_set(m, security_.tls_insecure)) != MOSQ_ERR_SUCCESS) {
      *error = "config-file [mqtt] tls-insecure: " + reason(rc);
    }
  }
  if (rc != MOSQ_ERR_SUCCESS) {
    mosquitto_destroy(m);
    return nullptr;
  }
  return m;
}

std::string MqttTransport::prepare() {
  std::string error = topicError(topic_);
  if (!error.empty()) return "topic: " + error;
  // The client is made once here so that a bad TLS file or credential fails the start.
  client_ = newClient(&error);
  return client_ ? "" : error;
}

void MqttTransport::destroyClient(bool connecting) {
  if (!client_) return;
  if (loop_running_) {
    // disconnect() makes libmosquitto's loop end instead of reconnecting; loop_stop joins it.
    // A client whose connection attempt failed is stopped by force (the loop thread cancelled):
    // its loop can stay in its socket wait with the wake-up byte already drained, or wait on a
    // broker that accepted the TCP connection and never answers, and a graceful stop then
    // waited for ever (seen in the sanitizer run of publish-mqtt-faults). Our callbacks cannot
    // be cancelled half-way (CancelGuard), and nothing of that attempt is in flight.
    mosquitto_disconnect(client_);
    mosquitto_loop_stop(client_, connecting);
    loop_running_ = false;
  }
  mosquitto_destroy(client_);
  client_ = nullptr;
  connected_ = false;
  const int lost = in_flight_.exchange(0);
  if (lost > 0) counters_->lost += static_cast<std::uint64_t>(lost);
}

void MqttTransport::abandon() {
  destroyClient();
}

std::string MqttTransport::connect(std::chrono::milliseconds timeout) {
  std::string error;
  if (client_ && loop_running_) destroyClient();  // a client that was connected once
  if (!client_ && !(client_ = newClient(&error))) return error;
  // From here until connected, a failure stops the attempt's loop thread by force.
  {
    std::lock_guard<std::mutex> lock(mutex_);
    connack_ = -1;
    disconnect_rc_ = 0;
  }
  int rc = mosquitto_loop_start(client_);
  if (rc != MOSQ_ERR_SUCCESS) return "could not start the MQTT network thread: " + reason(rc);
  loop_running_ = true;
  rc = mosquitto_connect_async(client_, endpoint_.host.c_str(), endpoint_.port, kKeepAliveSeconds);
  std::string where = endpoint_.host + ":" + std::to_string(endpoint_.port);
  if (rc != MOSQ_ERR_SUCCESS) {
    error = where + ": " + reason(rc);
    destroyClient(true);
    return error;
  }
  std::unique_lock<std::mutex> lock(mutex_);
  const bool answered =
      cv_.wait_for(lock, timeout, [&] { return connack_ >= 0 || disconnect_rc_ != 0; });
  const int connack = connack_;
  const int disconnect_rc = disconnect_rc_;
  lock.unlock();
  if (answered && connack == 0 && disconnect_rc == 0) {
    connected_ = true;
    return "";
  }
  if (!answered)
    error =
        where + ": no answer within connect-timeout (" + std::to_string(timeout.count()) + " ms)";
  else if (connack > 0)
    error = where + ": " + mosquitto_connack_string(connack);
  else
    error = where + ": " +
            (disconnect_rc == MOSQ_ERR_ERRNO || disconnect_rc == MOSQ_ERR_CONN_LOST
                 ? std::string("connection refused or closed")
                 : reason(disconnect_rc));
  destroyClient(true);
  return error;
}

PublishTransport::Send MqttTransport::send(const std::string& payload) {
  if (!connected_) return Send::Disconnected;
  if (in_flight_ >= kMaxInFlight) return Send::Busy;
  in_flight_++;
  const int rc = mosquitto_publish(client_, nullptr, topic_.c_str(),
                                   static_cast<int>(payload.size()), payload.data(), 1, false);
  if (rc == MOSQ_ERR_SUCCESS) return Send::Sent;
  in_flight_--;
  if (rc == MOSQ_ERR_PAYLOAD_SIZE || rc == MOSQ_ERR_OVERSIZE_PACKET) {
    counters_->refused++;
    return Send::Refused;
  }
  log_(GST_LEVEL_WARNING, "publish failed: " + reason(rc));
  connected_ = false;
  return Send::Disconnected;
}

void MqttTransport::service(std::chrono::milliseconds timeout) {
  // libmosquitto's thread does the network and wakes this one on acknowledgements and on a lost
  // connection.
  waitReadable(wakeFd(), timeout);
}

void MqttTransport::onConnect(mosquitto*, void* data, int rc) {
  CancelGuard guard;
  auto* self = static_cast<MqttTransport*>(data);
  {
    std::lock_guard<std::mutex> lock(self->mutex_);
    self->connack_ = rc;
  }
  self->cv_.notify_all();
}

void MqttTransport::onDisconnect(mosquitto*, void* data, int rc) {
  CancelGuard guard;
  auto* self = static_cast<MqttTransport*>(data);
  {
    std::lock_guard<std::mutex> lock(self->mutex_);
    self->disconnect_rc_ = rc != 0 ? rc : MOSQ_ERR_CONN_LOST;
  }
  self->connected_ = false;
  self->cv_.notify_all();
  self->wake();
}

void MqttTransport::onPublish(mosquitto*, void* data, int) {
  CancelGuard guard;
  auto* self = static_cast<MqttTransport*>(data);
  // Only PUBACKs of this client's current connection arrive here: a new connection is a new
  // client, so no message is counted twice.
  if (self->in_flight_.fetch_sub(1) > 0)
    self->counters_->delivered++;
  else
    self->in_flight_++;
  self->wake();
}

void MqttTransport::onLog(mosquitto*, void* data, int level, const char* text) {
  CancelGuard guard;
  auto* self = static_cast<MqttTransport*>(data);
  self->log_(level & (MOSQ_LOG_ERR | MOSQ_LOG_WARNING) ? GST_LEVEL_INFO : GST_LEVEL_LOG,
             std::string("libmosquitto: ") + (text ? text : ""));
}

}  // namespace jointflow::gst
