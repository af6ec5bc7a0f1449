#pragma once
// Command-line checks the tools share.
#include <CLI/CLI.hpp>
#include <cmath>
#include <string>

namespace sweep::tools {

// A file name given must not be empty: `--report ""` would otherwise mean "no report" silently.
inline const CLI::Validator kNonEmptyName(
    [](std::string& name) { return name.empty() ? std::string("the file name is empty") : std::string(); },
    "", "NONEMPTY");

// A finite number at least (or, `strictly`, above) `lo`. CLI11's own NonNegativeNumber and
// PositiveNumber let NaN through (every comparison with it is false) and print their upper bound,
// DBL_MAX, in full.
inline CLI::Validator finite_number(double lo, bool strictly) {
  return CLI::Validator(
      [lo, strictly](std::string& text) -> std::string {
        double x = 0;
        try {
          std::size_t used = 0;
          x = std::stod(text, &used);
          if (used != text.size()) return "must be a number, got " + text;
        } catch (const std::exception&) {
          return "must be a number, got " + text;
        }
        if (!std::isfinite(x)) return "must be a finite number, got " + text;
        if (strictly ? !(x > lo) : !(x >= lo)) {
          return std::string("must be ") + (strictly ? "> " : ">= ") + CLI::detail::to_string(lo) + ", got " + text;
        }
        return {};
      },
      strictly ? "NUMBER > 0" : "NUMBER >= 0", strictly ? "POSITIVE" : "NONNEGATIVE");
}
inline const CLI::Validator kNonNegative = finite_number(0, false);
inline const CLI::Validator kPositive = finite_number(0, true);

}  // namespace sweep::tools
