#pragma once
// Outputs are written to a temporary file beside the target and renamed into place only when
// complete, so a failure or a kill never leaves a half-written file under the final name.
#include <filesystem>
#include <string_view>

namespace sweep::io {

// Writes bytes to path atomically. Throws Error(output) naming the path on any failure; the
// temporary file is removed in that case.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// Reads a whole file. Throws Error(bad_input) naming the path when it is missing or unreadable.
std::string read_file(const std::filesystem::path& path);

}  // namespace sweep::io
