#pragma once
// Outputs are written to a temporary file beside the target and renamed into place only when
// complete, so a failure or a kill never leaves a half-written file under the final name.
#include <filesystem>
#include <string_view>

namespace sweep::io {

// Writes bytes to path atomically. Throws Error(output) naming the path on any failure; the
// temporary file is removed in that case.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// Fails now, with the message write_file_atomically would give later (Error(output) naming the
// path), when a file cannot be created beside `path` (missing or read-only folder, a file in
// place of the folder). Tools check every output this way before any work, so that an output
// that cannot be written is found before the others are written. Creates and removes a
// temporary; the target itself is not touched.
void check_can_create(const std::filesystem::path& path);

// Reads a whole file. Throws Error(bad_input) naming the path when it is missing or unreadable.
std::string read_file(const std::filesystem::path& path);

}  // namespace sweep::io
