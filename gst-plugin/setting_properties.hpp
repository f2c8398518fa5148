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

/// The row of a property id, or nullptr when the id is not one of the rows.
template <typename Settings>
const SettingSpec<Settings>* settingRow(const std::vector<SettingSpec<Settings>>& rows,
                                        guint prop_id) {
  return prop_id >= 1 && prop_id <= rows.size() ? &rows[prop_id - 1] : nullptr;
}

}  // namespace jointflow::gst
