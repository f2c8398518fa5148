#include "queue.hpp"

#include <algorithm>
#include <utility>

namespace jointflow::gst {

PublishQueue::PublishQueue(std::size_t capacity) : capacity_(std::max<std::size_t>(capacity, 1)) {}

bool PublishQueue::push(std::string message) {
  std::string oldest;  // freed outside the lock
  bool dropped = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (messages_.size() >= capacity_) {
      oldest = std::move(messages_.front());
      messages_.pop_front();
      ++dropped_;
      dropped = true;
    }
    messages_.push_back(std::move(message));
  }
  return dropped;
}

std::optional<std::string> PublishQueue::pop() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (messages_.empty()) return std::nullopt;
  std::string message = std::move(messages_.front());
  messages_.pop_front();
  return message;
}

std::size_t PublishQueue::clear() {
  std::deque<std::string> old;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    old.swap(messages_);
    dropped_ += old.size();
  }
  return old.size();
}

std::size_t PublishQueue::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return messages_.size();
}

std::uint64_t PublishQueue::dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

}  // namespace jointflow::gst
