// Options and the documentation table from an element's properties (property_options.hpp).
#include "property_options.hpp"

#include <cstdio>
#include <sstream>
#include <vector>

#include "jointflow/error.hpp"

namespace jointflow::cli {
namespace {

std::vector<GParamSpec*> ownWritableProperties(GstElement* element) {
  guint n = 0;
  GParamSpec** specs = g_object_class_list_properties(G_OBJECT_GET_CLASS(element), &n);
  std::vector<GParamSpec*> out;
  for (guint i = 0; i < n; ++i)
    if (specs[i]->owner_type == G_OBJECT_TYPE(element) && (specs[i]->flags & G_PARAM_WRITABLE))
      out.push_back(specs[i]);
  g_free(specs);
  return out;
}

std::string floatText(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

std::string defaultText(GParamSpec* spec) {
  const GValue* def = g_param_spec_get_default_value(spec);
  if (G_VALUE_HOLDS_FLOAT(def)) return floatText(g_value_get_float(def));
  gchar* s = gst_value_serialize(def);
  std::string text = s ? s : "";
  g_free(s);
  return text.empty() ? "none" : text;
}

// What --help shows as the option's value.
std::string typeName(GParamSpec* spec) {
  switch (G_TYPE_FUNDAMENTAL(spec->value_type)) {
    case G_TYPE_INT:
    case G_TYPE_UINT:
      return "INT";
    case G_TYPE_FLOAT:
    case G_TYPE_DOUBLE:
      return "FLOAT";
    case G_TYPE_BOOLEAN:
      return "true|false";
    case G_TYPE_ENUM:
      return "NAME";
    default:
      return "TEXT";
  }
}

// What the documentation table shows as the property's type.
std::string docTypeName(GParamSpec* spec) {
  switch (G_TYPE_FUNDAMENTAL(spec->value_type)) {
    case G_TYPE_INT:
      return "int";
    case G_TYPE_UINT:
      return "uint";
    case G_TYPE_FLOAT:
      return "float";
    case G_TYPE_BOOLEAN:
      return "bool";
    case G_TYPE_ENUM:
      return "enum";
    case G_TYPE_STRING:
      return "string";
    default:
      return g_type_name(spec->value_type);
  }
}

std::string enumNicks(GParamSpec* spec, const char* separator) {
  std::string text;
  GEnumClass* klass = G_PARAM_SPEC_ENUM(spec)->enum_class;
  for (guint i = 0; i < klass->n_values; ++i)
    text += std::string(i ? separator : "") + klass->values[i].value_nick;
  return text;
}

std::string allowedValues(GParamSpec* spec) {
  return G_IS_PARAM_SPEC_ENUM(spec) ? " [" + enumNicks(spec, "|") + "]" : "";
}

std::string rangeText(GParamSpec* spec) {
  if (G_IS_PARAM_SPEC_INT(spec))
    return std::to_string(G_PARAM_SPEC_INT(spec)->minimum) + " to " +
           std::to_string(G_PARAM_SPEC_INT(spec)->maximum);
  if (G_IS_PARAM_SPEC_UINT(spec))
    return std::to_string(G_PARAM_SPEC_UINT(spec)->minimum) + " to " +
           std::to_string(G_PARAM_SPEC_UINT(spec)->maximum);
  if (G_IS_PARAM_SPEC_FLOAT(spec))
    return floatText(G_PARAM_SPEC_FLOAT(spec)->minimum) + " to " +
           floatText(G_PARAM_SPEC_FLOAT(spec)->maximum);
  if (G_IS_PARAM_SPEC_ENUM(spec)) return enumNicks(spec, ", ");
  return "";
}

// Sets a property from text the way gst-launch does, refusing what the element refuses.
void setProperty(GstElement* element, const std::string& name, const std::string& text) {
  GParamSpec* spec = g_object_class_find_property(G_OBJECT_GET_CLASS(element), name.c_str());
  GValue value = G_VALUE_INIT;
  g_value_init(&value, spec->value_type);
  if (!gst_value_deserialize(&value, text.c_str())) {
    g_value_unset(&value);
    throw Error("--" + name + ": \"" + text + "\" is not a valid value" + allowedValues(spec));
  }
  if (g_param_value_validate(spec, &value)) {  // TRUE when the value had to be changed
    g_value_unset(&value);
    throw Error("--" + name + ": " + text + " is out of range (see --help)");
  }
  // The element validates what a GParamSpec cannot (input-size, scales) and warns: make that an
  // error here.
  std::string refused;
  const guint handler = g_log_set_handler(
      nullptr, static_cast<GLogLevelFlags>(G_LOG_LEVEL_WARNING | G_LOG_LEVEL_CRITICAL),
      [](const gchar*, GLogLevelFlags, const gchar* message, gpointer data) {
        *static_cast<std::string*>(data) = message;
      },
      &refused);
  g_object_set_property(G_OBJECT(element), name.c_str(), &value);
  g_log_remove_handler(nullptr, handler);
  g_value_unset(&value);
  if (!refused.empty()) throw Error("--" + name + ": " + refused);
}

}  // namespace

std::list<PropertyOption> addPropertyOptions(CLI::App& app, GstElement* element) {
  std::list<PropertyOption> options;
  for (GParamSpec* spec : ownWritableProperties(element)) {
    PropertyOption& o = options.emplace_back(PropertyOption{spec->name, ""});
    const std::string help = std::string(g_param_spec_get_blurb(spec)) + allowedValues(spec) +
                             " (default: " + defaultText(spec) + ")";
    app.add_option("--" + o.name, o.value, help)->type_name(typeName(spec));
  }
  return options;
}

void applyPropertyOptions(const CLI::App& app, GstElement* element,
                          const std::list<PropertyOption>& options) {
  for (const PropertyOption& o : options)
    if (app.count("--" + o.name) > 0) setProperty(element, o.name, o.value);
}

std::string propertyTableMarkdown(GstElement* element) {
  std::ostringstream out;
  out << "| property | type | default | range | meaning |\n|---|---|---|---|---|\n";
  for (GParamSpec* spec : ownWritableProperties(element)) {
    const std::string type = docTypeName(spec);
    std::string def = defaultText(spec);
    if (def == "none") def = "\"\"";
    std::string blurb = g_param_spec_get_blurb(spec);
    for (size_t at = blurb.find('|'); at != std::string::npos; at = blurb.find('|', at + 2))
      blurb.replace(at, 1, "\\|");  // a table cell
    out << "| `" << spec->name << "` | " << type << " | " << def << " | " << rangeText(spec)
        << " | " << blurb
        << ((spec->flags & GST_PARAM_MUTABLE_PLAYING) ? " (changes apply at once)" : "") << " |\n";
  }
  return out.str();
}

}  // namespace jointflow::cli
