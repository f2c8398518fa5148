// What jointflowmetapublish's publishing thread needs from a broker client (or a file), so that
// the thread's logic (connection attempts with backoff, the bounded queue, flushing, counting)
// is written once. Every call comes from that one thread: implementations need no locks of
// their own, except for the counters, which the streaming thread reads.
#pragma once

#include <gst/gst.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace jointflow::gst {

/// Where each message handed to a transport ends: delivered (acknowledged by the broker, or
/// written to the file), lost (handed over but not delivered: the connection broke with it in
/// flight, or the client gave up on it) or refused (too large for the client or broker).
struct PublishCounters {
  std::atomic<std::uint64_t> delivered{0};
  std::atomic<std::uint64_t> lost{0};
  std::atomic<std::uint64_t> refused{0};
};

/// Log lines of the publishing thread, at a GStreamer debug level.
using PublishLog = std::function<void(GstDebugLevel, const std::string&)>;

class PublishTransport {
 public:
  enum class Send {
    Sent,          ///< handed over; it will be counted delivered or lost
    Busy,          ///< the client's own bound is reached: try again after service()
    Refused,       ///< never sendable (too large); counted refused by the transport
    Disconnected,  ///< no connection: connected() is now false
  };

  virtual ~PublishTransport() = default;

  /// Checks and applies the settings that need no network (files, TLS setup, client options),
  /// at the element's start; "" when fine, else the reason (posted as an error naming it).
  virtual std::string prepare() = 0;

  /// One connection attempt of at most @timeout; "" when connected, else the reason.
  virtual std::string connect(std::chrono::milliseconds timeout) = 0;
  virtual bool connected() const = 0;
  /// Never blocks on the network.
  virtual Send send(const std::string& payload) = 0;
  /// Waits at most @timeout for the network or for the wake fd (see setWakeFd()) to become
  /// readable, then does the client's work (acknowledgements, keep-alives). Leaves the wake fd
  /// for the caller to drain.
  virtual void service(std::chrono::milliseconds timeout) = 0;
  /// Messages sent and neither delivered nor lost yet.
  virtual std::size_t inFlight() const = 0;
  /// Gives up on every message in flight (counted lost), before the transport is destroyed.
  virtual void abandon() = 0;
  /// Makes a connect() in progress end soon, as a failure: the element is stopping. Called once,
  /// from the thread that stops the publishing thread. The default does nothing: the attempt
  /// then ends on its own, within its timeout.
  virtual void interrupt() {}
  /// A failure that no retry can mend (an unknown Kafka topic, a fatal client error); "" when
  /// there is none. The thread stops and the element posts it as an error.
  virtual std::string fatalError() const { return ""; }

  /// The eventfd that wakes the publishing thread: written by the streaming thread for each new
  /// message, and by a client's own threads (acknowledgements, a lost connection).
  void setWakeFd(int fd) { wake_fd_ = fd; }

 protected:
  int wakeFd() const { return wake_fd_; }
  void wake() const;

 private:
  int wake_fd_ = -1;
};

/// Waits at most @timeout for @fd to become readable (the transports' idle wait).
void waitReadable(int fd, std::chrono::milliseconds timeout);

}  // namespace jointflow::gst
