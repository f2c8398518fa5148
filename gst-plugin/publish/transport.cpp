// The transports' shared parts (transport.hpp).
#include "transport.hpp"

#include <poll.h>
#include <unistd.h>

namespace jointflow::gst {

void waitReadable(int fd, std::chrono::milliseconds timeout) {
  pollfd p{fd, POLLIN, 0};
  poll(&p, 1, static_cast<int>(timeout.count()));
}

void PublishTransport::wake() const {
  const std::uint64_t one = 1;
  if (wake_fd_ >= 0 && write(wake_fd_, &one, sizeof one) < 0) {
    // EAGAIN: the counter is already non-zero, so the thread will wake anyway.
  }
}

}  // namespace jointflow::gst
