// The properties of the two elements that send the records out, jointflowjsonwriter and
// jointflowmetapublish, as settings rows (jointflow::SettingSpec, setting_properties.hpp), as
// jointflowtrack's are: one row is one property (id = index + 1), with its range and default.
#pragma once

#include <string>
#include <vector>

#include "jointflow/settings_schema.hpp"
#include "publish/worker.hpp"

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
  // The publishing thread's defaults (PublishWorkerSettings), in the properties' units: 300
  // messages are 10 s of 30 fps video; 1000000 bytes is librdkafka's and Kafka's message limit.
  unsigned max_connect_attempts = PublishWorkerSettings{}.max_connect_attempts;
  unsigned max_reconnect_interval_ms =
      static_cast<unsigned>(PublishWorkerSettings{}.max_reconnect_interval.count());
  unsigned connect_timeout_ms =
      static_cast<unsigned>(PublishWorkerSettings{}.connect_timeout.count());
  unsigned max_queue_size = static_cast<unsigned>(PublishWorkerSettings{}.queue_capacity);
  unsigned max_message_size = static_cast<unsigned>(PublishWorkerSettings{}.max_message_size);
  unsigned flush_timeout_ms = 5000;
};

/// The rows, in property-id order.
const std::vector<SettingSpec<JsonWriterSettings>>& jsonWriterProperties();
const std::vector<SettingSpec<PublishElementSettings>>& publishProperties();

/// The values of jointflowmetapublish's `method`: the transport table's rows (their index the
/// value, their name the nick).
const EnumView& publishMethodView();

}  // namespace jointflow::gst
