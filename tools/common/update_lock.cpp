#include "tools/common/update_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "sweep/core/error.h"
#include "sweep/io/interrupt.h"

namespace sweep::tools {
namespace fs = std::filesystem;

UpdateLock::UpdateLock(const fs::path& target) {
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  lock_ = dir / ("." + target.filename().string() + ".lock");
  for (;;) {
    fd_ = ::open(lock_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd_ < 0) {
      fail(ErrorCategory::output,
           target.string() + ": cannot create its lock file " + lock_.string() + ": " + std::strerror(errno));
    }
    int rc = 0;
    while ((rc = ::flock(fd_, LOCK_EX)) != 0 && errno == EINTR) {
    }
    if (rc != 0) {
      const std::string reason = std::strerror(errno);
      ::close(fd_);
      fail(ErrorCategory::output, target.string() + ": cannot lock " + lock_.string() + ": " + reason);
    }
    // The holder before us removes the file as it lets go: the lock we hold is then on a file no
    // longer under the name, which a third run may already have made and locked. Take that one.
    struct stat held {
    }, named{};
    if (::fstat(fd_, &held) == 0 && ::stat(lock_.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
        held.st_ino == named.st_ino) {
      break;
    }
    ::close(fd_);
  }
  slot_ = io::track_temporary(lock_.string(), target.string());
}

UpdateLock::~UpdateLock() {
  // Unlink before unlocking: a waiter that then gets the lock finds the name gone and starts over.
  ::unlink(lock_.c_str());
  io::untrack_temporary(slot_);
  ::close(fd_);
}

}  // namespace sweep::tools
