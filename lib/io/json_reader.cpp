#include "sweep/io/json_reader.h"

#include <cmath>
#include <sstream>

#include "sweep/core/error.h"
#include "sweep/core/text.h"

namespace sweep::io {

Json parse_json_text(const std::string& text, const std::string& source) {
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    // e.byte is 1-based and points just past the offending character; turn it into line:column.
    const std::size_t at = e.byte == 0 ? 0 : std::min<std::size_t>(e.byte - 1, text.size());
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < at; ++i) {
      if (text[i] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    std::string what = e.what();
    // nlohmann's text is "[json.exception.parse_error.101] parse error at line 1, column 2: ...";
    // keep only what follows its own position.
    if (const auto colon = what.find(": ");
        colon != std::string::npos && what.find("parse error") != std::string::npos) {
      what = what.substr(colon + 2);
    }
    if (text.empty()) what = "empty file, expected JSON";
    fail(ErrorCategory::bad_input, source + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + what);
  } catch (const Json::exception& e) {
    // Not a syntax error but a value the parser cannot hold (a number that overflows a double).
    std::string what = e.what();
    if (const auto bracket = what.find("] "); bracket != std::string::npos) what = what.substr(bracket + 2);
    fail(ErrorCategory::bad_input, source + ": " + what);
  }
}

std::string member(const std::string& pointer, const std::string& key) {
  std::string escaped;
  for (char c : key) {
    if (c == '~') {
      escaped += "~0";
    } else if (c == '/') {
      escaped += "~1";
    } else {
      escaped += c;
    }
  }
  return pointer + "/" + escaped;
}

std::string element(const std::string& pointer, std::size_t index) {
  return pointer + "/" + std::to_string(index);
}

std::string describe(const Json& value) {
  switch (value.type()) {
    case Json::value_t::object:
      return "an object";
    case Json::value_t::array:
      return "an array";
    case Json::value_t::null:
      return "null";
    default: {
      std::string s = value.dump();
      if (s.size() > 40) s = s.substr(0, 37) + "...";
      return s;
    }
  }
}

void JsonReader::fail_at(const std::string& pointer, const std::string& what) const {
  fail(ErrorCategory::bad_input, source_ + ": " + (pointer.empty() ? "(document)" : pointer) + ": " + what);
}

void JsonReader::warn_at(const std::string& pointer, const std::string& what) const {
  if (warn_) warn_(source_ + ": " + (pointer.empty() ? "(document)" : pointer) + ": " + what);
}

const Json& JsonReader::required(const Json& obj, const std::string& pointer, const char* key) const {
  const auto it = obj.find(key);
  if (it == obj.end()) fail_at(pointer, std::string("missing required member \"") + key + "\"");
  return *it;
}

const Json* JsonReader::optional(const Json& obj, const char* key) const {
  const auto it = obj.find(key);
  return it == obj.end() ? nullptr : &*it;
}

void JsonReader::object(const Json& value, const std::string& pointer, std::initializer_list<const char*> known) const {
  if (!value.is_object()) fail_at(pointer, "must be an object, got " + describe(value));
  for (const auto& [key, unused] : value.items()) {
    bool ok = false;
    for (const char* k : known) ok = ok || key == k;
    if (!ok) warn_at(member(pointer, key), "unknown member \"" + key + "\" ignored");
  }
}

void JsonReader::array(const Json& value, const std::string& pointer) const {
  if (!value.is_array()) fail_at(pointer, "must be an array, got " + describe(value));
}

double JsonReader::number(const Json& value, const std::string& pointer) const {
  if (!value.is_number()) fail_at(pointer, "must be a number, got " + describe(value));
  const double x = value.get<double>();
  if (!std::isfinite(x)) fail_at(pointer, "must be a finite number");
  return x;
}

double JsonReader::positive(const Json& value, const std::string& pointer) const {
  const double x = number(value, pointer);
  if (!(x > 0)) fail_at(pointer, "must be a positive number, got " + describe(value));
  return x;
}

double JsonReader::non_negative(const Json& value, const std::string& pointer) const {
  const double x = number(value, pointer);
  if (x < 0) fail_at(pointer, "must not be negative, got " + describe(value));
  return x;
}

// Text of a bound, for messages: "1e+09", "0.001", "10000".
static std::string bound_text(double x) {
  return format_number(x, 6);
}

double JsonReader::bounded(const Json& value, const std::string& pointer, double lo, double hi) const {
  const double x = number(value, pointer);
  if (!(x >= lo && x <= hi)) {
    fail_at(pointer, "must be between " + bound_text(lo) + " and " + bound_text(hi) + ", got " + describe(value));
  }
  return x;
}

Vec3 JsonReader::bounded_vec3(const Json& value, const std::string& pointer, double hi) const {
  const Vec3 v = vec3(value, pointer);
  for (int k = 0; k < 3; ++k) bounded(value[k], element(pointer, k), -hi, hi);
  return v;
}

long long JsonReader::integer(const Json& value, const std::string& pointer, long long lo, long long hi) const {
  if (!value.is_number_integer()) fail_at(pointer, "must be a whole number, got " + describe(value));
  const long long x = value.get<long long>();
  if (x < lo || x > hi) {
    fail_at(pointer,
            "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " + describe(value));
  }
  return x;
}

std::string JsonReader::string(const Json& value, const std::string& pointer) const {
  if (!value.is_string()) fail_at(pointer, "must be a string, got " + describe(value));
  return value.get<std::string>();
}

bool JsonReader::boolean(const Json& value, const std::string& pointer) const {
  if (!value.is_boolean()) fail_at(pointer, "must be true or false, got " + describe(value));
  return value.get<bool>();
}

Vec3 JsonReader::vec3(const Json& value, const std::string& pointer) const {
  if (!value.is_array() || value.size() != 3) fail_at(pointer, "must be an array of 3 numbers, got " + describe(value));
  return {number(value[0], element(pointer, 0)), number(value[1], element(pointer, 1)),
          number(value[2], element(pointer, 2))};
}

}  // namespace sweep::io
