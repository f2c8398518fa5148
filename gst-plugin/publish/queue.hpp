// The bounded queue between the streaming thread and jointflowmetapublish's publishing thread.
// The streaming thread never waits on it: when it is full, the oldest message is dropped (and
// counted), so that what is delivered after a broker outage is the most recent past, and the
// memory held is bounded by the capacity whatever the broker does.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>

namespace jointflow::gst {

class PublishQueue {
 public:
  /// @capacity >= 1 messages.
  explicit PublishQueue(std::size_t capacity);

  /// Appends @message; when the queue is full, drops the oldest one first. Returns true when a
  /// message was dropped. Never blocks beyond the short critical section.
  bool push(std::string message);
  /// The oldest message, or nothing when the queue is empty.
  std::optional<std::string> pop();
  /// Drops every queued message (counted as dropped); returns how many.
  std::size_t clear();

  std::size_t size() const;
  std::size_t capacity() const { return capacity_; }
  /// Messages dropped by push() and clear() since construction.
  std::uint64_t dropped() const;

 private:
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::deque<std::string> messages_;
  std::uint64_t dropped_ = 0;
};

}  // namespace jointflow::gst
