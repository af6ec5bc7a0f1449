#pragma once
// Command-line checks the tools share: every number given is read whole (no trailing text), must
// be finite, and is checked against its range with the text given quoted back (never a bound such
// as DBL_MAX printed in full, never a value read through a narrower type).
#include <CLI/CLI.hpp>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>

namespace sweep::tools {

// A file name given must not be empty: `--report ""` would otherwise mean "no report" silently.
inline const CLI::Validator kNonEmptyName(
    [](std::string& name) { return name.empty() ? std::string("the file name is empty") : std::string(); }, "",
    "NONEMPTY");

// `text` as a double, whole (nothing after the number); nullopt when it is not one. strtod, not
// std::stod: stod throws for a value that underflows (1e-308, a subnormal), which is a number.
inline std::optional<double> read_double(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return std::nullopt;
  return x;
}

// A finite number at least (or, `strictly`, above) `lo`. CLI11's own NonNegativeNumber and
// PositiveNumber let NaN through (every comparison with it is false) and print their upper bound,
// DBL_MAX, in full.
inline CLI::Validator finite_number(double lo, bool strictly) {
  return CLI::Validator(
      [lo, strictly](std::string& text) -> std::string {
        const std::optional<double> x = read_double(text);
        if (!x) return "must be a number, got '" + text + "'";
        if (!std::isfinite(*x)) return "must be a finite number, got " + text;
        if (strictly ? !(*x > lo) : !(*x >= lo)) {
          return std::string("must be ") + (strictly ? "> " : ">= ") + CLI::detail::to_string(lo) + ", got " + text;
        }
        return {};
      },
      strictly ? "NUMBER > 0" : "NUMBER >= 0", strictly ? "POSITIVE" : "NONNEGATIVE");
}
inline const CLI::Validator kNonNegative = finite_number(0, false);
inline const CLI::Validator kPositive = finite_number(0, true);

// A finite number in [lo, hi] (CLI::Range lets NaN through).
inline CLI::Validator finite_range(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        const std::optional<double> x = read_double(text);
        if (!x) return "must be a number, got '" + text + "'";
        if (!std::isfinite(*x)) return "must be a finite number, got " + text;
        if (!(*x >= lo && *x <= hi)) {
          return "must be between " + CLI::detail::to_string(lo) + " and " + CLI::detail::to_string(hi) + ", got " +
                 text;
        }
        return {};
      },
      "NUMBER", "RANGE");
}

// `text` as a whole number 0 … 2^64 − 1 (digits only: no sign, no exponent), or nullopt with
// `why` saying what is wrong in words ("not a whole number", "beyond 2^64 - 1").
inline std::optional<std::uint64_t> read_whole(const std::string& text, std::string& why) {
  std::uint64_t v = 0;
  const char* end = text.data() + text.size();
  const auto [stop, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || stop != end || (ec != std::errc() && ec != std::errc::result_out_of_range)) {
    why = "must be a whole number >= 0, got '" + text + "'";
    return std::nullopt;
  }
  if (ec == std::errc::result_out_of_range) {
    why = "is too large: " + text + " is beyond 2^64 - 1";
    return std::nullopt;
  }
  return v;
}

// A byte count with an optional unit: K, M, G (and KB, MB, GB) are powers of 1000, KiB, MiB, GiB
// of 1024, any case. Must be at least 1 and at most 2^64 - 1 bytes: 0, a sign, a fraction and an
// overflow are refused (none means "no limit": leave the option out for that).
inline std::optional<std::uint64_t> read_byte_size(const std::string& text, std::string& why) {
  std::size_t digits = 0;
  while (digits < text.size() && text[digits] >= '0' && text[digits] <= '9') ++digits;
  std::string unit = text.substr(digits);
  for (char& c : unit) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::uint64_t scale = 0;
  if (unit.empty() || unit == "b")
    scale = 1;
  else if (unit == "k" || unit == "kb")
    scale = 1000;
  else if (unit == "m" || unit == "mb")
    scale = 1000000;
  else if (unit == "g" || unit == "gb")
    scale = 1000000000;
  else if (unit == "kib")
    scale = 1024;
  else if (unit == "mib")
    scale = std::uint64_t{1} << 20;
  else if (unit == "gib")
    scale = std::uint64_t{1} << 30;
  if (digits == 0 || scale == 0) {
    why = "must be a whole number of bytes with an optional unit (K, M, G, KiB, MiB, GiB), got '" + text + "'";
    return std::nullopt;
  }
  std::string number_why;
  const std::optional<std::uint64_t> n = read_whole(text.substr(0, digits), number_why);
  if (!n || *n > UINT64_MAX / scale) {
    why = "is too large: " + text + " is beyond 2^64 - 1 bytes";
    return std::nullopt;
  }
  if (*n == 0) {
    why = "must be at least 1 byte, got '" + text + "' (leave the option out for no limit)";
    return std::nullopt;
  }
  return *n * scale;
}

}  // namespace sweep::tools
