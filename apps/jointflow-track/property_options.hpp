// jointflow-track's options made from jointflowtrack's own properties: same names, documentation,
// defaults and validation as the element (which makes them from the core's settings schema), so
// the command line and the element cannot drift apart. The same introspection writes the
// property table of docs/gstreamer.md (--properties-markdown).
#pragma once

#include <gst/gst.h>

#include <list>
#include <string>

#include <CLI/CLI.hpp>

namespace jointflow::cli {

struct PropertyOption {
  std::string name;   ///< property name = option name without "--"
  std::string value;  ///< the text given on the command line
};

/// Adds one option per writable property that `element`'s own class installs. The list holds the
/// values CLI11 writes into (a list: its elements never move).
std::list<PropertyOption> addPropertyOptions(CLI::App& app, GstElement* element);

/// Sets the properties whose options were given, as gst-launch does; throws jointflow::Error
/// naming the option when the element refuses a value.
void applyPropertyOptions(const CLI::App& app, GstElement* element,
                          const std::list<PropertyOption>& options);

/// The Markdown table of `element`'s own properties: name, type, default, range, description.
std::string propertyTableMarkdown(GstElement* element);

}  // namespace jointflow::cli
