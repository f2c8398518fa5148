// jointflowmetapublish's config-file: TLS and credentials, kept out of the pipeline description
// (and so out of `ps` and shell histories). A GLib key file (INI):
//
//   [mqtt]
//   username=camera1
//   password=secret
//   ca-file=/etc/jointflow/ca.pem     # TLS is on when ca-file or ca-path is set
//   cert-file=/etc/jointflow/camera1.pem
//   key-file=/etc/jointflow/camera1.key
//   tls-insecure=false                # true: do not check the broker's host name
//
//   [kafka]
//   # any librdkafka configuration property, passed as it is (CONFIGURATION.md of librdkafka)
//   security.protocol=SASL_SSL
//   sasl.mechanisms=SCRAM-SHA-512
//   sasl.username=camera1
//   sasl.password=secret
//   ssl.ca.location=/etc/jointflow/ca.pem
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace jointflow::gst {

struct MqttSecurity {
  std::string username;
  std::string password;
  std::string ca_file;
  std::string ca_path;
  std::string cert_file;
  std::string key_file;
  bool tls_insecure = false;
  bool tls() const { return !ca_file.empty() || !ca_path.empty(); }
};

struct PublishConfig {
  MqttSecurity mqtt;
  /// librdkafka properties in file order.
  std::vector<std::pair<std::string, std::string>> kafka;
};

/// Reads @path. Fails, with @error naming the file and the line or key, on a missing or
/// malformed file, an unknown group, an unknown [mqtt] key or cert-file without key-file.
std::optional<PublishConfig> loadPublishConfig(const std::string& path, std::string* error);

}  // namespace jointflow::gst
