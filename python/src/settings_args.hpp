// The keyword arguments of jointflow.Tracker, made from the core's settings schema
// (trackerSettingsSchema()): one keyword per row, named as the row with '-' -> '_', typed by the
// row's kind, checked by checkSettingValue (the messages name the setting as the element and the
// command line do). No list of settings is kept here.
#pragma once

#include <string>

#include <pybind11/pybind11.h>

#include "jointflow/settings_schema.hpp"

namespace jointflow::python {

/// "tau_delta" for the row "tau-delta".
std::string pythonName(const SettingInfo& info);

/// TrackerSettings{} with the keywords applied. Raises TypeError for an unknown keyword (listing
/// the valid ones) or a value of the wrong type, ValueError (the core's message) for a value out
/// of range, an unknown name of an enumeration, or text the row cannot parse.
TrackerSettings settingsFromKwargs(const pybind11::kwargs& kwargs);

/// {python name: value} of every row; enumerations as their names.
pybind11::dict settingsDict(const TrackerSettings& settings);

/// One dict per row (name, type, default, range, choices, doc), in schema order.
pybind11::list settingsSchemaList();

/// The Tracker's docstring: its keywords with their types, defaults and descriptions.
std::string trackerDoc();

}  // namespace jointflow::python
