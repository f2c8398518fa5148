// The tracker settings that users set by name, one row each: the name, a short and a long
// description, the kind and range of the value, and where the value goes in TrackerSettings.
//
// Every front end is made from these rows, so that a setting added here appears everywhere at
// once: the GStreamer element's properties (gst-plugin/track_properties.cpp), and through them the
// options of jointflow-track and the property table of docs/gstreamer.md; and the keyword
// arguments of the Python module. Defaults are those of TrackerSettings{}. A row's range is the
// setting's only range: front ends check a value against it (checkSettingValue), and the core
// checks a whole struct by walking the rows (checkSettings); only the checks across settings are
// written by hand (validateTrackerSettings, validateSpatialOptions).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "jointflow/setting_enums.hpp"
#include "jointflow/tracker.hpp"

namespace jointflow {

/// A setting's value on its way between a settings struct and a front end. Enumerations travel as
/// the int of their value; their names are in SettingSpec::enumeration.
using SettingValue = std::variant<bool, int, unsigned, float, std::string>;

enum class SettingKind { kBool, kInt, kUInt, kFloat, kString, kEnum };

/// The values of an enumeration without its C++ type, for front ends.
struct EnumView {
  const char* what;  ///< "similarity", ...: names the enumeration in messages
  struct Value {
    int value;
    const char* nick;
    const char* description;
  };
  std::vector<Value> values;
};

template <typename E>
const EnumView& enumView();  // defined below for the enums of setting_enums.hpp

/// What a front end needs to know of a setting, whatever struct holds it.
struct SettingInfo {
  const char* name;   ///< "tau-delta": property name; Python uses "tau_delta"
  const char* nick;   ///< "Tau delta"
  const char* blurb;  ///< what it does, with its unit
  SettingKind kind = SettingKind::kInt;
  double min = 0, max = 0;                ///< kInt, kUInt, kFloat: the accepted range
  const EnumView* enumeration = nullptr;  ///< kEnum: its values
  bool live = false;  ///< may change while frames flow; otherwise read when processing starts
};

/// Throws jointflow::Error naming the setting when `value` is not of the setting's kind or outside
/// its range (the checks a GParamSpec makes, for front ends without one).
void checkSettingValue(const SettingInfo& info, const SettingValue& value);

/// The value (as SettingValue carries it) of an enumeration row's name; throws jointflow::Error
/// naming the setting and its names ("reid: unknown appearance model 'x', expected off, ...").
int parseSettingEnum(const SettingInfo& info, std::string_view nick);

/// "2.5", "true", "max:640", "oks": a value as users write it.
std::string settingValueText(const SettingInfo& info, const SettingValue& value);

template <typename Settings>
struct SettingSpec : SettingInfo {
  std::function<SettingValue(const Settings&)> get;
  /// Stores a value of the row's kind; throws jointflow::Error for text it cannot parse
  /// (input-size, scales). Range checks are the front end's (checkSettingValue).
  std::function<void(Settings&, const SettingValue&)> set;
};

/// A row whose value is a member of Settings, reached through the member pointers of `path`
/// (`&TrackerSettings::spatial, &SpatialOptions::person_threshold`). The value's C++ type gives
/// the kind (an enum of setting_enums.hpp: kEnum with its values); info.kind is overwritten.
template <typename Settings, typename... Path>
SettingSpec<Settings> memberSetting(SettingInfo info, Path... path);

/// A row with its own accessors (a value that is parsed, or that sets several members).
template <typename Settings>
SettingSpec<Settings> customSetting(SettingInfo info,
                                    std::function<SettingValue(const Settings&)> get,
                                    std::function<void(Settings&, const SettingValue&)> set) {
  SettingSpec<Settings> r;
  static_cast<SettingInfo&>(r) = info;
  r.get = std::move(get);
  r.set = std::move(set);
  return r;
}

/// Checks every row's value in @settings: a number within the row's range (NaN is outside every
/// range), an enumeration one of its names, a text that the row parses (scales, input-size,
/// joint-thresholds: the parser is the range). Throws jointflow::Error naming the first setting
/// at fault and what it accepts.
template <typename Settings>
void checkSettings(const std::vector<SettingSpec<Settings>>& rows, const Settings& settings) {
  Settings parsed = settings;  // where the text rows parse their own text back into
  for (const SettingSpec<Settings>& row : rows) {
    const SettingValue value = row.get(settings);
    checkSettingValue(row, value);
    if (row.kind == SettingKind::kString) row.set(parsed, value);
  }
}

/// The rows for TrackerSettings, in the order front ends list them.
const std::vector<SettingSpec<TrackerSettings>>& trackerSettingsSchema();

/// The rows of an inner settings struct as rows of an outer one that holds it in `member`.
template <typename Outer, typename Inner>
std::vector<SettingSpec<Outer>> nestSettings(const std::vector<SettingSpec<Inner>>& rows,
                                             Inner Outer::*member) {
  std::vector<SettingSpec<Outer>> out;
  for (const SettingSpec<Inner>& r : rows) {
    out.push_back(customSetting<Outer>(
        r, [get = r.get, member](const Outer& s) { return get(s.*member); },
        [set = r.set, member](Outer& s, const SettingValue& v) { set(s.*member, v); }));
  }
  return out;
}

// --- Implementation details of the templates above ----------------------------------------------

template <typename Settings, typename... Path>
SettingSpec<Settings> memberSetting(SettingInfo info, Path... path) {
  using T = std::decay_t<decltype((std::declval<Settings&>().*....*path))>;
  if constexpr (std::is_enum_v<T>) {
    info.kind = SettingKind::kEnum;
    info.enumeration = &enumView<T>();
  } else if constexpr (std::is_same_v<T, bool>) {
    info.kind = SettingKind::kBool;
  } else if constexpr (std::is_same_v<T, int>) {
    info.kind = SettingKind::kInt;
  } else if constexpr (std::is_same_v<T, unsigned>) {
    info.kind = SettingKind::kUInt;
  } else if constexpr (std::is_same_v<T, float>) {
    info.kind = SettingKind::kFloat;
  } else {
    static_assert(std::is_same_v<T, std::string>,
                  "a setting is bool, int, unsigned, float, "
                  "std::string or an enum of setting_enums.hpp");
    info.kind = SettingKind::kString;
  }
  return customSetting<Settings>(
      info,
      [path...](const Settings& s) {
        const T& v = (s.*....*path);
        if constexpr (std::is_enum_v<T>)
          return SettingValue{static_cast<int>(v)};
        else
          return SettingValue{v};
      },
      [path...](Settings& s, const SettingValue& v) {
        T& field = (s.*....*path);
        if constexpr (std::is_enum_v<T>)
          field = static_cast<T>(std::get<int>(v));
        else
          field = std::get<T>(v);
      });
}

template <typename E>
const EnumView& enumView() {
  static const EnumView view = [] {
    EnumView v{EnumInfo<E>::kWhat, {}};
    for (const auto& e : EnumInfo<E>::kEntries)
      v.values.push_back({static_cast<int>(e.value), e.nick, e.description});
    return v;
  }();
  return view;
}

}  // namespace jointflow
