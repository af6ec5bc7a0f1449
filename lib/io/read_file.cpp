#include "sweep/io/read_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "sweep/core/error.h"

namespace sweep::io {
namespace fs = std::filesystem;

std::string read_file(const fs::path& path, std::uint64_t max_bytes) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) fail(ErrorCategory::bad_input, path.string() + ": no such file");
  if (fs::is_directory(st)) fail(ErrorCategory::bad_input, path.string() + ": is a directory, not a file");
  if (!fs::is_regular_file(st)) {
    fail(ErrorCategory::bad_input, path.string() + ": is not a regular file (a FIFO, a device or a socket)");
  }
  if (const std::uintmax_t size = fs::file_size(path, ec); !ec && size > max_bytes) {
    fail(ErrorCategory::bad_input, path.string() + ": " + std::to_string(size) + " bytes, more than the limit of " +
                                       std::to_string(max_bytes) + " for this kind of file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(ErrorCategory::bad_input, path.string() + ": cannot open: " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) fail(ErrorCategory::bad_input, path.string() + ": cannot read");
  return std::move(ss).str();
}

std::string read_text_file(const fs::path& path) {
  std::string text = read_file(path);
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  return text;
}

}  // namespace sweep::io
