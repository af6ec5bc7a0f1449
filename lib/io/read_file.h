#pragma once
// Reading a whole input file, with the checks every reader needs first.
#include <cstdint>
#include <filesystem>
#include <string>

namespace sweep::io {

// Reads a whole file. Throws Error(bad_input) naming the path when it is missing, unreadable, not
// a regular file (a FIFO or a device would block or never end) or larger than `max_bytes`
// (checked before reading: JSON inputs pass limits::kMaxJsonBytes).
std::string read_file(const std::filesystem::path& path, std::uint64_t max_bytes = UINT64_MAX);

// read_file for text: a UTF-8 byte order mark at the start is skipped (it is not content).
std::string read_text_file(const std::filesystem::path& path);

}  // namespace sweep::io
