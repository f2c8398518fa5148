// jointflowmetapublish's publishing thread: takes the messages the streaming thread queues,
// connects (and reconnects) with exponential backoff, hands messages to the transport, and
// counts where each one ends. The streaming thread only ever takes a short lock to queue a
// message (offer()); the network is never waited on there, except by flush() at EOS, which is
// bounded in time.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "queue.hpp"
#include "reconnect_backoff.hpp"
#include "transport.hpp"

namespace jointflow::gst {

struct PublishWorkerSettings {
  /// Failed attempts at the first connection before giving up (0: never give up). Once a
  /// connection was made, a lost one is retried for as long as the element runs.
  std::uint32_t max_connect_attempts = 5;
  std::chrono::milliseconds first_retry{100};
  std::chrono::milliseconds max_reconnect_interval{30000};
  std::chrono::milliseconds connect_timeout{5000};
  std::size_t queue_capacity = 300;
  std::size_t max_message_size = 1000000;
  /// At most one warning per this interval about dropped or refused messages.
  std::chrono::milliseconds warn_interval{1000};
};

class PublishWorker {
 public:
  /// @on_fatal is called once, from the publishing thread, when the first connection cannot be
  /// made within max_connect_attempts or the transport reports a fatal error.
  PublishWorker(std::unique_ptr<PublishTransport> transport,
                std::shared_ptr<PublishCounters> counters, PublishWorkerSettings settings,
                PublishLog log, std::function<void(const std::string&)> on_fatal);
  /// Stops the thread (see stop()).
  ~PublishWorker();
  PublishWorker(const PublishWorker&) = delete;
  PublishWorker& operator=(const PublishWorker&) = delete;

  enum class Offer { Queued, QueuedDroppedOldest, Refused, Failed };
  /// Streaming thread: queues @payload (never blocks). Refused: larger than max_message_size
  /// (counted refused). Failed: the thread has stopped on a fatal error.
  Offer offer(std::string payload);
  /// Waits until every message offered so far is delivered, lost or dropped, or @timeout has
  /// passed; returns how many were still unsettled (0: all flushed).
  std::uint64_t flush(std::chrono::milliseconds timeout);
  /// Ends the thread at once; what is still queued or in flight is counted dropped.
  void stop();

  std::uint64_t delivered() const { return counters_->delivered; }
  /// Messages waiting in the queue for the connection.
  std::size_t queued() const { return queue_.size(); }
  /// Dropped from the queue (overflow, stop) plus lost by the transport.
  std::uint64_t dropped() const;
  /// Larger than max_message_size (refused by offer()) or than the client takes.
  std::uint64_t refused() const;
  std::size_t maxMessageSize() const { return settings_.max_message_size; }
  bool isConnected() const { return connected_; }
  bool failed() const { return failed_; }

 private:
  void run();
  void sendQueued();
  bool waitOrStop(std::chrono::milliseconds duration);
  void reportDrops(bool force);
  std::uint64_t settled() const;
  void signal();
  void drainWake();

  std::unique_ptr<PublishTransport> transport_;
  std::shared_ptr<PublishCounters> counters_;
  PublishWorkerSettings settings_;
  PublishLog log_;
  std::function<void(const std::string&)> on_fatal_;
  ReconnectBackoff backoff_;
  PublishQueue queue_;
  int wake_fd_ = -1;

  std::optional<std::string> pending_;  // taken from the queue, not yet taken by the transport
  std::atomic<std::uint64_t> offered_{0};
  std::atomic<std::uint64_t> stop_dropped_{0};
  std::atomic<std::uint64_t> offer_refused_{0};
  std::atomic<bool> stopping_{false};
  std::atomic<bool> connected_{false};
  std::atomic<bool> failed_{false};

  std::mutex settle_mutex_;
  std::condition_variable settle_cv_;

  std::chrono::steady_clock::time_point last_warn_{};
  std::uint64_t warned_dropped_ = 0;
  std::uint64_t warned_refused_ = 0;
  std::thread thread_;
};

}  // namespace jointflow::gst
