// GObject properties made from settings rows (jointflow::SettingSpec, settings_schema.hpp): one
// row is one property, its id the row's index + 1. An element installs its rows once in
// class_init and forwards set_property/get_property here, so no property is written twice.
#pragma once

#include <gst/gst.h>

#include <string>
#include <vector>

#include "jointflow/settings_schema.hpp"

namespace jointflow::gst {

/// A GParamSpec for the row: its kind, range, blurb, `default_value`; READY-mutable, or
/// PLAYING-mutable when the row is live.
GParamSpec* makeParamSpec(const SettingInfo& info, const SettingValue& default_value);

/// The row's value held by a GValue of the row's GParamSpec type, and the reverse.
SettingValue fromGValue(const SettingInfo& info, const GValue* value);
void toGValue(const SettingInfo& info, const SettingValue& setting, GValue* value);

template <typename Settings>
void installSettingProperties(GObjectClass* klass, const std::vector<SettingSpec<Settings>>& rows) {
  const Settings defaults{};
  for (size_t i = 0; i < rows.size(); ++i)
    g_object_class_install_property(klass, static_cast<guint>(i + 1),
                                    makeParamSpec(rows[i], rows[i].get(defaults)));
}

/// Logs a value a row refused (text it cannot parse): a GStreamer warning on the element and a
/// GLib warning, which gst-launch shows and jointflow-track turns into an error.
void warnRefused(GstObject* element, const char* property, const std::string& why);

/// set_property for settings rows: stores the value under the object lock. A value the row
/// refuses leaves the previous one and is warned about.
template <typename Settings>
void setSettingProperty(GObject* object, Settings& settings,
                        const std::vector<SettingSpec<Settings>>& rows, guint prop_id,
                        const GValue* value, GParamSpec* pspec) {
  if (prop_id < 1 || prop_id > rows.size()) {
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, prop_id, pspec);
    return;
  }
  const SettingSpec<Settings>& row = rows[prop_id - 1];
  const SettingValue v = fromGValue(row, value);
  std::string refused;
  GST_OBJECT_LOCK(object);
  try {
    row.set(settings, v);  // a text that does not parse throws before anything is stored
  } catch (const std::exception& e) {
    refused = e.what();
  }
  GST_OBJECT_UNLOCK(object);
  if (!refused.empty()) warnRefused(GST_OBJECT(object), pspec->name, refused);
}

/// get_property for settings rows, under the object lock.
template <typename Settings>
void getSettingProperty(GObject* object, const Settings& settings,
                        const std::vector<SettingSpec<Settings>>& rows, guint prop_id,
                        GValue* value, GParamSpec* pspec) {
  if (prop_id < 1 || prop_id > rows.size()) {
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, prop_id, pspec);
    return;
  }
  const SettingSpec<Settings>& row = rows[prop_id - 1];
  GST_OBJECT_LOCK(object);
  const SettingValue v = row.get(settings);
  GST_OBJECT_UNLOCK(object);
  toGValue(row, v, value);
}

}  // namespace jointflow::gst
