#include "worker.hpp"

#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <random>
#include <utility>

namespace jointflow::gst {

PublishWorker::PublishWorker(std::unique_ptr<PublishTransport> transport,
                             std::shared_ptr<PublishCounters> counters,
                             PublishWorkerSettings settings, PublishLog log,
                             std::function<void(const std::string&)> on_fatal)
    : transport_(std::move(transport)),
      counters_(std::move(counters)),
      settings_(settings),
      log_(std::move(log)),
      on_fatal_(std::move(on_fatal)),
      backoff_(settings.first_retry, settings.max_reconnect_interval),
      queue_(settings.queue_capacity) {
  // The streaming thread wakes the publishing thread through an eventfd, which the transports
  // poll together with their sockets (one wait for both).
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  transport_->setWakeFd(wake_fd_);
  thread_ = std::thread([this] { run(); });
}

PublishWorker::~PublishWorker() {
  stop();
  if (wake_fd_ >= 0) close(wake_fd_);
}

PublishWorker::Offer PublishWorker::offer(std::string payload) {
  if (failed_) return Offer::Failed;
  if (payload.size() > settings_.max_message_size) {
    offer_refused_++;
    return Offer::Refused;
  }
  const bool dropped = queue_.push(std::move(payload));
  offered_++;
  signal();
  return dropped ? Offer::QueuedDroppedOldest : Offer::Queued;
}

std::uint64_t PublishWorker::settled() const {
  return counters_->delivered + counters_->lost + counters_->refused + queue_.dropped() +
         stop_dropped_;
}

std::uint64_t PublishWorker::refused() const {
  return counters_->refused + offer_refused_;
}

std::uint64_t PublishWorker::dropped() const {
  return queue_.dropped() + counters_->lost + stop_dropped_;
}

std::uint64_t PublishWorker::flush(std::chrono::milliseconds timeout) {
  const std::uint64_t target = offered_;
  std::unique_lock<std::mutex> lock(settle_mutex_);
  settle_cv_.wait_for(lock, timeout, [&] { return settled() >= target || failed_ || stopping_; });
  const std::uint64_t done = settled();
  return done >= target ? 0 : target - done;
}

void PublishWorker::stop() {
  if (!thread_.joinable()) return;
  stopping_ = true;
  transport_->interrupt();  // a connection attempt need not wait for connect-timeout
  signal();
  {
    std::lock_guard<std::mutex> lock(settle_mutex_);
    settle_cv_.notify_all();
  }
  thread_.join();
  // What never reached the broker is counted dropped, so that the element's totals add up.
  queue_.clear();
  if (pending_) {
    pending_.reset();
    stop_dropped_++;
  }
  transport_->abandon();
  reportDrops(true);
}

void PublishWorker::signal() {
  const std::uint64_t one = 1;
  if (wake_fd_ >= 0 && write(wake_fd_, &one, sizeof one) < 0) {
    // EAGAIN: the counter is already non-zero, so the thread will wake anyway.
  }
}

void PublishWorker::drainWake() {
  std::uint64_t value = 0;
  if (wake_fd_ >= 0 && read(wake_fd_, &value, sizeof value) < 0) {
    // EAGAIN: nothing was signalled.
  }
}

bool PublishWorker::waitOrStop(std::chrono::milliseconds duration) {
  // Waits in slices so that drops during an outage are still reported about once a second.
  const auto deadline = std::chrono::steady_clock::now() + duration;
  std::unique_lock<std::mutex> lock(settle_mutex_);
  while (!stopping_) {
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) break;
    const auto slice =
        std::min<std::chrono::steady_clock::duration>(deadline - now, settings_.warn_interval);
    settle_cv_.wait_for(lock, slice, [&] { return stopping_.load(); });
    lock.unlock();
    reportDrops(false);
    lock.lock();
  }
  return !stopping_;
}

void PublishWorker::reportDrops(bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_warn_ < settings_.warn_interval) return;
  const std::uint64_t dropped_now = dropped();
  const std::uint64_t refused_now = refused();
  if (dropped_now == warned_dropped_ && refused_now == warned_refused_) return;
  last_warn_ = now;
  std::string text;
  if (dropped_now != warned_dropped_)
    text += std::to_string(dropped_now - warned_dropped_) + " message(s) dropped (" +
            std::to_string(dropped_now) + " in all: queue full, broker unreachable or " +
            "connection lost with them in flight)";
  if (refused_now != warned_refused_)
    text += (text.empty() ? "" : "; ") + std::to_string(refused_now - warned_refused_) +
            " refused as larger than max-message-size (" + std::to_string(refused_now) + " in all)";
  warned_dropped_ = dropped_now;
  warned_refused_ = refused_now;
  log_(GST_LEVEL_WARNING, text);
}

void PublishWorker::sendQueued() {
  while (!stopping_) {
    if (!pending_) pending_ = queue_.pop();
    if (!pending_) return;
    const PublishTransport::Send result = transport_->send(*pending_);
    if (result == PublishTransport::Send::Sent || result == PublishTransport::Send::Refused) {
      pending_.reset();
      continue;
    }
    return;  // Busy or Disconnected: keep it for later, in order
  }
}

void PublishWorker::run() {
  std::mt19937 random(std::random_device{}());
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::uint32_t failures = 0;
  bool ever_connected = false;
  while (!stopping_) {
    if (!transport_->connected()) {
      if (connected_) {
        connected_ = false;
        log_(GST_LEVEL_WARNING, "connection lost; reconnecting (messages are queued meanwhile)");
      }
      const std::string why = transport_->connect(settings_.connect_timeout);
      if (stopping_) break;  // an attempt that stop() interrupted is no failure to report
      if (!why.empty()) {
        ++failures;
        if (!ever_connected && settings_.max_connect_attempts > 0 &&
            failures >= settings_.max_connect_attempts) {
          // The error goes on the bus before offer() can answer Failed: the element returns
          // GST_FLOW_ERROR from it, and the application must find the reason there by then.
          on_fatal_(
              why + " (" + std::to_string(failures) + " attempt" + (failures == 1 ? "" : "s") +
              ", max-connect-attempts=" + std::to_string(settings_.max_connect_attempts) + ")");
          failed_ = true;
          break;
        }
        const auto wait = backoff_.delay(failures, uniform(random));
        log_(failures == 1 || failures % 10 == 0 ? GST_LEVEL_WARNING : GST_LEVEL_INFO,
             "connection attempt " + std::to_string(failures) + " failed: " + why + "; next in " +
                 std::to_string(wait.count()) + " ms");
        waitOrStop(wait);
        continue;
      }
      log_(GST_LEVEL_INFO,
           failures == 0 && !ever_connected
               ? "connected"
               : "connected after " + std::to_string(failures) + " failed attempt(s)");
      failures = 0;
      ever_connected = true;
      connected_ = true;
    }
    sendQueued();
    const std::string fatal = transport_->fatalError();
    if (!fatal.empty()) {
      on_fatal_(fatal);  // on the bus first, as above
      failed_ = true;
      break;
    }
    // Nothing left to hand over (or the client is busy): wait for the network or a new message.
    // The slice bounds how late a drop warning or a keep-alive can be.
    transport_->service(settings_.warn_interval);
    drainWake();
    reportDrops(false);
    std::lock_guard<std::mutex> lock(settle_mutex_);
    settle_cv_.notify_all();
  }
  std::lock_guard<std::mutex> lock(settle_mutex_);
  settle_cv_.notify_all();
}

}  // namespace jointflow::gst
