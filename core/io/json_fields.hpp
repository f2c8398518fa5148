// Strict access to the fields of a parsed JSON document, for the PoseTrack readers: every failure
// throws jointflow::Error naming the file, the field's path and what was expected.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace jointflow::io {

/// A JSON value together with where it came from ("file.json" and "annolist[2].annorect").
class Field {
 public:
  Field(const nlohmann::json& value, std::string file, std::string path)
      : value_(value), file_(std::move(file)), path_(std::move(path)) {}

  const nlohmann::json& json() const { return value_; }
  const std::string& path() const { return path_; }

  bool has(const char* key) const { return value_.is_object() && value_.contains(key); }
  /// The member `key`; throws when this is not an object or the member is missing.
  Field operator[](const char* key) const;
  /// Element `i` of an array (the caller checks the bounds with size()).
  Field operator[](std::size_t i) const;
  /// Number of elements; throws when this is not an array.
  std::size_t size() const;

  double number() const;
  std::int64_t integer() const;
  std::string string() const;
  bool boolean() const;  ///< true/false, or a number (0 = false), as PoseTrack files write both

  /// A 2017-style value: a one-element list holding it, or (leniently) the bare value.
  Field unwrapped() const;

  /// Throws "<file>: <path>: expected <what>, got <type>".
  [[noreturn]] void fail(const std::string& what) const;
  /// Throws "<file>: <path>: <message>".
  [[noreturn]] void reject(const std::string& message) const;

 private:
  const nlohmann::json& value_;
  std::string file_;
  std::string path_;
};

/// Parses JSON text; a syntax error (truncated file, ...) names the file and the byte.
nlohmann::json parseJson(const std::string& text, const std::string& file);

}  // namespace jointflow::io
