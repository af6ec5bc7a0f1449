#pragma once
// Validating access to a parsed JSON document: every value is named by its JSON pointer, so a
// wrong value becomes "file: /sweeps/0/sections/2/radii/5: must be a positive number, got -1".
// Malformed text becomes "file:LINE:COLUMN: ..." . Unknown members are warnings, not errors.
#include <functional>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>

#include "sweep/core/frame.h"

namespace sweep::io {

using Json = nlohmann::json;
using WarningSink = std::function<void(const std::string&)>;

// Parses text; a syntax error throws Error(bad_input) "source:line:column: what". Invalid UTF-8
// in a string is a syntax error too (nlohmann only finds it when a string is dumped, as a
// type_error, which would otherwise surface as an internal error).
Json parse_json_text(const std::string& text, const std::string& source);

class JsonReader {
 public:
  JsonReader(std::string source, WarningSink warn) : source_(std::move(source)), warn_(std::move(warn)) {}

  [[noreturn]] void fail_at(const std::string& pointer, const std::string& what) const;
  void warn_at(const std::string& pointer, const std::string& what) const;

  // A member that must be there / may be there (nullptr when absent). `obj` must be an object.
  const Json& required(const Json& obj, const std::string& pointer, const char* key) const;
  const Json* optional(const Json& obj, const char* key) const;
  // Checks `value` is an object and warns about members not in `known`.
  void object(const Json& value, const std::string& pointer, std::initializer_list<const char*> known) const;
  void array(const Json& value, const std::string& pointer) const;

  double number(const Json& value, const std::string& pointer) const;  // finite
  double positive(const Json& value, const std::string& pointer) const;
  double non_negative(const Json& value, const std::string& pointer) const;
  // A number in [lo, hi] (core/limits.h holds the bounds); "must be between lo and hi, got x".
  double bounded(const Json& value, const std::string& pointer, double lo, double hi) const;
  // A vector whose every component is within ±`hi`.
  Vec3 bounded_vec3(const Json& value, const std::string& pointer, double hi) const;
  long long integer(const Json& value, const std::string& pointer, long long lo, long long hi) const;
  std::string string(const Json& value, const std::string& pointer) const;
  Vec3 vec3(const Json& value, const std::string& pointer) const;
  bool boolean(const Json& value, const std::string& pointer) const;

  const std::string& source() const { return source_; }

 private:
  std::string source_;
  WarningSink warn_;
};

// Pointer of a member or an element below `pointer`.
std::string member(const std::string& pointer, const std::string& key);
std::string element(const std::string& pointer, std::size_t index);

// A short rendering of a JSON value for messages ("-1", "\"abc\"", "an object").
std::string describe(const Json& value);

}  // namespace sweep::io
