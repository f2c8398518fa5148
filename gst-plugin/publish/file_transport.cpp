#include "file_transport.hpp"

#include <glib.h>

#include <cerrno>
#include <utility>

#include "transports.hpp"

namespace jointflow::gst {

FileTransport::FileTransport(std::string path, std::shared_ptr<PublishCounters> counters)
    : path_(std::move(path)), counters_(std::move(counters)) {}

std::unique_ptr<PublishTransport> makeFileTransport(const TransportRequest& request) {
  return std::make_unique<FileTransport>(request.address, request.counters);
}

FileTransport::~FileTransport() {
  if (file_ && owns_) std::fclose(file_);
}

std::string FileTransport::prepare() {
  if (path_.empty() || path_ == "-") {
    file_ = stdout;
    return "";
  }
  file_ = std::fopen(path_.c_str(), "w");
  if (!file_) return "could not open \"" + path_ + "\" for writing: " + g_strerror(errno);
  owns_ = true;
  return "";
}

PublishTransport::Send FileTransport::send(const std::string& payload) {
  if (!fatal_.empty()) {
    counters_->lost++;
    return Send::Sent;
  }
  if (std::fwrite(payload.data(), 1, payload.size(), file_) != payload.size() ||
      std::fputc('\n', file_) == EOF || std::fflush(file_) != 0) {
    fatal_ = "could not write to \"" + (owns_ ? path_ : std::string("stdout")) +
             "\": " + g_strerror(errno);
    counters_->lost++;
    return Send::Sent;
  }
  counters_->delivered++;
  return Send::Sent;
}

void FileTransport::service(std::chrono::milliseconds timeout) {
  waitReadable(wakeFd(), timeout);
}

}  // namespace jointflow::gst
