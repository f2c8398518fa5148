// `--set NAME=VALUE`: any row of the tracker settings schema (settings_schema.hpp) by its property
// name, for benchmarks that take the element's settings without an option of their own for each
// (tiles, backend, ...). Values are written as on jointflow-track's command line.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "jointflow/error.hpp"
#include "jointflow/settings_schema.hpp"

namespace jointflow::bench {

/// Applies "name=value" to `settings`; throws jointflow::Error naming the setting when the name is
/// unknown or the value not of its kind or out of its range.
inline void applySetting(TrackerSettings& settings, const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos) throw Error("--set " + assignment + ": expected NAME=VALUE");
  const std::string name = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  for (const auto& row : trackerSettingsSchema()) {
    if (name != row.name) continue;
    SettingValue value;
    try {
      switch (row.kind) {
        case SettingKind::kBool:
          if (text != "true" && text != "false") throw Error("expected true or false");
          value = text == "true";
          break;
        case SettingKind::kInt:
          value = std::stoi(text);
          break;
        case SettingKind::kUInt:
          value = static_cast<unsigned>(std::stoul(text));
          break;
        case SettingKind::kFloat:
          value = std::stof(text);
          break;
        case SettingKind::kString:
          value = text;
          break;
        case SettingKind::kEnum:
          value = parseSettingEnum(row, text);
          break;
      }
    } catch (const std::logic_error&) {  // std::stoi and friends
      throw Error(name + ": \"" + text + "\" is not a number");
    }
    checkSettingValue(row, value);
    row.set(settings, value);
    return;
  }
  throw Error("--set " + assignment + ": no setting is called " + name);
}

inline void applySettings(TrackerSettings& settings, const std::vector<std::string>& assignments) {
  for (const std::string& a : assignments) applySetting(settings, a);
}

/// Declares `--set NAME=VALUE` (repeatable) on a benchmark's command line; `more` ends its help.
inline void addSetOption(CLI::App& app, std::vector<std::string>& assignments,
                         const std::string& more = "") {
  app.add_option("--set", assignments,
                 "NAME=VALUE: any setting of jointflowtrack by its property name, applied before "
                 "the benchmark's own options (e.g. --set tiles=false --set backend=openvino)" +
                     more);
}

/// The assignments as typed on the command line (" --set a --set b"), for a document's command.
inline std::string setArguments(const std::vector<std::string>& assignments) {
  std::string out;
  for (const std::string& a : assignments) out += " --set " + a;
  return out;
}

}  // namespace jointflow::bench
