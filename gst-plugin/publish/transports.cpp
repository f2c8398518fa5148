// The table of jointflowmetapublish's transports (transports.hpp).
#include "transports.hpp"

#include "file_transport.hpp"
#include "kafka_transport.hpp"
#include "mqtt_transport.hpp"

namespace jointflow::gst {

const std::vector<TransportRow>& publishTransports() {
  // The first three keep the values the property had as a hand-written enum (file 0, mqtt 1,
  // kafka 2): new rows go at the end.
  static const std::vector<TransportRow> rows{
      {"file", "file", "JSON Lines to a file (address: path, - = stdout)", 0, true, nullptr,
       makeFileTransport},
      {"mqtt", "mqtt", "MQTT broker (address: host:port)", 1883, true, MqttTransport::topicError,
       makeMqttTransport},
      {"kafka", "kafka", "Kafka cluster (address: bootstrap host:port[,host:port...])", 9092, false,
       KafkaTransport::topicError, makeKafkaTransport},
  };
  return rows;
}

const TransportRow* findTransport(std::string_view name) {
  for (const TransportRow& row : publishTransports())
    if (name == row.name) return &row;
  return nullptr;
}

const TransportRow* findTransportScheme(std::string_view scheme) {
  for (const TransportRow& row : publishTransports())
    if (scheme == row.scheme) return &row;
  return nullptr;
}

std::unique_ptr<PublishTransport> makeTransport(const TransportRow& row, TransportRequest request,
                                                std::string* error) {
  if (row.broker()) {
    auto endpoints = parseBrokerAddress(row, request.address, error);
    if (!endpoints) {
      *error = "Invalid address \"" + request.address + "\" (property address): " + *error;
      return nullptr;
    }
    request.endpoints = std::move(*endpoints);
  }
  if (row.topic_error) {
    const std::string why = row.topic_error(request.topic);
    if (!why.empty()) {
      *error = "Invalid topic \"" + request.topic + "\" (property topic): " + why;
      return nullptr;
    }
  }
  return row.make(request);
}

}  // namespace jointflow::gst
