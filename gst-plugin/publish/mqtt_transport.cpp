#include "mqtt_transport.hpp"

#include <mosquitto.h>

#include <cerrno>
#include <cstring>
#include <mutex>
#include <utility>

#include "transports.hpp"

namespace jointflow::gst {
namespace {

constexpr int kKeepAliveSeconds = 30;
// The longest that one turn of the network loop waits for the socket. A publish or a disconnect
// wakes it at once (libmosquitto writes to its wake-up pipe), so this bounds only how long
// destroyClient() can wait for the loop to see its stop flag.
constexpr int kLoopWaitMs = 100;

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

std::unique_ptr<PublishTransport> makeMqttTransport(const TransportRequest& request) {
  return std::make_unique<MqttTransport>(request.endpoints.front(), request.topic,
                                         request.client_id, request.config.mqtt, request.counters,
                                         request.log);
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
  // The network loop runs on a thread of ours (runLoop), not on mosquitto_loop_start()'s: the
  // library then takes its locks for calls from the publishing thread.
  mosquitto_threaded_set(m, true);
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

void MqttTransport::destroyClient() {
  if (!client_) return;
  if (loop_thread_.joinable()) {
    // The DISCONNECT wakes the loop, which sends it and ends the connection; the loop ends at its
    // next turn (at most kLoopWaitMs) whatever the broker does.
    mosquitto_disconnect(client_);
    stop_loop_ = true;
    loop_thread_.join();
    stop_loop_ = false;
  }
  mosquitto_destroy(client_);
  client_ = nullptr;
  connected_ = false;
  const int lost = in_flight_.exchange(0);
  if (lost > 0) counters_->lost += static_cast<std::uint64_t>(lost);
}

void MqttTransport::runLoop() {
  // Our own loop instead of mosquitto_loop_start(), whose thread can only be stopped gracefully
  // or by force. A graceful stop could wait for ever: the thread ends only when it sees the
  // disconnect, and it can miss the wake-up while going to sleep before its own reconnect
  // (eclipse-mosquitto/mosquitto#1555) or wait on a broker that accepted the TCP connection and
  // never answers. A forced stop cancels the thread wherever it is: inside that reconnect, it
  // leaked the address that getaddrinfo() had just allocated (LeakSanitizer, 64 bytes, in the
  // sanitizer run of publish-mqtt-faults). This loop never reconnects (the publishing thread
  // makes a fresh client, see the header) and checks its stop flag at every turn.
  while (!stop_loop_) {
    const int rc = mosquitto_loop(client_, kLoopWaitMs, 1);
    if (rc != MOSQ_ERR_SUCCESS) {
      // The connection is gone (or never came): on_disconnect has said so, except for a failed
      // TLS handshake and a failed select(), which only return their code.
      connectionEnded(rc);
      return;
    }
  }
}

void MqttTransport::connectionEnded(int rc) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (disconnect_rc_ == 0) disconnect_rc_ = rc != 0 ? rc : MOSQ_ERR_CONN_LOST;
    connected_ = false;
  }
  cv_.notify_all();
  wake();
}

void MqttTransport::abandon() {
  destroyClient();
}

void MqttTransport::interrupt() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    interrupted_ = true;
  }
  cv_.notify_all();
}

std::string MqttTransport::connect(std::chrono::milliseconds timeout) {
  std::string error;
  if (client_ && loop_thread_.joinable()) destroyClient();  // a client that was connected once
  if (!client_ && !(client_ = newClient(&error))) return error;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    connack_ = -1;
    disconnect_rc_ = 0;
    error_log_.clear();
  }
  const std::string why = attempt(timeout);
  if (why.empty()) return "";
  error = endpoint_.host + ":" + std::to_string(endpoint_.port) + ": " + why;
  {
    // libmosquitto says what went wrong only in its log: a failed TLS handshake (a certificate
    // not trusted, a wrong host name) otherwise reads "A TLS error occurred." or "connection
    // refused or closed". The handshake can fail on either thread: in mosquitto_connect_async()
    // when the broker answers at once, or in the network loop.
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_log_.empty()) error += " (libmosquitto: " + error_log_ + ")";
  }
  destroyClient();
  return error;
}

std::string MqttTransport::attempt(std::chrono::milliseconds timeout) {
  const int rc =
      mosquitto_connect_async(client_, endpoint_.host.c_str(), endpoint_.port, kKeepAliveSeconds);
  if (rc != MOSQ_ERR_SUCCESS) return reason(rc);
  loop_thread_ = std::thread(&MqttTransport::runLoop, this);
  std::unique_lock<std::mutex> lock(mutex_);
  if (!cv_.wait_for(lock, timeout,
                    [&] { return connack_ >= 0 || disconnect_rc_ != 0 || interrupted_; }))
    return "no answer within connect-timeout (" + std::to_string(timeout.count()) + " ms)";
  if (interrupted_) return "stopped during the connection attempt";
  if (connack_ > 0) return mosquitto_connack_string(connack_);
  if (disconnect_rc_ == MOSQ_ERR_ERRNO || disconnect_rc_ == MOSQ_ERR_CONN_LOST)
    return "connection refused or closed";
  if (disconnect_rc_ != 0) return reason(disconnect_rc_);
  // Under the lock, as connectionEnded() clears it: a connection that ends just after its
  // CONNACK is not taken for an open one.
  connected_ = true;
  return "";
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
  auto* self = static_cast<MqttTransport*>(data);
  {
    std::lock_guard<std::mutex> lock(self->mutex_);
    self->connack_ = rc;
  }
  self->cv_.notify_all();
}

void MqttTransport::onDisconnect(mosquitto*, void* data, int rc) {
  static_cast<MqttTransport*>(data)->connectionEnded(rc);
}

void MqttTransport::onPublish(mosquitto*, void* data, int) {
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
  auto* self = static_cast<MqttTransport*>(data);
  if (level & MOSQ_LOG_ERR && text) {
    std::lock_guard<std::mutex> lock(self->mutex_);
    self->error_log_ = text;
  }
  self->log_(level & (MOSQ_LOG_ERR | MOSQ_LOG_WARNING) ? GST_LEVEL_INFO : GST_LEVEL_LOG,
             std::string("libmosquitto: ") + (text ? text : ""));
}

}  // namespace jointflow::gst
