// The HTTP endpoint of --metrics-port: GET /metrics answers with what @render returns, in
// Prometheus' text format, from libmicrohttpd's own thread. The listening socket is bound here,
// before the daemon starts, so that a port in use or an address that is not ours is said plainly
// (the daemon alone says only that it failed).
#pragma once

#include <functional>
#include <string>

struct MHD_Daemon;

namespace jointflow::cli {

class MetricsServer {
 public:
  /// Listens on @address:@port (IPv4 dotted quad, e.g. "0.0.0.0" for every interface).
  /// Throws jointflow::Error naming the address and port when it cannot.
  MetricsServer(const std::string& address, int port, std::function<std::string()> render);
  ~MetricsServer();
  MetricsServer(const MetricsServer&) = delete;
  MetricsServer& operator=(const MetricsServer&) = delete;

  /// The page, for the request handler (libmicrohttpd's thread).
  std::string render() const { return render_(); }

 private:
  std::function<std::string()> render_;
  MHD_Daemon* daemon_ = nullptr;
};

}  // namespace jointflow::cli
