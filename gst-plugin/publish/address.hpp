// Where jointflowmetapublish sends to, as users write it: the `address` property ("host:port",
// a comma-separated list of Kafka bootstrap servers) and the one-string form of jointflow-track's
// --publish (mqtt://host:port/topic, kafka://host:port/topic, file:///path or a plain path).
// Parsing is GLib's (GUri, GNetworkAddress); only Kafka's rule for topic names is written here,
// since librdkafka leaves it to the broker and a bad name would only fail at the first message.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace jointflow::gst {

/// The values of jointflowmetapublish's `method` property (a GEnum of the same numbers).
enum class PublishMethod { File = 0, Mqtt = 1, Kafka = 2 };

const char* publishMethodName(PublishMethod method);

/// One --publish target.
struct PublishTarget {
  PublishMethod method = PublishMethod::File;
  std::string address;  ///< "host:port" for the brokers, the path for a file ("-": stdout)
  std::string topic;    ///< empty for a file
};

/// Parses mqtt://host[:port]/topic, kafka://host[:port]/topic, file:///path, "-" or a plain file
/// path. The topic is the URI's path without its leading '/', percent-decoded (so an MQTT topic
/// may have levels: mqtt://h/poses/cam1 -> "poses/cam1"). On failure returns nothing and sets
/// @error to a sentence naming what is wrong.
std::optional<PublishTarget> parsePublishUri(const std::string& uri, std::string* error);

struct BrokerEndpoint {
  std::string host;  ///< without brackets for IPv6
  std::uint16_t port = 0;
};

/// The default port of a broker method: 1883 (MQTT), 9092 (Kafka).
std::uint16_t defaultPort(PublishMethod method);

/// Parses the `address` property of a broker method: "host[:port]" or "[v6addr]:port"; Kafka
/// also takes a comma-separated list. Fails (with @error set) on an empty address, a bad port, or
/// more than one endpoint for MQTT.
std::optional<std::vector<BrokerEndpoint>> parseBrokerAddress(PublishMethod method,
                                                              const std::string& address,
                                                              std::string* error);

/// librdkafka's bootstrap.servers for @endpoints ("h1:p1,[v6]:p2").
std::string bootstrapServers(const std::vector<BrokerEndpoint>& endpoints);

/// Why Kafka would refuse @topic as a topic name ("" when it is valid): 1 to 249 characters of
/// [a-zA-Z0-9._-], and neither "." nor "..".
std::string kafkaTopicError(const std::string& topic);

}  // namespace jointflow::gst
