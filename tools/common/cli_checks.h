#pragma once
// Command-line checks the tools share.
#include <CLI/CLI.hpp>
#include <string>

namespace sweep::tools {

// A file name given must not be empty: `--report ""` would otherwise mean "no report" silently.
inline const CLI::Validator kNonEmptyName(
    [](std::string& name) { return name.empty() ? std::string("the file name is empty") : std::string(); },
    "", "NONEMPTY");

}  // namespace sweep::tools
