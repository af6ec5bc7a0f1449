#pragma once
// Private to the bake writers (bake*.cpp): temporary files and the protocol every writer shares.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "io/bake.h"

namespace sweep::io::detail {

// The largest coordinate a bake accepts, rest or baked. Beyond it a float32 delta or sum could
// overflow; a simulated vertex this far out has run away, so frame() reports it as diverged.
constexpr float kMaxBakeCoordinate = 1e30f;

// A file being written: a temporary beside `target`, buffered, renamed onto `target` by commit().
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
  int fd_ = -1;
  std::vector<char> buffer_;
  std::uint64_t size_ = 0;
};

// What begin() establishes and frame() checks, the same for every format: the protocol (frames in
// order, all of them), positions finite and in range, static vertices at rest. A writer derives
// from it and implements the start/write/complete/abandon hooks; the base closes the writer and
// calls abandon() (which must remove every temporary) whenever anything throws.
class BakeWriterBase : public BakeWriter {
 public:
  explicit BakeWriterBase(std::filesystem::path out);

  void begin(const Mesh& rest, const BakeInfo& info) final;
  void frame(int index, std::span<const Eigen::Vector3f> positions) final;
  void finish() final;

 protected:
  virtual void start(const Mesh& rest) = 0;
  // Called with positions already checked.
  virtual void write_frame(int index, std::span<const Eigen::Vector3f> positions) = 0;
  virtual void complete() = 0;
  virtual void abandon() noexcept = 0;

  const std::filesystem::path& out() const { return out_; }
  const BakeInfo& info() const { return info_; }
  // Rest positions as float32.
  const std::vector<Eigen::Vector3f>& rest() const { return rest_; }
  // Ascending, unique vertices that may move (every vertex when none were listed).
  const std::vector<std::uint32_t>& animated() const { return animated_; }
  bool all_animated() const { return animated_.size() == rest_.size(); }

 private:
  enum class State { created, begun, finished, closed };
  void check_frame(int index, std::span<const Eigen::Vector3f> positions) const;
  template <typename F>
  void guarded(F&& body);

  std::filesystem::path out_;
  BakeInfo info_;
  std::vector<Eigen::Vector3f> rest_;
  std::vector<std::uint32_t> animated_;
  State state_ = State::created;
  int next_frame_ = 0;
};

// "1.5", "-0", "nan": shortest round-trippable text of a float32, locale-independent.
void append_float(std::string& out, float value);
void append_uint(std::string& out, std::uint64_t value);

}  // namespace sweep::io::detail
