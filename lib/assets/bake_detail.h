#pragma once
// Private to the bake writers (bake*.cpp): the begin/frame/finish protocol every writer shares.
// The files themselves are each writer's: io::TempFile temporaries (io/atomic_file.h), sealed and
// handed to an io::Publication in complete(), discarded in abandon().
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sweep/assets/bake.h"
#include "sweep/io/atomic_file.h"

namespace sweep::assets::detail {

// The largest coordinate a bake accepts, rest or baked. Beyond it a float32 delta or sum could
// overflow; a simulated vertex this far out has run away, so frame() reports it as diverged.
constexpr float kMaxBakeCoordinate = 1e30f;

// The largest .glb: its header's length field is 32 bits.
constexpr std::uint64_t kGlbMaxBytes = 0xFFFFFFFFull;

// The body's pose each frame as glTF animation keys: translations (x y z) and rotations (x y z w),
// each rotation kept on the side of the one before, so that LINEAR (slerp) between two keys takes
// the short way.
struct BodyKeys {
  std::vector<float> translations, rotations;
  void add(const BodyPose& pose);
};

// What begin() establishes and frame() checks, the same for every format: the protocol (frames in
// order, all of them), positions finite and in range, static vertices at rest. A writer derives
// from it and implements the start/write/complete/abandon hooks; the base closes the writer and
// calls abandon() (which must remove every temporary) whenever anything throws.
class BakeWriterBase : public BakeWriter {
 public:
  explicit BakeWriterBase(std::filesystem::path out);

  void begin(const Mesh& rest, const BakeInfo& info) final;
  using BakeWriter::frame;
  void frame(int index, std::span<const Eigen::Vector3f> positions, const BodyPose& body) final;
  void finish() final;
  void finish_into(io::Publication& outputs) final;
  std::uint64_t estimated_bytes() const final { return estimate_; }

 protected:
  virtual void start(const Mesh& rest) = 0;
  // Called with positions already checked, in the body's frame (see world_positions()).
  virtual void write_frame(int index, std::span<const Eigen::Vector3f> positions) = 0;
  // The body's pose of the frame being written (identity unless info().body_moves).
  const BodyPose& body_pose() const { return body_; }
  // `positions` as the .pc2 and .obj writers store them: moved by the body's pose into world
  // space, then into the mesh's local space (BakeSource::to_world's inverse). `positions` itself
  // when neither applies; else a scratch buffer, valid until the next call. A vertex at rest in a
  // frame with no body motion is its local rest position (stored_rest()), the same every frame.
  std::span<const Eigen::Vector3f> stored_positions(std::span<const Eigen::Vector3f> positions);
  // The rest positions as stored_positions stores them (rest() when there is no local space).
  const std::vector<Eigen::Vector3f>& stored_rest() const { return local_ ? stored_rest_ : rest_; }
  // Seals what is left and hands every temporary to `outputs`.
  virtual void complete(io::Publication& outputs) = 0;
  virtual void abandon() noexcept = 0;

  const std::filesystem::path& out() const { return out_; }
  const BakeInfo& info() const { return info_; }
  // Rest positions as float32.
  const std::vector<Eigen::Vector3f>& rest() const { return rest_; }
  // Ascending, unique vertices that may move (every vertex when none were listed).
  const std::vector<std::uint32_t>& animated() const { return animated_; }
  // start() records its estimate of the files' size (estimated_bytes()).
  void set_estimate(std::uint64_t bytes) { estimate_ = bytes; }
  bool all_animated() const { return animated_.size() == rest_.size(); }

 private:
  enum class State { created, begun, finished, closed };
  void check_frame(int index, std::span<const Eigen::Vector3f> positions) const;
  // `p` as float32, or Error(diverged) naming vertex `v` when it leaves the bake's range.
  Eigen::Vector3f stored(const Eigen::Vector3d& p, std::size_t v) const;
  template <typename F>
  void guarded(F&& body);

  std::filesystem::path out_;
  BakeInfo info_;
  std::vector<Eigen::Vector3f> rest_;
  std::vector<std::uint32_t> animated_;
  State state_ = State::created;
  int next_frame_ = 0;
  std::uint64_t estimate_ = 0;
  BodyPose body_;
  std::vector<Eigen::Vector3f> world_;
  bool local_ = false;  // the mesh has a local space other than world
  Eigen::Affine3d to_local_ = Eigen::Affine3d::Identity();
  std::vector<Eigen::Vector3f> stored_rest_;  // rest in local space, from the double positions
};

}  // namespace sweep::assets::detail
