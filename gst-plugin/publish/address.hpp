// Where jointflowmetapublish sends to, as users write it: the `address` property ("host:port",
// a comma-separated list of Kafka bootstrap servers) and the one-string form of jointflow-track's
// --publish (<scheme>://host:port/topic for a broker, file:///path or a plain path), the schemes
// and default ports those of the transport table (transports.hpp). Parsing is GLib's (GUri,
// GNetworkAddress).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace jointflow::gst {

struct TransportRow;  // transports.hpp

/// One --publish target.
struct PublishTarget {
  const TransportRow* transport = nullptr;  ///< never null in a parsed target
  std::string address;  ///< "host:port" for the brokers, the path for a file ("-": stdout)
  std::string topic;    ///< empty for a file
};

/// Parses <scheme>://host[:port]/topic for a broker transport (mqtt://, kafka://), file:///path,
/// "-" or a plain file path. The topic is the URI's path without its leading '/', percent-decoded
/// (so an MQTT topic may have levels: mqtt://h/poses/cam1 -> "poses/cam1"). On failure returns
/// nothing and sets
/// @error to a sentence naming what is wrong.
std::optional<PublishTarget> parsePublishUri(const std::string& uri, std::string* error);

struct BrokerEndpoint {
  std::string host;  ///< without brackets for IPv6
  std::uint16_t port = 0;
};

/// Parses the `address` property of a broker transport: "host[:port]" (the row's default port)
/// or "[v6addr]:port", or a comma-separated list of them unless the row takes one broker. Fails
/// (with @error set) on an empty address, a bad port, or a list where one broker is taken.
std::optional<std::vector<BrokerEndpoint>> parseBrokerAddress(const TransportRow& transport,
                                                              const std::string& address,
                                                              std::string* error);

/// librdkafka's bootstrap.servers for @endpoints ("h1:p1,[v6]:p2").
std::string bootstrapServers(const std::vector<BrokerEndpoint>& endpoints);

}  // namespace jointflow::gst
