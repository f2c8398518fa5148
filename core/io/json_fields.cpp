#include "json_fields.hpp"

#include <cmath>

#include "jointflow/error.hpp"

namespace jointflow::io {

Field Field::operator[](const char* key) const {
  if (!value_.is_object()) fail("an object with \"" + std::string(key) + "\"");
  auto it = value_.find(key);
  if (it == value_.end()) {
    throw Error(file_ + ": " + (path_.empty() ? std::string(key) : path_ + "." + key) +
                ": required field is missing");
  }
  return Field(*it, file_, path_.empty() ? std::string(key) : path_ + "." + key);
}

Field Field::operator[](std::size_t i) const {
  return Field(value_.at(i), file_, path_ + "[" + std::to_string(i) + "]");
}

std::size_t Field::size() const {
  if (!value_.is_array()) fail("a list");
  return value_.size();
}

double Field::number() const {
  if (!value_.is_number()) fail("a number");
  const double v = value_.get<double>();
  if (!std::isfinite(v)) fail("a finite number");
  return v;
}

std::int64_t Field::integer() const {
  if (value_.is_number_integer()) return value_.get<std::int64_t>();
  // Some writers emit integral floats (3.0); anything else is not an id.
  if (value_.is_number_float()) {
    const double v = value_.get<double>();
    if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 9.0e15) {
      return static_cast<std::int64_t>(v);
    }
  }
  fail("an integer");
}

std::string Field::string() const {
  if (!value_.is_string()) fail("a string");
  return value_.get<std::string>();
}

bool Field::boolean() const {
  if (value_.is_boolean()) return value_.get<bool>();
  if (value_.is_number()) return value_.get<double>() != 0.0;
  fail("true/false or a number");
}

Field Field::unwrapped() const {
  if (!value_.is_array()) return *this;
  if (value_.size() != 1) fail("a one-element list");
  return (*this)[std::size_t{0}];
}

void Field::fail(const std::string& what) const {
  throw Error(file_ + ": " + (path_.empty() ? std::string("top level") : path_) + ": expected " +
              what + ", got " + (value_.is_null() ? std::string("null") : value_.type_name()));
}

void Field::reject(const std::string& message) const {
  throw Error(file_ + ": " + (path_.empty() ? std::string("top level") : path_) + ": " + message);
}

nlohmann::json parseJson(const std::string& text, const std::string& file) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(file + ": not valid JSON (truncated or corrupt) at byte " + std::to_string(e.byte) +
                ": " + e.what());
  } catch (const nlohmann::json::exception& e) {
    // The parser throws out_of_range, not parse_error, for a number beyond double ("1e400"); found
    // by fuzzing (tests/hardening/fuzz_regressions/number_overflow.json).
    throw Error(file + ": not valid JSON: " + e.what());
  }
}

}  // namespace jointflow::io
