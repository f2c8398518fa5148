#include "address.hpp"

#include <gio/gio.h>

#include <cstring>
#include <memory>

#include "transports.hpp"

namespace jointflow::gst {
namespace {

template <typename T, void (*Free)(T*)>
struct GFree {
  void operator()(T* p) const { Free(p); }
};
using UriPtr = std::unique_ptr<GUri, GFree<GUri, g_uri_unref>>;

void freeGObject(GSocketConnectable* p) {
  g_object_unref(p);
}
using ConnectablePtr = std::unique_ptr<GSocketConnectable, GFree<GSocketConnectable, freeGObject>>;

std::string takeError(GError* err) {
  std::string text = err && err->message ? err->message : "unknown error";
  if (err) g_error_free(err);
  return text;
}

// "file://, mqtt:// or kafka://": the schemes of the transport table, for messages.
std::string schemeList() {
  std::string text;
  const auto& rows = publishTransports();
  for (size_t i = 0; i < rows.size(); ++i)
    text +=
        std::string(i == 0 ? "" : (i + 1 == rows.size() ? " or " : ", ")) + rows[i].scheme + "://";
  return text;
}

}  // namespace

std::optional<PublishTarget> parsePublishUri(const std::string& uri, std::string* error) {
  const std::string scheme_end = "://";
  if (uri.empty()) {
    *error = "the publish target is empty";
    return std::nullopt;
  }
  if (uri.find(scheme_end) == std::string::npos) {  // a plain path, or "-" for stdout
    return PublishTarget{findTransport("file"), uri, ""};
  }
  GError* err = nullptr;
  UriPtr parsed(g_uri_parse(uri.c_str(), G_URI_FLAGS_NONE, &err));
  if (!parsed) {
    *error = "\"" + uri + "\" is not a valid URI: " + takeError(err);
    return std::nullopt;
  }
  const std::string scheme = g_uri_get_scheme(parsed.get());
  const std::string path = g_uri_get_path(parsed.get()) ? g_uri_get_path(parsed.get()) : "";
  const TransportRow* transport = findTransportScheme(scheme);
  if (!transport) {
    *error = "\"" + uri + "\": unknown scheme \"" + scheme + "\" (use " + schemeList() + ")";
    return std::nullopt;
  }
  if (!transport->broker()) {
    if (path.empty()) {
      *error = "\"" + uri + "\" names no file";
      return std::nullopt;
    }
    return PublishTarget{transport, path, ""};
  }
  PublishTarget target;
  target.transport = transport;
  const char* host = g_uri_get_host(parsed.get());
  if (host == nullptr || *host == '\0') {
    *error = "\"" + uri + "\" names no broker host";
    return std::nullopt;
  }
  const int port = g_uri_get_port(parsed.get());
  const std::string h = std::strchr(host, ':') ? "[" + std::string(host) + "]" : host;
  target.address = h + ":" + std::to_string(port > 0 ? port : transport->default_port);
  target.topic = path.size() > 1 && path[0] == '/' ? path.substr(1) : "";
  if (target.topic.empty()) {
    *error = "\"" + uri + "\" names no topic (" + scheme + "://host:port/topic)";
    return std::nullopt;
  }
  return target;
}

std::optional<std::vector<BrokerEndpoint>> parseBrokerAddress(const TransportRow& transport,
                                                              const std::string& address,
                                                              std::string* error) {
  std::vector<BrokerEndpoint> endpoints;
  gchar** parts = g_strsplit(address.c_str(), ",", -1);
  for (gchar** part = parts; *part != nullptr; ++part) {
    g_strstrip(*part);
    if (**part == '\0') continue;
    GError* err = nullptr;
    ConnectablePtr connectable(g_network_address_parse(*part, transport.default_port, &err));
    if (!connectable) {
      *error = "\"" + std::string(*part) + "\" is not host[:port]: " + takeError(err);
      g_strfreev(parts);
      return std::nullopt;
    }
    auto* net = G_NETWORK_ADDRESS(connectable.get());
    const guint16 port = g_network_address_get_port(net);
    if (port == 0) {
      *error = "\"" + std::string(*part) + "\": port 0 cannot be connected to";
      g_strfreev(parts);
      return std::nullopt;
    }
    endpoints.push_back({g_network_address_get_hostname(net), port});
  }
  g_strfreev(parts);
  if (endpoints.empty()) {
    *error = "the address is empty (host:port)";
    return std::nullopt;
  }
  if (transport.one_broker && endpoints.size() > 1) {
    *error = std::string(transport.name) + " connects to one broker: \"" + address + "\" names " +
             std::to_string(endpoints.size());
    return std::nullopt;
  }
  return endpoints;
}

std::string bootstrapServers(const std::vector<BrokerEndpoint>& endpoints) {
  std::string out;
  for (const auto& e : endpoints) {
    if (!out.empty()) out += ",";
    out += (e.host.find(':') != std::string::npos ? "[" + e.host + "]" : e.host) + ":" +
           std::to_string(e.port);
  }
  return out;
}

}  // namespace jointflow::gst
