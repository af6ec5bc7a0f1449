#pragma once
// A run that reads a file, works, and writes it back (sweep-fit adding a sweep to a rig) must not
// overlap another doing the same, or the second to write drops what the first added. UpdateLock
// holds an exclusive flock on a hidden lock file beside the target, ".<name>.lock", from before the
// read to after the write; a second run waits for it. The lock file is removed when the lock is
// released (and by a signal's cleanup, as a temporary); a run that finds it removed or replaced
// after taking the lock takes the new one, so two runs never hold locks on different files.
#include <filesystem>

namespace sweep::tools {

class UpdateLock {
 public:
  // Blocks until the lock is held. Error(output) naming the target when the lock file cannot be
  // made (a missing or read-only folder: the target could not be written either).
  explicit UpdateLock(const std::filesystem::path& target);
  ~UpdateLock();
  UpdateLock(const UpdateLock&) = delete;
  UpdateLock& operator=(const UpdateLock&) = delete;

  const std::filesystem::path& lock_file() const { return lock_; }

 private:
  std::filesystem::path lock_;
  int fd_ = -1;
  int slot_ = -1;  // its slot among the files a signal removes (io/interrupt.h)
};

}  // namespace sweep::tools
