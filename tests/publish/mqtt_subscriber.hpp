// The tests' MQTT consumer, on libmosquitto: subscribes at QoS 1 with a persistent session
// (clean_session=false), so that it also gets what was published while it was reconnecting
// after a broker restart, and collects every payload in arrival order.
#pragma once

#include <mosquitto.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <vector>

namespace jointflow::test {

class MqttSubscriber {
 public:
  MqttSubscriber(const std::string& client_id, const std::string& topic, int port) : topic_(topic) {
    mosquitto_lib_init();
    client_ = mosquitto_new(client_id.c_str(), false, this);
    mosquitto_reconnect_delay_set(client_, 1, 1, false);
    mosquitto_connect_callback_set(client_, [](mosquitto* m, void* self, int rc) {
      auto* s = static_cast<MqttSubscriber*>(self);
      if (rc == 0) mosquitto_subscribe(m, nullptr, s->topic_.c_str(), 1);
    });
    mosquitto_subscribe_callback_set(client_, [](mosquitto*, void* self, int, int, const int*) {
      auto* s = static_cast<MqttSubscriber*>(self);
      std::lock_guard<std::mutex> lock(s->mutex_);
      s->subscriptions_++;
      s->cv_.notify_all();
    });
    mosquitto_message_callback_set(client_, [](mosquitto*, void* self, const mosquitto_message* m) {
      auto* s = static_cast<MqttSubscriber*>(self);
      std::lock_guard<std::mutex> lock(s->mutex_);
      s->messages_.emplace_back(static_cast<const char*>(m->payload), m->payloadlen);
      s->cv_.notify_all();
    });
    mosquitto_connect_async(client_, "127.0.0.1", port, 30);
    mosquitto_loop_start(client_);
  }
  ~MqttSubscriber() {
    mosquitto_disconnect(client_);
    mosquitto_loop_stop(client_, false);
    mosquitto_destroy(client_);
  }

  /// Waits (at most @timeout) for the @n-th SUBACK since construction.
  bool waitSubscribed(int n, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] { return subscriptions_ >= n; });
  }
  /// Waits (at most @timeout) until @n messages arrived; returns all received so far.
  std::vector<std::string> waitMessages(std::size_t n, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, timeout, [&] { return messages_.size() >= n; });
    return messages_;
  }

 private:
  std::string topic_;
  mosquitto* client_ = nullptr;
  std::mutex mutex_;
  std::condition_variable cv_;
  int subscriptions_ = 0;
  std::vector<std::string> messages_;
};

}  // namespace jointflow::test
