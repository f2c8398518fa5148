// --publish: the poses of every frame to an MQTT broker, a Kafka topic or a file, through
// jointflowmetapublish (the record --output-json writes, one message per frame).
#pragma once

#include <gst/gst.h>

#include <string>
#include <utility>

#include <CLI/CLI.hpp>

namespace jointflow::cli {

struct PublishOptions {
  std::string target;       ///< mqtt://host:port/topic, kafka://host:port/topic, or a file
  std::string source_id;    ///< the camera's name: in every record, the Kafka key
  std::string config_file;  ///< TLS and credentials (jointflowmetapublish config-file)
};

void addPublishOptions(CLI::App& app, PublishOptions& options);

/// jointflowmetapublish for options.target (a floating reference), or nullptr without --publish.
/// Throws jointflow::Error naming --publish when the target cannot be parsed.
GstElement* makePublisher(const PublishOptions& options);

/// "N published, M dropped, K refused" of the pipeline's publisher after the run ("" without).
std::string publishSummary(GstElement* pipeline);

}  // namespace jointflow::cli
