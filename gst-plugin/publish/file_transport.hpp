// jointflowmetapublish method=file: the records as JSON Lines in a file (or stdout), written by
// the publishing thread, so that a slow disk does not hold up the video either.
#pragma once

#include <cstdio>
#include <memory>
#include <string>

#include "transport.hpp"

namespace jointflow::gst {

class FileTransport : public PublishTransport {
 public:
  /// @path: the file (replaced if it exists); "" or "-" is stdout.
  FileTransport(std::string path, std::shared_ptr<PublishCounters> counters);
  ~FileTransport() override;

  std::string prepare() override;
  std::string connect(std::chrono::milliseconds) override { return ""; }
  bool connected() const override { return true; }
  Send send(const std::string& payload) override;
  void service(std::chrono::milliseconds timeout) override;
  std::size_t inFlight() const override { return 0; }
  void abandon() override {}
  std::string fatalError() const override { return fatal_; }

 private:
  std::string path_;
  std::shared_ptr<PublishCounters> counters_;
  FILE* file_ = nullptr;
  bool owns_ = false;
  std::string fatal_;
};

struct TransportRequest;
/// The transport table's factory (transports.cpp): request.address is the path.
std::unique_ptr<PublishTransport> makeFileTransport(const TransportRequest& request);

}  // namespace jointflow::gst
