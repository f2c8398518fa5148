// The properties of the two elements that send the records out, jointflowjsonwriter and
// jointflowmetapublish, as settings rows (jointflow::SettingSpec, setting_properties.hpp), as
// jointflowtrack's are: one row is one property (id = index + 1), with its range and default.
#pragma once

#include <string>
#include <vector>

#include "jointflow/settings_schema.hpp"

namespace jointflow::gst {

/// Everything jointflowjsonwriter's properties set; read at start.
struct JsonWriterSettings {
  std::string location;   ///< "" or "-": stdout
  std::string source_id;  ///< "": no "source_id" field
};

/// Everything jointflowmetapublish's settable properties set; read at start.
struct PublishElementSettings {
  int method = 0;  ///< an index into publishTransports(); 0 = a file
  std::string address;
  std::string topic;
  std::string client_id;  ///< "": made unique per element
  std::string source_id;
  std::string config_file;
  unsigned max_connect_attempts = 5;
  unsigned max_reconnect_interval_ms = 30000;
  unsigned connect_timeout_ms = 5000;
  unsigned max_queue_size = 300;        // 10 s of 30 fps video
  unsigned max_message_size = 1000000;  // librdkafka's and Kafka's default limit
  unsigned flush_timeout_ms = 5000;
};

/// The rows, in property-id order.
const std::vector<SettingSpec<JsonWriterSettings>>& jsonWriterProperties();
const std::vector<SettingSpec<PublishElementSettings>>& publishProperties();

/// The values of jointflowmetapublish's `method`: the transport table's rows (their index the
/// value, their name the nick).
const EnumView& publishMethodView();

}  // namespace jointflow::gst
