#pragma once
// Outputs are written to a temporary file beside the target and renamed into place only when
// complete, so a failure or a kill never leaves a half-written file under the final name.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace sweep::io {

// A file being written: a temporary beside `target`, buffered, renamed onto `target` by commit().
// The temporary is named ".<target name>.<tool>-<pid>.tmp-XXXXXX" (a name too long for that keeps
// its first 200 bytes and a hash), so any name the file system takes can be written, and a signal
// removes it (io/interrupt.h). The first temporary a run creates in a folder removes the ones there
// that runs of these tools left when they were killed (their process is gone), with a note.
// A target that exists and is not a regular file (a FIFO, a device, a symlink, a folder) is
// refused, Error(output): renaming onto it would replace the node, not write through it.
// A scratch file (scratch = true) is unlinked as soon as it is created, so it never has a name
// and vanishes with its descriptor; it is read back with copy_to(). Until commit(), destruction
// or discard() removes the temporary. Every failure is Error(output, "<target>: ...").
class TempFile {
 public:
  explicit TempFile(std::filesystem::path target, bool scratch = false);
  ~TempFile();
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  void write(const void* data, std::size_t size);
  void write(std::string_view bytes) { write(bytes.data(), bytes.size()); }
  // Bytes written so far.
  std::uint64_t size() const { return size_; }
  // Appends this (scratch) file's whole content to `out`.
  void copy_to(TempFile& out);
  // Flushes, gives the usual permissions, syncs, closes and renames onto the target: seal() does
  // all but the rename, publish() the rename (a sealed temporary holds no descriptor).
  void commit();
  void seal();
  void publish();
  // Removes the temporary (no-op once committed or discarded). Never throws.
  void discard() noexcept;
  const std::filesystem::path& target() const { return target_; }

 private:
  void flush();
  [[noreturn]] void fail_errno(const char* what);

  std::filesystem::path target_;
  std::string temp_;  // the temporary's name; empty for a scratch file
  int slot_ = -1;     // its slot among the temporaries a signal removes (io/interrupt.h)
  int fd_ = -1;
  std::vector<char> buffer_;
  std::uint64_t size_ = 0;
};

// Sealed temporaries that go into place together: a run with several outputs (a bake to .glb and
// .pc2 with its report, a rig with its report and preview) publishes none of them unless it can
// publish all. commit(): with SIGINT, SIGTERM and SIGHUP held off (they wait until it returns) and
// each destination folder locked (FolderLock), every earlier file under a target name is set aside,
// then every temporary renamed into place; if any step fails, what was renamed is removed and the
// earlier files are put back, and the error is raised. Destroyed uncommitted, it removes them all.
class Publication {
 public:
  Publication() = default;
  Publication(const Publication&) = delete;
  Publication& operator=(const Publication&) = delete;
  ~Publication() = default;  // the files' own destructors remove uncommitted temporaries

  // A sealed (TempFile::seal) named temporary.
  void add(std::unique_ptr<TempFile> sealed);
  // `bytes` written to a sealed temporary for `path`, added.
  void add(const std::filesystem::path& path, std::string_view bytes);
  // A file to remove with the commit (set aside with the earlier files, removed once all are in
  // place, put back if the set cannot be completed): a re-bake's frames past its new end.
  void remove(const std::filesystem::path& path);
  void commit();
  std::vector<std::filesystem::path> targets() const;

 private:
  std::vector<std::unique_ptr<TempFile>> files_;
  std::vector<std::filesystem::path> removals_;
};

// Renames an existing `target` to a hidden unique name beside it and returns that name (empty
// when there was no target), so that a set of files can be replaced all or nothing: put each
// back with std::rename on failure, remove them on success. Error(output) when it cannot.
std::filesystem::path set_aside(const std::filesystem::path& target);

// Removes, once a run per folder, the temporaries in `folder` that these tools' runs left when
// they were killed (named as TempFile names them, their process gone), each with a note(); an
// earlier file such a run had set aside (set_aside) is put back under its name when nothing has
// taken it, else removed.
void remove_stale_temporaries(const std::filesystem::path& folder);

// Holds an exclusive lock on a folder (flock; released when destroyed, or when the process
// dies), so that runs publishing a set of files into it take turns. Error(output) on failure.
class FolderLock {
 public:
  explicit FolderLock(const std::filesystem::path& folder);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

// Writes bytes to path atomically. Throws Error(output) naming the path on any failure; the
// temporary file is removed in that case.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// Fails now, with the message write_file_atomically would give later (Error(output) naming the
// path), when a file cannot be created beside `path` (missing or read-only folder, a file in
// place of the folder). Tools check every output this way before any work, so that an output
// that cannot be written is found before the others are written. Creates and removes a
// temporary; the target itself is not touched.
void check_can_create(const std::filesystem::path& path);

}  // namespace sweep::io
