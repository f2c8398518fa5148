// --publish (publish_output.hpp).
#include "publish_output.hpp"

#include "jointflow/error.hpp"
#include "publish/transports.hpp"

namespace jointflow::cli {

void addPublishOptions(CLI::App& app, PublishOptions& options) {
  app.add_option("--publish", options.target,
                 "Publish each frame's record to mqtt://host:port/topic, "
                 "kafka://host:port/topic or a file (jointflowmetapublish)");
  app.add_option("--source-id", options.source_id,
                 "The camera's name: \"source_id\" in every record (--output-json too) and the "
                 "Kafka message key");
  app.add_option("--publish-config", options.config_file,
                 "Key file with TLS and credentials for --publish (docs/gstreamer.md)");
}

GstElement* makePublisher(const PublishOptions& options) {
  if (options.target.empty()) return nullptr;
  std::string error;
  const auto target = jointflow::gst::parsePublishUri(options.target, &error);
  if (!target) throw Error("--publish: " + error);
  GstElement* e = gst_element_factory_make("jointflowmetapublish", "publish");
  if (!e) throw Error("the jointflowmetapublish element is missing from the plugin");
  gst_util_set_object_arg(G_OBJECT(e), "method", target->transport->name);
  g_object_set(e, "address", target->address.c_str(), nullptr);
  if (!target->topic.empty()) g_object_set(e, "topic", target->topic.c_str(), nullptr);
  if (!options.source_id.empty()) g_object_set(e, "source-id", options.source_id.c_str(), nullptr);
  if (!options.config_file.empty())
    g_object_set(e, "config-file", options.config_file.c_str(), nullptr);
  return e;
}

std::string publishSummary(GstElement* pipeline) {
  GstElement* e = gst_bin_get_by_name(GST_BIN(pipeline), "publish");
  if (!e) return "";
  guint64 published = 0, dropped = 0, refused = 0;
  g_object_get(e, "messages-published", &published, "messages-dropped", &dropped,
               "messages-refused", &refused, nullptr);
  gst_object_unref(e);
  return std::to_string(published) + " published, " + std::to_string(dropped) + " dropped, " +
         std::to_string(refused) + " refused";
}

}  // namespace jointflow::cli
