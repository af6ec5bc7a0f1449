#pragma once
// The readers' refusal of a file they cannot take: "<file>: <what is wrong>".
#include <filesystem>
#include <string>

#include "sweep/core/error.h"

namespace sweep::assets::detail {

[[noreturn]] inline void refuse(const std::filesystem::path& file, const std::string& what,
                                ErrorCategory category = ErrorCategory::bad_input) {
  fail(category, file.string() + ": " + what);
}

}  // namespace sweep::assets::detail
