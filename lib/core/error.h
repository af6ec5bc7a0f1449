#pragma once
// One error type for everything the tools can meet at run time. Programmer errors are asserts;
// bad data is an Error with a category, and each category has one documented exit code
// (exit_code below is the only place that mapping lives).
#include <stdexcept>
#include <string>

namespace sweep {

enum class ErrorCategory {
  usage,        // bad command line
  bad_input,    // an input file is missing, unreadable, malformed or inconsistent
  unsupported,  // valid input that this version cannot handle (format, feature)
  output,       // an output cannot be written
  diverged,     // a simulation produced non-finite or runaway values
  internal,     // a bug: should never happen
};

class Error : public std::runtime_error {
 public:
  Error(ErrorCategory category, const std::string& message) : std::runtime_error(message), category_(category) {}
  ErrorCategory category() const { return category_; }

 private:
  ErrorCategory category_;
};

// Exit codes, as listed in docs/tools.md ("Exit codes").
constexpr int exit_code(ErrorCategory c) {
  switch (c) {
    case ErrorCategory::usage:
      return 1;
    case ErrorCategory::bad_input:
      return 2;
    case ErrorCategory::unsupported:
      return 3;
    case ErrorCategory::output:
      return 4;
    case ErrorCategory::diverged:
      return 5;
    case ErrorCategory::internal:
      return 6;
  }
  return 6;
}

[[noreturn]] inline void fail(ErrorCategory c, const std::string& message) {
  throw Error(c, message);
}

}  // namespace sweep
