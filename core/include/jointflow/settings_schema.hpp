// The tracker settings that users set by name, one row each: the name, a short and a long
// description, the kind and range of the value, and where the value goes in TrackerSettings.
//
// Every front end is made from these rows, so that a setting added here appears everywhere at
// once: the GStreamer element's properties (gst-plugin/track_properties.cpp), and through them the
// options of jointflow-track and the property table of docs/gstreamer.md; and the keyword
// arguments of the Python module. Defaults are those of TrackerSettings{}; validation of
// combinations stays with the core (Tracker, PoseAssociator), which names the setting at fault.
#pragma once

#include <functional>
#include <string>
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

/// "2.5", "true", "max:640", "oks": a value as users write it.
std::string settingValueText(const SettingInfo& info, const SettingValue& value);

template <typename Settings>
struct SettingSpec : SettingInfo {
  std::function<SettingValue(const Settings&)> get;
  /// Stores a value of the row's kind; throws jointflow::Error for text it cannot parse
  /// (input-size, scales). Range checks are the front end's (checkSettingValue).
  std::function<void(Settings&, const SettingValue&)> set;
};

/// The rows for TrackerSettings, in the order front ends list them.
const std::vector<SettingSpec<TrackerSettings>>& trackerSettingsSchema();

/// The rows of an inner settings struct as rows of an outer one that holds it in `member`.
template <typename Outer, typename Inner>
std::vector<SettingSpec<Outer>> nestSettings(const std::vector<SettingSpec<Inner>>& rows,
                                             Inner Outer::*member) {
  std::vector<SettingSpec<Outer>> out;
  for (const SettingSpec<Inner>& r : rows) {
    SettingSpec<Outer> o;
    static_cast<SettingInfo&>(o) = r;
    o.get = [get = r.get, member](const Outer& s) { return get(s.*member); };
    o.set = [set = r.set, member](Outer& s, const SettingValue& v) { set(s.*member, v); };
    out.push_back(std::move(o));
  }
  return out;
}

// --- Implementation details of the templates above ----------------------------------------------

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
