// --metrics-port's HTTP endpoint on libmicrohttpd (metrics_server.hpp).
#include "metrics_server.hpp"

#include <arpa/inet.h>
#include <microhttpd.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "jointflow/error.hpp"

namespace jointflow::cli {
namespace {

MHD_Result answer(MHD_Connection* connection, unsigned status, const std::string& body,
                  const char* type) {
  MHD_Response* response = MHD_create_response_from_buffer(
      body.size(), const_cast<char*>(body.data()), MHD_RESPMEM_MUST_COPY);
  MHD_add_response_header(response, MHD_HTTP_HEADER_CONTENT_TYPE, type);
  const MHD_Result ret = MHD_queue_response(connection, status, response);
  MHD_destroy_response(response);
  return ret;
}

MHD_Result onRequest(void* cls, MHD_Connection* connection, const char* url, const char* method,
                     const char*, const char*, size_t*, void**) {
  const auto* server = static_cast<const MetricsServer*>(cls);
  if (std::strcmp(method, MHD_HTTP_METHOD_GET) != 0 &&
      std::strcmp(method, MHD_HTTP_METHOD_HEAD) != 0)
    return answer(connection, MHD_HTTP_METHOD_NOT_ALLOWED, "GET /metrics\n", "text/plain");
  if (std::strcmp(url, "/metrics") != 0)
    return answer(connection, MHD_HTTP_NOT_FOUND, "not found: the metrics are at /metrics\n",
                  "text/plain");
  return answer(connection, MHD_HTTP_OK, server->render(),
                "text/plain; version=0.0.4; charset=utf-8");
}

}  // namespace

MetricsServer::MetricsServer(const std::string& address, int port,
                             std::function<std::string()> render)
    : render_(std::move(render)) {
  const std::string where = address + ":" + std::to_string(port);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  if (port < 1 || port > 65535 || inet_pton(AF_INET, address.c_str(), &addr.sin_addr) != 1)
    throw Error("--metrics-port/--metrics-address: " + where +
                " is not an IPv4 address and a port in 1-65535");
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw Error(std::string("--metrics-port: no socket: ") + std::strerror(errno));
  // A restarted service gets its port back at once, past the old connections' TIME_WAIT.
  const int one = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || listen(fd, 16) != 0) {
    const std::string why = std::strerror(errno);
    close(fd);
    throw Error("--metrics-port " + std::to_string(port) + ": cannot listen on " + where + ": " +
                why);
  }
  // One thread of libmicrohttpd's own answers the requests; the daemon owns the socket from here.
  daemon_ = MHD_start_daemon(MHD_USE_INTERNAL_POLLING_THREAD, 0, nullptr, nullptr, &onRequest, this,
                             MHD_OPTION_LISTEN_SOCKET, fd, MHD_OPTION_CONNECTION_TIMEOUT, 10u,
                             MHD_OPTION_END);
  if (!daemon_) {
    close(fd);
    throw Error("--metrics-port " + std::to_string(port) + ": the HTTP server did not start on " +
                where);
  }
}

MetricsServer::~MetricsServer() {
  if (daemon_) MHD_stop_daemon(daemon_);
}

}  // namespace jointflow::cli
