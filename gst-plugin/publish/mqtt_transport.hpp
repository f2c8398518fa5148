// jointflowmetapublish method=mqtt, on libmosquitto (the Eclipse Mosquitto client library).
// Messages go out at QoS 1, so that the broker acknowledges each one and "delivered" counts
// what the broker really took. A lost connection is not resumed: the client is destroyed, the
// messages it had in flight (at most kMaxInFlight) are counted lost rather than sent again, and
// a fresh client connects, so that a subscriber never sees a frame twice (at most once, in
// order). A network thread of this class runs libmosquitto's loop (runLoop); the rest is used
// from the publishing thread, and libmosquitto's callbacks run on the network thread.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "address.hpp"
#include "config.hpp"
#include "transport.hpp"

struct mosquitto;

namespace jointflow::gst {

class MqttTransport : public PublishTransport {
 public:
  static constexpr int kMaxInFlight = 32;

  MqttTransport(BrokerEndpoint endpoint, std::string topic, std::string client_id,
                MqttSecurity security, std::shared_ptr<PublishCounters> counters, PublishLog log);
  ~MqttTransport() override;

  std::string prepare() override;
  std::string connect(std::chrono::milliseconds timeout) override;
  bool connected() const override { return connected_; }
  Send send(const std::string& payload) override;
  void service(std::chrono::milliseconds timeout) override;
  std::size_t inFlight() const override { return static_cast<std::size_t>(in_flight_.load()); }
  void abandon() override;
  void interrupt() override;

  /// Why libmosquitto refuses @topic as a topic to publish to ("" when it takes it).
  static std::string topicError(const std::string& topic);

 private:
  mosquitto* newClient(std::string* error);
  /// One connection attempt of the fresh client_, with its network thread: "" when the broker
  /// accepted it, else why not.
  std::string attempt(std::chrono::milliseconds timeout);
  /// Stops the network thread (within one turn of its loop) and destroys the client.
  void destroyClient();
  /// The network thread: libmosquitto's loop until the connection ends or destroyClient().
  void runLoop();
  /// Records that the connection ended (or never came) with libmosquitto's code @rc.
  void connectionEnded(int rc);

  static void onConnect(mosquitto*, void* self, int rc);
  static void onDisconnect(mosquitto*, void* self, int rc);
  static void onPublish(mosquitto*, void* self, int mid);
  static void onLog(mosquitto*, void* self, int level, const char* text);

  BrokerEndpoint endpoint_;
  std::string topic_;
  std::string client_id_;
  MqttSecurity security_;
  std::shared_ptr<PublishCounters> counters_;
  PublishLog log_;

  mosquitto* client_ = nullptr;
  std::thread loop_thread_;  // runLoop(), from a connection attempt until destroyClient()
  std::atomic<bool> stop_loop_{false};
  std::atomic<bool> connected_{false};
  std::atomic<int> in_flight_{0};

  // Guards the members below, and connected_ where both threads set it.
  std::mutex mutex_;
  std::condition_variable cv_;
  int connack_ = -1;          // CONNACK's return code, -1 before it comes
  int disconnect_rc_ = 0;     // != 0 once the connection went away
  std::string error_log_;     // libmosquitto's last error line of this connection attempt
  bool interrupted_ = false;  // the element is stopping: no attempt waits for its answer
};

struct TransportRequest;
/// The transport table's factory (transports.cpp).
std::unique_ptr<PublishTransport> makeMqttTransport(const TransportRequest& request);

}  // namespace jointflow::gst
