#include "config.hpp"

#include <glib.h>

#include <cstring>
#include <memory>

namespace jointflow::gst {
namespace {

struct KeyFileFree {
  void operator()(GKeyFile* k) const { g_key_file_unref(k); }
};

std::string takeString(gchar* s) {
  std::string out = s ? s : "";
  g_free(s);
  return out;
}

}  // namespace

std::optional<PublishConfig> loadPublishConfig(const std::string& path, std::string* error) {
  std::unique_ptr<GKeyFile, KeyFileFree> file(g_key_file_new());
  GError* err = nullptr;
  if (!g_key_file_load_from_file(file.get(), path.c_str(), G_KEY_FILE_NONE, &err)) {
    *error = "cannot read config file \"" + path + "\": " + err->message;
    g_error_free(err);
    return std::nullopt;
  }
  PublishConfig config;
  gsize n_groups = 0;
  gchar** groups = g_key_file_get_groups(file.get(), &n_groups);
  bool ok = true;
  for (gsize g = 0; ok && g < n_groups; ++g) {
    const std::string group = groups[g];
    if (group != "mqtt" && group != "kafka") {
      *error = "config file \"" + path + "\": unknown group [" + group + "] (use [mqtt], [kafka])";
      ok = false;
      break;
    }
    gsize n_keys = 0;
    gchar** keys = g_key_file_get_keys(file.get(), group.c_str(), &n_keys, nullptr);
    for (gsize k = 0; ok && k < n_keys; ++k) {
      const std::string key = keys[k];
      // Values are taken raw (no escapes, no list parsing): a password may hold any character
      // but a newline.
      const std::string value =
          takeString(g_key_file_get_value(file.get(), group.c_str(), key.c_str(), nullptr));
      if (group == "kafka") {
        config.kafka.emplace_back(key, value);
        continue;
      }
      MqttSecurity& m = config.mqtt;
      if (key == "username")
        m.username = value;
      else if (key == "password")
        m.password = value;
      else if (key == "ca-file")
        m.ca_file = value;
      else if (key == "ca-path")
        m.ca_path = value;
      else if (key == "cert-file")
        m.cert_file = value;
      else if (key == "key-file")
        m.key_file = value;
      else if (key == "tls-insecure") {
        GError* bool_err = nullptr;
        m.tls_insecure = g_key_file_get_boolean(file.get(), "mqtt", "tls-insecure", &bool_err);
        if (bool_err) {
          *error = "config file \"" + path + "\": [mqtt] tls-insecure must be true or false";
          g_error_free(bool_err);
          ok = false;
        }
      } else {
        *error = "config file \"" + path + "\": unknown key \"" + key +
                 "\" in [mqtt] (username, password, ca-file, ca-path, cert-file, key-file, "
                 "tls-insecure)";
        ok = false;
      }
    }
    g_strfreev(keys);
  }
  g_strfreev(groups);
  if (!ok) return std::nullopt;
  if (config.mqtt.cert_file.empty() != config.mqtt.key_file.empty()) {
    *error = "config file \"" + path + "\": [mqtt] cert-file and key-file go together";
    return std::nullopt;
  }
  if (!config.mqtt.cert_file.empty() && !config.mqtt.tls()) {
    *error = "config file \"" + path + "\": [mqtt] cert-file needs ca-file or ca-path (TLS)";
    return std::nullopt;
  }
  return config;
}

}  // namespace jointflow::gst
