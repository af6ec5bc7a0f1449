#include "io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace sweep::io {
namespace fs = std::filesystem;

namespace {

// Creates the temporary beside `path` (".<name>.tmp-XXXXXX"); returns its descriptor and name.
int create_temporary(const fs::path& path, std::string& name) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  name = (dir / ("." + path.filename().string() + ".tmp-XXXXXX")).string();
  const int fd = ::mkstemp(name.data());
  if (fd < 0) {
    fail(ErrorCategory::output, path.string() + ": cannot create a file in " + dir.string() + ": " +
                                    std::strerror(errno));
  }
  return fd;
}

}  // namespace

void check_can_create(const fs::path& path) {
  std::string tmp;
  const int fd = create_temporary(path, tmp);
  ::close(fd);
  ::unlink(tmp.c_str());
}

void write_file_atomically(const fs::path& path, std::string_view bytes) {
  std::string tmp;
  const int fd = create_temporary(path, tmp);
  auto give_up = [&](const char* what) {
    const std::string reason = std::strerror(errno);
    ::close(fd);
    ::unlink(tmp.c_str());
    fail(ErrorCategory::output, path.string() + ": " + what + ": " + reason);
  };
  const char* p = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      give_up("cannot write");
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  // Files are created 0600 by mkstemp; give them the usual permissions (umask applies).
  const mode_t mask = ::umask(0);
  ::umask(mask);
  if (::fchmod(fd, 0666 & ~mask) != 0) give_up("cannot set permissions");
  if (::fsync(fd) != 0) give_up("cannot flush to disk");
  if (::close(fd) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(tmp.c_str());
    fail(ErrorCategory::output, path.string() + ": cannot close: " + reason);
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(tmp.c_str());
    fail(ErrorCategory::output, path.string() + ": cannot rename into place: " + reason);
  }
}

std::string read_file(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(ErrorCategory::bad_input, path.string() + ": no such file");
  if (fs::is_directory(path, ec)) fail(ErrorCategory::bad_input, path.string() + ": is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(ErrorCategory::bad_input, path.string() + ": cannot open: " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) fail(ErrorCategory::bad_input, path.string() + ": cannot read");
  return std::move(ss).str();
}

}  // namespace sweep::io
