// The transports of jointflowmetapublish, one row each: the name users write, the URI scheme, the
// default port, the topic rule and the factory. The `method` property's GEnum (one value per row,
// its index the value), jointflow-track's --publish URIs (address.hpp) and the element's start
// are made from these rows, as the core's EnumInfo tables make its enums: a new transport is its
// file (a PublishTransport and its make function) and one row in transports.cpp.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "address.hpp"
#include "config.hpp"
#include "transport.hpp"

namespace jointflow::gst {

/// What the element hands a transport's factory when it starts.
struct TransportRequest {
  std::string address;  ///< the `address` property: a path, or broker host:port as users wrote it
  std::vector<BrokerEndpoint> endpoints;  ///< a broker transport's address, parsed
  std::string topic;
  std::string client_id;
  std::string source_id;  ///< the camera's name (Kafka's message key)
  PublishConfig config;   ///< the config file's TLS and credentials
  std::size_t queue_capacity = 300;
  std::chrono::milliseconds max_reconnect_interval{30000};
  std::shared_ptr<PublishCounters> counters;
  PublishLog log;
};

struct TransportRow {
  const char* name;         ///< the `method` property's value ("mqtt")
  const char* scheme;       ///< --publish's URI scheme: mqtt://host:port/topic
  const char* description;  ///< the value's line in gst-inspect: where to and what `address` is
  /// Port of a broker address written without one; 0: the address is a file path, not a broker.
  std::uint16_t default_port;
  /// The address names one broker, not a comma-separated list (Kafka's bootstrap servers).
  bool one_broker;
  /// Why the transport refuses @topic ("" when it takes it); null: it has no topic.
  std::string (*topic_error)(const std::string& topic);
  /// The transport of a request whose address parsed and whose topic was taken.
  std::unique_ptr<PublishTransport> (*make)(const TransportRequest& request);

  bool broker() const { return default_port != 0; }
};

/// Every transport, in the order of the `method` GEnum's values (a row's index is its value).
const std::vector<TransportRow>& publishTransports();

/// The row named @name, or of URI scheme @scheme; null when there is none.
const TransportRow* findTransport(std::string_view name);
const TransportRow* findTransportScheme(std::string_view scheme);

/// The row's transport for @request: a broker address is parsed into request.endpoints first and
/// the topic checked; null on failure, with @error a sentence naming the property at fault.
std::unique_ptr<PublishTransport> makeTransport(const TransportRow& row, TransportRequest request,
                                                std::string* error);

}  // namespace jointflow::gst
