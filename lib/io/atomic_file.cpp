#include "sweep/io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "sweep/core/error.h"
#include "sweep/core/hash.h"
#include "sweep/io/interrupt.h"

namespace sweep::io {
namespace fs = std::filesystem;

void check_can_create(const fs::path& path) {
  TempFile probe(path, /*scratch=*/true);  // nameless: gone when the probe is
}

void write_file_atomically(const fs::path& path, std::string_view bytes) {
  TempFile file(path);
  file.write(bytes);
  file.commit();
}

namespace {

// The process's umask, read once. Linux shows it in /proc/self/status, so it is read without the
// umask(0)/umask(mask) dance, which would briefly change it under other threads.
mode_t process_umask() {
  static const mode_t mask = [] {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
      if (line.rfind("Umask:", 0) == 0) return static_cast<mode_t>(std::stoul(line.substr(6), nullptr, 8));
    }
    const mode_t m = ::umask(0);  // older kernels: the dance, once
    ::umask(m);
    return m;
  }();
  return mask;
}

constexpr std::size_t kBufferBytes = std::size_t{1} << 20;  // TempFile's write buffer

}  // namespace

namespace {

// The temporary's base name: the target's, cut and hashed when the result would pass NAME_MAX.
std::string temp_base(const std::string& name) {
  constexpr std::size_t kKeep = 200;  // + "-" + 16 hex + ".scratch-XXXXXX" + "." < 255
  if (name.size() <= kKeep) return name;
  const std::uint64_t h = fnv1a(name);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return name.substr(0, kKeep) + "-" + hex;
}

}  // namespace

namespace {

// ".<name>.<tool>-<pid>.tmp-XXXXXX" (a temporary) or ".<name>.<tool>-<pid>.old-XXXXXX" (an earlier
// file set aside while a set was published) of one of these tools: the pid, or 0 when `file` is
// neither. `set_aside_file` says which; `name` gets <name>.
long temporary_pid(const std::string& file, bool* set_aside_file = nullptr, std::string* name = nullptr) {
  std::size_t tmp = file.rfind(".tmp-");
  const std::size_t old = file.rfind(".old-");
  if (tmp == std::string::npos || (old != std::string::npos && old > tmp)) tmp = old;
  if (file.empty() || file[0] != '.' || tmp == std::string::npos || file.size() != tmp + 11) return 0;
  if (set_aside_file) *set_aside_file = tmp == old;
  const std::size_t dash = file.rfind('-', tmp);
  const std::size_t dot = file.rfind('.', dash);
  if (dash == std::string::npos || dot == std::string::npos || dash < dot) return 0;
  const std::string tool = file.substr(dot + 1, dash - dot - 1);
  if (tool != "sweep" && tool.rfind("sweep-", 0) != 0) return 0;
  long pid = 0;
  for (std::size_t i = dash + 1; i < tmp; ++i) {
    if (file[i] < '0' || file[i] > '9' || pid > 100000000) return 0;
    pid = pid * 10 + (file[i] - '0');
  }
  if (name) *name = file.substr(1, dot - 1);
  return pid;
}

}  // namespace

namespace {

// ".<name>.old-XXXXXX": an earlier file set aside as earlier versions named it (no tool or process
// in the name); `name` gets <name>.
bool legacy_set_aside(const std::string& file, std::string& name) {
  if (file.size() < 13 || file[0] != '.' || file.compare(file.size() - 11, 5, ".old-") != 0) return false;
  name = file.substr(1, file.size() - 12);
  return !name.empty();
}

// An earlier file set aside by a run killed while publishing (`hidden`, standing for `target`):
// put back when nothing took its name (the run died before its new file went into place), else
// superseded and removed. A name cut to fit (temp_base) cannot be put back: only removed.
void settle_set_aside(const fs::path& hidden, const fs::path& target, const std::string& why) {
  struct stat st {};
  const std::string name = target.filename().string();
  if (temp_base(name) == name && ::lstat(target.c_str(), &st) != 0 && errno == ENOENT &&
      ::rename(hidden.c_str(), target.c_str()) == 0) {
    note("put back " + target.string() + ", set aside by a run that was killed" + why +
         " before its new file went into place");
  } else if (::unlink(hidden.c_str()) == 0) {
    note("removed " + hidden.string() + ", an earlier " + name + " set aside by a run that was killed" + why);
  }
}

}  // namespace

void remove_stale_temporaries(const fs::path& folder) {
  static std::set<fs::path> done;  // once a folder per run
  if (!done.insert(folder).second) return;
  std::error_code ec;
  std::vector<std::pair<fs::path, std::string>> set_aside_files;  // (hidden, target name)
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string file = it->path().filename().string();
    bool earlier = false;
    std::string name;
    const long pid = temporary_pid(file, &earlier, &name);
    if (pid <= 0 && legacy_set_aside(file, name)) set_aside_files.emplace_back(it->path(), name);
    if (pid <= 0 || pid == ::getpid()) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive (or not ours)
    if (earlier) {
      settle_set_aside(it->path(), folder / name, " (process " + std::to_string(pid) + " is gone)");
    } else if (::unlink(it->path().c_str()) == 0) {
      note("removed " + it->path().string() + ", left by a run that was killed (process " + std::to_string(pid) +
           " is gone)");
    }
  }
  // Earlier versions named a set-aside file without its process. A run sets files aside and
  // settles them under the folder's lock (Publication::commit), so under that lock any such file
  // is a killed run's.
  if (set_aside_files.empty()) return;
  const FolderLock lock(folder);
  for (const auto& [hidden, name] : set_aside_files) {
    if (fs::exists(fs::symlink_status(hidden, ec))) settle_set_aside(hidden, folder / name, "");
  }
}

fs::path set_aside(const fs::path& target) {
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  struct stat st {};
  if (::lstat(target.c_str(), &st) != 0) return {};
  // Named by the tool and process, as temporaries are: a run killed while publishing leaves it,
  // and the next run writing here puts it back or removes it (remove_stale_temporaries).
  std::string name = (dir / ("." + temp_base(target.filename().string()) + "." + tool_name() + "-" +
                             std::to_string(::getpid()) + ".old-XXXXXX"))
                         .string();
  const int fd = ::mkostemp(name.data(), O_CLOEXEC);  // reserves the name
  if (fd < 0 || ::close(fd) != 0 || ::rename(target.c_str(), name.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    if (fd >= 0) ::unlink(name.c_str());
    fail(ErrorCategory::output, target.string() + ": cannot set the earlier file aside: " + reason);
  }
  return name;
}

FolderLock::FolderLock(const fs::path& folder) {
  const fs::path dir = folder.empty() ? fs::path(".") : folder;
  fd_ = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  int rc = -1;
  if (fd_ >= 0) {
    while ((rc = ::flock(fd_, LOCK_EX)) != 0 && errno == EINTR) {
    }
  }
  if (rc != 0) {
    const std::string reason = std::strerror(errno);
    if (fd_ >= 0) ::close(fd_);
    fail(ErrorCategory::output, dir.string() + ": cannot lock the folder: " + reason);
  }
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);
}

TempFile::TempFile(fs::path target, bool scratch) : target_(std::move(target)) {
  const fs::path dir = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  struct stat st {};
  if (::lstat(target_.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    const char* what = S_ISLNK(st.st_mode)                            ? "a symbolic link"
                       : S_ISFIFO(st.st_mode)                         ? "a FIFO"
                       : S_ISDIR(st.st_mode)                          ? "a folder"
                       : (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) ? "a device"
                                                                      : "not a regular file";
    fail(ErrorCategory::output,
         target_.string() + ": is " + what + "; outputs replace regular files only (give another name)");
  }
  if (!scratch) remove_stale_temporaries(dir);
  std::string name = (dir / ("." + temp_base(target_.filename().string()) +
                             (scratch ? std::string(".scratch-XXXXXX")
                                      : "." + tool_name() + "-" + std::to_string(::getpid()) + ".tmp-XXXXXX")))
                         .string();
  fd_ = ::mkostemp(name.data(), O_CLOEXEC);
  if (fd_ < 0) {
    fail(ErrorCategory::output,
         target_.string() + ": cannot create a file in " + dir.string() + ": " + std::strerror(errno));
  }
  if (scratch) {
    ::unlink(name.c_str());  // nameless from now on: nothing to clean up, ever
  } else {
    slot_ = track_temporary(name, target_.string());
    temp_ = std::move(name);
  }
}

TempFile::~TempFile() {
  discard();
}

void TempFile::discard() noexcept {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  if (!temp_.empty()) {
    ::unlink(temp_.c_str());
    temp_.clear();
  }
  untrack_temporary(std::exchange(slot_, -1));
  std::vector<char>().swap(buffer_);
}

void TempFile::fail_errno(const char* what) {
  const std::string reason = std::strerror(errno);
  discard();
  fail(ErrorCategory::output, target_.string() + ": " + what + ": " + reason);
}

void TempFile::flush() {
  if (fd_ < 0) fail(ErrorCategory::internal, target_.string() + ": write to a closed file");
  if (buffer_.empty()) return;
  const char* p = buffer_.data();
  std::size_t left = buffer_.size();
  while (left > 0) {
    const ssize_t n = ::write(fd_, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail_errno("cannot write");
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  buffer_.clear();
}

void TempFile::write(const void* data, std::size_t size) {
  if (fd_ < 0) fail(ErrorCategory::internal, target_.string() + ": write to a closed file");
  const char* p = static_cast<const char*>(data);
  size_ += size;
  if (buffer_.size() + size <= kBufferBytes) {
    buffer_.insert(buffer_.end(), p, p + size);
    return;
  }
  flush();
  if (size < kBufferBytes) {
    buffer_.insert(buffer_.end(), p, p + size);
    return;
  }
  while (size > 0) {  // large blocks go straight to the file
    const ssize_t n = ::write(fd_, p, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail_errno("cannot write");
    }
    p += n;
    size -= static_cast<std::size_t>(n);
  }
}

void TempFile::copy_to(TempFile& out) {
  flush();
  std::vector<char> chunk(kBufferBytes);
  off_t offset = 0;
  while (static_cast<std::uint64_t>(offset) < size_) {
    const ssize_t n = ::pread(fd_, chunk.data(), chunk.size(), offset);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail_errno("cannot read back a scratch file");
    }
    if (n == 0) {
      errno = EIO;
      fail_errno("scratch file is shorter than written");
    }
    out.write(chunk.data(), static_cast<std::size_t>(n));
    offset += n;
  }
}

void TempFile::commit() {
  seal();
  publish();
}

void TempFile::seal() {
  if (temp_.empty()) fail(ErrorCategory::internal, target_.string() + ": seal of a scratch file");
  flush();
  // mkstemp creates files 0600; give them the usual permissions (umask applies).
  if (::fchmod(fd_, 0666 & ~process_umask()) != 0) fail_errno("cannot set permissions");
  if (::fsync(fd_) != 0) fail_errno("cannot flush to disk");
  const int fd = std::exchange(fd_, -1);
  std::vector<char>().swap(buffer_);
  if (::close(fd) != 0) fail_errno("cannot close");
}

void TempFile::publish() {
  if (fd_ >= 0 || temp_.empty()) {
    fail(ErrorCategory::internal, target_.string() + ": publish of a file not sealed");
  }
  if (::rename(temp_.c_str(), target_.c_str()) != 0) fail_errno("cannot rename into place");
  temp_.clear();
  untrack_temporary(std::exchange(slot_, -1));
}

void Publication::add(std::unique_ptr<TempFile> sealed) {
  files_.push_back(std::move(sealed));
}

void Publication::add(const fs::path& path, std::string_view bytes) {
  auto file = std::make_unique<TempFile>(path);
  file->write(bytes);
  file->seal();
  add(std::move(file));
}

void Publication::remove(const fs::path& path) {
  removals_.push_back(path);
}

std::vector<fs::path> Publication::targets() const {
  std::vector<fs::path> out;
  for (const auto& f : files_) out.push_back(f->target());
  return out;
}

void Publication::commit() {
  const SignalsHeld hold;
  // Folders in a fixed order, so two runs publishing into the same folders cannot deadlock.
  std::set<fs::path> folders;
  for (const auto& f : files_) {
    folders.insert(f->target().has_parent_path() ? f->target().parent_path() : fs::path("."));
  }
  for (const fs::path& r : removals_) folders.insert(r.has_parent_path() ? r.parent_path() : fs::path("."));
  std::vector<std::unique_ptr<FolderLock>> locks;
  for (const fs::path& folder : folders) locks.push_back(std::make_unique<FolderLock>(folder));
  // The files to remove are set aside after the targets, the same way: put back on failure.
  std::vector<fs::path> names;
  for (const auto& f : files_) names.push_back(f->target());
  names.insert(names.end(), removals_.begin(), removals_.end());
  std::vector<fs::path> earlier(names.size());
  std::size_t aside = 0, published = 0;
  try {
    for (; aside < names.size(); ++aside) earlier[aside] = set_aside(names[aside]);
    for (; published < files_.size(); ++published) files_[published]->publish();
  } catch (...) {
    for (std::size_t k = 0; k < published; ++k) ::unlink(files_[k]->target().c_str());
    for (std::size_t k = 0; k < aside; ++k) {
      if (!earlier[k].empty()) std::rename(earlier[k].c_str(), names[k].c_str());
    }
    throw;
  }
  for (const fs::path& old : earlier) {
    if (!old.empty()) ::unlink(old.c_str());
  }
  files_.clear();
  removals_.clear();
}

}  // namespace sweep::io
