// The rows of jointflowjsonwriter's and jointflowmetapublish's properties (output_properties.hpp).
#include "output_properties.hpp"

#include <glib.h>

#include "publish/transports.hpp"

namespace jointflow::gst {
namespace {

SettingInfo text(const char* name, const char* nick, const char* blurb) {
  return {name, nick, blurb, SettingKind::kString, 0, 0, nullptr, false};
}

SettingInfo count(const char* name, const char* nick, const char* blurb, double min, double max) {
  return {name, nick, blurb, SettingKind::kUInt, min, max, nullptr, false};
}

std::vector<SettingSpec<JsonWriterSettings>> makeWriterRows() {
  using W = JsonWriterSettings;
  return {
      memberSetting<W>(text("location", "Location",
                            "File the JSON Lines are written to (replaced if it exists); "
                            "unset, empty or \"-\" writes to stdout"),
                       &W::location),
      memberSetting<W>(text("source-id", "Source id",
                            "Name of the camera, written into every record as \"source_id\" "
                            "(the field jointflowmetapublish sends too); unset writes none"),
                       &W::source_id),
  };
}

std::vector<SettingSpec<PublishElementSettings>> makePublishRows() {
  using P = PublishElementSettings;
  SettingInfo method =
      text("method", "Method", "Where the messages go: a file, an MQTT broker or Kafka");
  method.kind = SettingKind::kEnum;
  method.enumeration = &publishMethodView();
  return {
      customSetting<P>(
          method, [](const P& s) { return SettingValue{s.method}; },
          [](P& s, const SettingValue& v) { s.method = std::get<int>(v); }),
      memberSetting<P>(text("address", "Address",
                            "mqtt: host:port of the broker (default port 1883); kafka: bootstrap "
                            "servers host:port[,host:port...] (default port 9092); file: the path "
                            "(replaced if it exists; unset, empty or \"-\" is stdout)"),
                       &P::address),
      memberSetting<P>(
          text("topic", "Topic",
               "MQTT topic (levels with '/', no wildcards) or Kafka topic ([a-zA-Z0-9._-], at most "
               "249 characters); unused by method=file"),
          &P::topic),
      memberSetting<P>(text("client-id", "Client id",
                            "Client id given to the broker; unset: jointflow-<source-id or "
                            "host>-<pid>-<n>, unique per element"),
                       &P::client_id),
      memberSetting<P>(text("source-id", "Source id",
                            "Name of the camera: written into every message as \"source_id\" and "
                            "used as the Kafka message key (one camera, one partition, in order)"),
                       &P::source_id),
      memberSetting<P>(
          text("config-file", "Config file",
               "Key file with TLS and credentials: [mqtt] username, password, ca-file, ca-path, "
               "cert-file, key-file, tls-insecure; [kafka] any librdkafka property "
               "(security.protocol, sasl.*, ssl.*) (docs/gstreamer.md)"),
          &P::config_file),
      memberSetting<P>(count("max-connect-attempts", "Max connect attempts",
                             "Attempts at the first connection before the element posts an error "
                             "(0: try without end); a connection lost later is always retried",
                             0, G_MAXUINT),
                       &P::max_connect_attempts),
      memberSetting<P>(count("max-reconnect-interval", "Max reconnect interval",
                             "Longest wait between two connection attempts in ms: waits double "
                             "from 100 ms up to this (each drawn in [1/2, 1] of it, so cameras "
                             "spread)",
                             100, G_MAXUINT),
                       &P::max_reconnect_interval_ms),
      memberSetting<P>(count("connect-timeout", "Connect timeout",
                             "How long one connection attempt may take, in ms", 100, 600000),
                       &P::connect_timeout_ms),
      memberSetting<P>(count("max-queue-size", "Max queue size",
                             "Messages held while the broker does not take them; beyond, the "
                             "oldest are dropped and counted (Kafka: librdkafka holds as many "
                             "again)",
                             1, 1000000),
                       &P::max_queue_size),
      memberSetting<P>(count("max-message-size", "Max message size",
                             "Largest message in bytes; a larger one is not published (counted "
                             "refused, with a warning)",
                             64, G_MAXINT),
                       &P::max_message_size),
      memberSetting<P>(count("flush-timeout", "Flush timeout",
                             "At EOS, how long to wait in ms for the queued messages to be "
                             "delivered",
                             0, 600000),
                       &P::flush_timeout_ms),
  };
}

}  // namespace

const std::vector<SettingSpec<JsonWriterSettings>>& jsonWriterProperties() {
  static const std::vector<SettingSpec<JsonWriterSettings>> rows = makeWriterRows();
  return rows;
}

const std::vector<SettingSpec<PublishElementSettings>>& publishProperties() {
  static const std::vector<SettingSpec<PublishElementSettings>> rows = makePublishRows();
  return rows;
}

const EnumView& publishMethodView() {
  static const EnumView view = [] {
    EnumView v{"publish method", {}};
    const auto& rows = publishTransports();
    for (size_t i = 0; i < rows.size(); ++i)
      v.values.push_back({static_cast<int>(i), rows[i].name, rows[i].description});
    return v;
  }();
  return view;
}

}  // namespace jointflow::gst
