// GParamSpecs and GValues for settings rows (setting_properties.hpp).
#include "setting_properties.hpp"

#include "setting_enum_types.h"

namespace jointflow::gst {

GParamSpec* makeParamSpec(const SettingInfo& info, const SettingValue& d) {
  // The names and texts are string literals of the rows: static for the process' life.
  const auto flags = static_cast<GParamFlags>(
      G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
      (info.live ? GST_PARAM_MUTABLE_PLAYING | GST_PARAM_CONTROLLABLE : GST_PARAM_MUTABLE_READY));
  switch (info.kind) {
    case SettingKind::kBool:
      return g_param_spec_boolean(info.name, info.nick, info.blurb, std::get<bool>(d), flags);
    case SettingKind::kInt:
      return g_param_spec_int(info.name, info.nick, info.blurb, static_cast<gint>(info.min),
                              static_cast<gint>(info.max), std::get<int>(d), flags);
    case SettingKind::kUInt:
      return g_param_spec_uint(info.name, info.nick, info.blurb, static_cast<guint>(info.min),
                               static_cast<guint>(info.max), std::get<unsigned>(d), flags);
    case SettingKind::kFloat:
      return g_param_spec_float(info.name, info.nick, info.blurb, static_cast<gfloat>(info.min),
                                static_cast<gfloat>(info.max), std::get<float>(d), flags);
    case SettingKind::kString:
      return g_param_spec_string(info.name, info.nick, info.blurb, std::get<std::string>(d).c_str(),
                                 flags);
    case SettingKind::kEnum:
      break;
  }
  return g_param_spec_enum(info.name, info.nick, info.blurb, enumGType(*info.enumeration),
                           std::get<int>(d), flags);
}

SettingValue fromGValue(const SettingInfo& info, const GValue* value) {
  switch (info.kind) {
    case SettingKind::kBool:
      return static_cast<bool>(g_value_get_boolean(value));
    case SettingKind::kInt:
      return static_cast<int>(g_value_get_int(value));
    case SettingKind::kUInt:
      return static_cast<unsigned>(g_value_get_uint(value));
    case SettingKind::kFloat:
      return static_cast<float>(g_value_get_float(value));
    case SettingKind::kString: {
      const char* text = g_value_get_string(value);
      return std::string(text ? text : "");
    }
    case SettingKind::kEnum:
      break;
  }
  return static_cast<int>(g_value_get_enum(value));
}

void toGValue(const SettingInfo& info, const SettingValue& s, GValue* value) {
  switch (info.kind) {
    case SettingKind::kBool:
      return g_value_set_boolean(value, std::get<bool>(s));
    case SettingKind::kInt:
      return g_value_set_int(value, std::get<int>(s));
    case SettingKind::kUInt:
      return g_value_set_uint(value, std::get<unsigned>(s));
    case SettingKind::kFloat:
      return g_value_set_float(value, std::get<float>(s));
    case SettingKind::kString:
      return g_value_set_string(value, std::get<std::string>(s).c_str());
    case SettingKind::kEnum:
      break;
  }
  g_value_set_enum(value, std::get<int>(s));
}

void warnRefused(GstObject* element, const char* property, const std::string& why) {
  GstElementFactory* factory =
      GST_IS_ELEMENT(element) ? gst_element_get_factory(GST_ELEMENT(element)) : nullptr;
  const char* name =
      factory ? gst_plugin_feature_get_name(GST_PLUGIN_FEATURE(factory)) : "jointflow";
  GST_WARNING_OBJECT(element, "%s refused: %s", property, why.c_str());
  g_warning("%s: %s refused, keeping the previous value: %s", name, property, why.c_str());
}

}  // namespace jointflow::gst
