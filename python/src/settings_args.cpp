#include "settings_args.hpp"

#include <algorithm>
#include <charconv>
#include <climits>
#include <string_view>

#include "jointflow/error.hpp"

namespace py = pybind11;

namespace jointflow::python {
namespace {

using Row = SettingSpec<TrackerSettings>;

std::string typeName(py::handle value) {
  return py::str(py::type::handle_of(value).attr("__name__"));
}

const char* pythonType(SettingKind kind) {
  switch (kind) {
    case SettingKind::kBool:
      return "bool";
    case SettingKind::kInt:
    case SettingKind::kUInt:
      return "int";
    case SettingKind::kFloat:
      return "float";
    case SettingKind::kString:
    case SettingKind::kEnum:
      break;
  }
  return "str";
}

std::string validNames() {
  std::string names;
  for (const Row& r : trackerSettingsSchema()) names += (names.empty() ? "" : ", ") + pythonName(r);
  return names;
}

[[noreturn]] void wrongType(const Row& row, py::handle value, const std::string& expected) {
  std::string shown = py::repr(value);
  if (shown.size() > 60) shown = shown.substr(0, 57) + "...";
  throw py::type_error("Tracker(): " + pythonName(row) + " expects " + expected + ", got " +
                       typeName(value) + " " + shown);
}

// An integer that does not fit the row's C type is outside its range as well: the core's
// message for the nearest value it can hold, with the number the user gave.
[[noreturn]] void tooWide(const Row& row, long long clamped, py::handle value) {
  try {
    checkSettingValue(row, row.kind == SettingKind::kUInt
                               ? SettingValue{static_cast<unsigned>(clamped)}
                               : SettingValue{static_cast<int>(clamped)});
  } catch (const Error& e) {
    const std::string message = e.what();
    const auto at = message.find(" is out of range");
    if (at != std::string::npos)
      throw py::value_error(std::string(row.name) + ": " + std::string(py::str(value)) +
                            message.substr(at));
    throw py::value_error(message);
  }
  throw py::value_error(std::string(row.name) + ": " + std::string(py::str(value)) +
                        " is out of range");
}

bool hasNick(const EnumView& view, std::string_view nick) {
  return std::any_of(view.values.begin(), view.values.end(),
                     [&](const EnumView::Value& v) { return nick == v.nick; });
}

SettingValue integerValue(const Row& row, py::handle value) {
  if (PyBool_Check(value.ptr()) || !PyIndex_Check(value.ptr())) wrongType(row, value, "an int");
  const py::int_ number = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
  if (!number) throw py::error_already_set();
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(number.ptr(), &overflow);
  if (v == -1 && PyErr_Occurred()) throw py::error_already_set();
  const long long lo = row.kind == SettingKind::kUInt ? 0 : INT_MIN;
  const long long hi = row.kind == SettingKind::kUInt ? UINT_MAX : INT_MAX;
  if (overflow < 0 || (overflow == 0 && v < lo)) tooWide(row, lo, value);
  if (overflow > 0 || v > hi) tooWide(row, hi, value);
  if (row.kind == SettingKind::kUInt) return SettingValue{static_cast<unsigned>(v)};
  return SettingValue{static_cast<int>(v)};
}

SettingValue toSettingValue(const Row& row, py::handle value) {
  switch (row.kind) {
    case SettingKind::kBool:
      if (!PyBool_Check(value.ptr())) wrongType(row, value, "True or False");
      return SettingValue{value.ptr() == Py_True};
    case SettingKind::kInt:
    case SettingKind::kUInt:
      return integerValue(row, value);
    case SettingKind::kFloat: {
      // int, float and numpy's numbers; not bool, not text.
      if (PyBool_Check(value.ptr()) || PyUnicode_Check(value.ptr()) || !PyNumber_Check(value.ptr()))
        wrongType(row, value, "a float");
      const double v = PyFloat_AsDouble(value.ptr());
      if (v == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        wrongType(row, value, "a float");
      }
      return SettingValue{static_cast<float>(v)};
    }
    case SettingKind::kString: {
      // Paths may come as os.PathLike (pathlib.Path).
      py::object text = py::reinterpret_borrow<py::object>(value);
      if (!PyUnicode_Check(value.ptr()) && py::hasattr(value, "__fspath__"))
        text = py::module_::import("os").attr("fspath")(value);
      if (!PyUnicode_Check(text.ptr())) wrongType(row, value, "a str");
      return SettingValue{text.cast<std::string>()};
    }
    case SettingKind::kEnum:
      // True and False name the values "true" and "false" where an enumeration has them (tiles:
      // auto, true or false, a bool before auto came): tiles=True keeps working.
      if (PyBool_Check(value.ptr()) && hasNick(*row.enumeration, "true") &&
          hasNick(*row.enumeration, "false"))
        return SettingValue{parseSettingEnum(row, value.ptr() == Py_True ? "true" : "false")};
      if (!PyUnicode_Check(value.ptr()))
        wrongType(row, value, "a str, one of " + joinNicks(row.enumeration->values));
      return SettingValue{parseSettingEnum(row, value.cast<std::string>())};
  }
  wrongType(row, value, "a value");
}

// The shortest decimal that reads back as the same float (0.1f -> 0.1, not 0.10000000149).
py::float_ shortestFloat(float v) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return py::float_(std::stod(std::string(text, end)));
}

py::object toPython(const Row& row, const SettingValue& value) {
  if (row.kind == SettingKind::kEnum) return py::str(settingValueText(row, value));
  return std::visit(
      [](const auto& v) -> py::object {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, float>)
          return shortestFloat(v);
        else
          return py::cast(v);
      },
      value);
}

}  // namespace

std::string pythonName(const SettingInfo& info) {
  std::string name = info.name;
  for (char& c : name)
    if (c == '-') c = '_';
  return name;
}

TrackerSettings settingsFromKwargs(const py::kwargs& kwargs) {
  TrackerSettings settings;
  const auto& rows = trackerSettingsSchema();
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key);
    const Row* row = nullptr;
    for (const Row& r : rows)
      if (pythonName(r) == name) row = &r;
    if (!row)
      throw py::type_error("Tracker(): unknown setting '" + name + "'; the settings are " +
                           validNames() + " (jointflow.settings() describes them)");
    const SettingValue v = toSettingValue(*row, value);
    try {
      checkSettingValue(*row, v);
      row->set(settings, v);
    } catch (const Error& e) {
      throw py::value_error(e.what());
    }
  }
  return settings;
}

py::dict settingsDict(const TrackerSettings& settings) {
  py::dict out;
  for (const Row& r : trackerSettingsSchema())
    out[py::str(pythonName(r))] = toPython(r, r.get(settings));
  return out;
}

py::list settingsSchemaList() {
  const TrackerSettings defaults;
  py::list out;
  for (const Row& r : trackerSettingsSchema()) {
    py::dict d;
    d["name"] = pythonName(r);
    d["type"] = py::module_::import("builtins").attr(pythonType(r.kind));
    d["default"] = toPython(r, r.get(defaults));
    const bool numeric = r.kind == SettingKind::kInt || r.kind == SettingKind::kUInt ||
                         r.kind == SettingKind::kFloat;
    d["range"] = numeric ? py::object(r.kind == SettingKind::kFloat
                                          ? py::make_tuple(r.min, r.max)
                                          : py::make_tuple(static_cast<long long>(r.min),
                                                           static_cast<long long>(r.max)))
                         : py::object(py::none());
    py::object choices = py::none();
    if (r.kind == SettingKind::kEnum) {
      py::list names;
      for (const auto& v : r.enumeration->values) names.append(v.nick);
      choices = py::tuple(names);
    }
    d["choices"] = choices;
    d["doc"] = r.blurb;
    out.append(d);
  }
  return out;
}

std::string trackerDoc() {
  std::string doc =
      "Tracker(**settings): the JointFlow pose tracker for one stream.\n\n"
      "Loads the models on construction. Settings (keyword arguments; the defaults are "
      "TrackerSettings'):\n\n";
  const TrackerSettings defaults;
  for (const Row& r : trackerSettingsSchema()) {
    doc += "  " + pythonName(r) + ": " + pythonType(r.kind) + " = " +
           std::string(py::repr(toPython(r, r.get(defaults)))) + "\n      " + r.blurb;
    if (r.kind == SettingKind::kEnum) doc += " (" + joinNicks(r.enumeration->values) + ")";
    doc += "\n";
  }
  return doc;
}

}  // namespace jointflow::python
