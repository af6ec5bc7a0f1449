// The parts every bake writer shares: choosing a writer by extension, the .obj sequence's file
// names, and the begin/frame/finish protocol with its checks (see bake.h and bake_detail.h). No
// file is opened here: each writer writes its own temporaries (io::TempFile, io/atomic_file.h) and
// hands them, sealed, to an io::Publication (finish_into: the run's; finish: one of its own), which
// renames them into place together.
#include "sweep/assets/bake.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "sweep/assets/bake_detail.h"
#include "sweep/core/error.h"
#include "sweep/core/frame.h"
#include "sweep/core/text.h"

namespace sweep::assets {
namespace fs = std::filesystem;

bool is_bake_extension(const fs::path& out) {
  const std::string ext = lower_extension(out);
  return ext == "glb" || ext == "pc2" || ext == "obj";
}

std::unique_ptr<BakeWriter> make_bake_writer(const fs::path& out) {
  const std::string ext = lower_extension(out);
  if (ext == "glb") return make_gltf_bake_writer(out);
  if (ext == "pc2") return make_pc2_bake_writer(out);
  if (ext == "obj") return make_obj_bake_writer(out);
  fail(ErrorCategory::unsupported,
       out.string() + ": cannot bake to '" + out.extension().string() +
           "' files; the output's extension must be .glb (glTF 2.0), .pc2 (point cache) or .obj "
           "(OBJ sequence)");
}

fs::path obj_sequence_path(const fs::path& out, int index, int frame_count) {
  const std::size_t width = std::max<std::size_t>(4, std::to_string(std::max(frame_count - 1, 0)).size());
  std::string digits = std::to_string(index);
  if (digits.size() < width) digits.insert(0, width - digits.size(), '0');
  fs::path name = out.stem();
  name += "_" + digits + out.extension().string();
  return out.has_parent_path() ? out.parent_path() / name : name;
}

std::vector<fs::path> bake_files(const fs::path& out, int frame_count) {
  if (lower_extension(out) != "obj") return {out};
  std::vector<fs::path> files;
  for (int k = 0; k < frame_count; ++k) files.push_back(obj_sequence_path(out, k, frame_count));
  return files;
}

namespace detail {

// ---------------------------------------------------------------------------------------------
// BakeWriterBase

BakeWriterBase::BakeWriterBase(fs::path out) : out_(std::move(out)) {}

template <typename F>
void BakeWriterBase::guarded(F&& body) {
  try {
    body();
  } catch (...) {
    state_ = State::closed;
    abandon();
    throw;
  }
}

void BakeWriterBase::begin(const Mesh& rest, const BakeInfo& info) {
  const std::string where = out_.string() + ": ";
  if (state_ != State::created) {
    fail(ErrorCategory::internal, where + "begin() called twice or after an error");
  }
  guarded([&] {
    if (info.frame_count < 1) {
      fail(ErrorCategory::internal, where + "a bake needs at least one frame, got " + std::to_string(info.frame_count));
    }
    if (!std::isfinite(info.fps) || info.fps <= 0) {
      fail(ErrorCategory::internal, where + "frames per second must be positive and finite");
    }
    const std::size_t n = rest.vertex_count();
    if (n == 0) fail(ErrorCategory::bad_input, where + "the mesh has no vertices");
    if (n > std::uint64_t{INT32_MAX}) {
      fail(ErrorCategory::unsupported, where + "a bake holds at most 2^31-1 vertices");
    }
    if (rest.face_offsets.empty() || rest.face_offsets.front() != 0 ||
        rest.face_offsets.back() != rest.face_vertices.size() ||
        !std::is_sorted(rest.face_offsets.begin(), rest.face_offsets.end())) {
      fail(ErrorCategory::internal, where + "the mesh's face offsets are inconsistent");
    }
    for (std::size_t k = 0; k < rest.face_vertices.size(); ++k) {
      if (rest.face_vertices[k] >= n) {
        const auto face =
            std::upper_bound(rest.face_offsets.begin(), rest.face_offsets.end(), static_cast<std::uint32_t>(k)) -
            rest.face_offsets.begin() - 1;
        fail(ErrorCategory::bad_input, where + "face " + std::to_string(face) + " uses vertex " +
                                           std::to_string(rest.face_vertices[k]) + " but the mesh has " +
                                           std::to_string(n) + " vertices");
      }
    }
    info_ = info;
    rest_.resize(n);
    for (std::size_t v = 0; v < n; ++v) {
      const Vec3& p = rest.positions[v];
      for (int c = 0; c < 3; ++c) {
        if (!std::islessequal(std::abs(p[c]), double{kMaxBakeCoordinate})) {  // quiet on NaN
          fail(ErrorCategory::bad_input, where + "rest vertex " + std::to_string(v) + ": coordinate " +
                                             (std::isfinite(p[c]) ? "beyond ±1e30" : "not finite") +
                                             "; a bake stores float32 positions");
        }
        rest_[v][c] = static_cast<float>(p[c]);
      }
    }
    if (info.animated_vertices) {
      animated_ = *info.animated_vertices;
      std::sort(animated_.begin(), animated_.end());
      animated_.erase(std::unique(animated_.begin(), animated_.end()), animated_.end());
      if (!animated_.empty() && animated_.back() >= n) {
        fail(ErrorCategory::internal, where + "animated vertex " + std::to_string(animated_.back()) +
                                          " is not in the mesh (" + std::to_string(n) + " vertices)");
      }
    } else {
      animated_.resize(n);
      for (std::size_t v = 0; v < n; ++v) animated_[v] = static_cast<std::uint32_t>(v);
    }
    info_.animated_vertices.reset();  // animated_ is the one copy
    const Eigen::Affine3d& to_world = info.source.to_world;
    local_ = !to_world.matrix().isIdentity(0.0);
    if (local_) {
      if (!(std::abs(to_world.linear().determinant()) > 0) || !is_finite(to_world.matrix())) {
        fail(ErrorCategory::bad_input, where +
                                           "the mesh's node transform is singular or not finite, so its "
                                           "local space cannot be had");
      }
      to_local_ = to_world.inverse();
      stored_rest_.resize(n);
      for (std::size_t v = 0; v < n; ++v) stored_rest_[v] = stored(to_local_ * rest.positions[v], v);
    }
    state_ = State::begun;
    start(rest);
  });
}

void BakeWriterBase::check_frame(int index, std::span<const Eigen::Vector3f> positions) const {
  const std::string where = out_.string() + ": ";
  if (index != next_frame_ || index >= info_.frame_count) {
    fail(ErrorCategory::internal, where + "frame " + std::to_string(index) + " given, but frame " +
                                      std::to_string(next_frame_) + " of " + std::to_string(info_.frame_count) +
                                      " was expected (frames come in order, from 0)");
  }
  const std::size_t n = rest_.size();
  if (positions.size() != n) {
    fail(ErrorCategory::internal, where + "frame " + std::to_string(index) + " has " +
                                      std::to_string(positions.size()) + " positions, the mesh " + std::to_string(n) +
                                      " vertices");
  }
  // One pass with no branch per vertex, find the culprit only on failure. islessequal is false
  // for NaN without raising FE_INVALID (callers may run with floating-point traps on).
  auto in_range = [](const Eigen::Vector3f& p) {
    // int, so that & (no branch) is not clang's -Wbitwise-instead-of-logical.
    return (int{std::islessequal(std::abs(p.x()), kMaxBakeCoordinate)} &
            int{std::islessequal(std::abs(p.y()), kMaxBakeCoordinate)} &
            int{std::islessequal(std::abs(p.z()), kMaxBakeCoordinate)}) != 0;
  };
  bool all_in_range = true;
  for (const Eigen::Vector3f& p : positions) all_in_range &= in_range(p);
  if (!all_in_range) {
    for (std::size_t v = 0; v < n; ++v) {
      const Eigen::Vector3f& p = positions[v];
      if (!in_range(p)) {
        const bool finite = is_finite(p);
        fail(ErrorCategory::diverged,
             where + "frame " + std::to_string(index) + ", vertex " + std::to_string(v) + ": position " +
                 format_exact_point(p) +
                 (finite ? " is beyond ±1e30: the simulation ran away" : " is not finite: the simulation diverged") +
                 "; nothing was written");
      }
    }
  }
  if (!all_animated()) {
    std::size_t a = 0;
    for (std::size_t v = 0; v < n; ++v) {
      if (a < animated_.size() && animated_[a] == v) {
        ++a;
        continue;
      }
      if (positions[v] != rest_[v]) {
        fail(ErrorCategory::internal, where + "frame " + std::to_string(index) + ": vertex " + std::to_string(v) +
                                          " moved to " + format_exact_point(positions[v]) + " from " +
                                          format_exact_point(rest_[v]) + " but is not in the animated-vertex list");
      }
    }
  }
}

void BakeWriterBase::frame(int index, std::span<const Eigen::Vector3f> positions, const BodyPose& body) {
  if (state_ != State::begun) {
    fail(ErrorCategory::internal, out_.string() + ": frame() outside begin() .. finish(), or after an error");
  }
  guarded([&] {
    check_frame(index, positions);
    const bool identity = body.rotation.coeffs() == Eigen::Quaterniond::Identity().coeffs() &&
                          body.translation == Eigen::Vector3d::Zero();
    if (!info_.body_moves && !identity) {
      fail(ErrorCategory::internal, out_.string() + ": a body pose for a bake whose body does not move");
    }
    if (!is_finite(body.rotation.coeffs()) || !is_finite(body.translation) ||
        body.translation.cwiseAbs().maxCoeff() > kMaxBakeCoordinate) {
      fail(ErrorCategory::diverged,
           out_.string() + ": frame " + std::to_string(index) + ": the body's pose is not finite");
    }
    body_ = body;
    write_frame(index, positions);
    ++next_frame_;
  });
}

Eigen::Vector3f BakeWriterBase::stored(const Eigen::Vector3d& p, std::size_t v) const {
  if (!(p.cwiseAbs().maxCoeff() <= kMaxBakeCoordinate)) {
    fail(ErrorCategory::diverged, out_.string() + ": vertex " + std::to_string(v) +
                                      " moved by the body or into the mesh's local space leaves the float range");
  }
  return p.cast<float>();
}

std::span<const Eigen::Vector3f> BakeWriterBase::stored_positions(std::span<const Eigen::Vector3f> positions) {
  if (!info_.body_moves && !local_) return positions;
  world_.resize(positions.size());
  const Eigen::Matrix3d r = body_.rotation.normalized().toRotationMatrix();
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (!info_.body_moves && positions[v] == rest_[v]) {
      world_[v] = stored_rest_[v];  // at rest: the same local numbers every frame
      continue;
    }
    Eigen::Vector3d w = positions[v].cast<double>();
    if (info_.body_moves) w = r * w + body_.translation;
    world_[v] = stored(local_ ? Eigen::Vector3d(to_local_ * w) : w, v);
  }
  return world_;
}

void BakeWriterBase::finish() {
  io::Publication outputs;
  finish_into(outputs);
  outputs.commit();
}

void BakeWriterBase::finish_into(io::Publication& outputs) {
  if (state_ != State::begun) {
    fail(ErrorCategory::internal, out_.string() + ": finish() without begin(), twice, or after an error");
  }
  guarded([&] {
    if (next_frame_ != info_.frame_count) {
      fail(ErrorCategory::internal, out_.string() + ": finish() after " + std::to_string(next_frame_) + " of " +
                                        std::to_string(info_.frame_count) + " frames");
    }
    complete(outputs);
    state_ = State::finished;
  });
}

void BodyKeys::add(const BodyPose& pose) {
  Eigen::Quaterniond q = pose.rotation.normalized();
  if (!rotations.empty()) {
    const std::size_t at = rotations.size() - 4;
    const double dot =
        q.x() * rotations[at] + q.y() * rotations[at + 1] + q.z() * rotations[at + 2] + q.w() * rotations[at + 3];
    if (dot < 0) q.coeffs() *= -1;
  }
  for (int c = 0; c < 3; ++c) translations.push_back(static_cast<float>(pose.translation[c]));
  for (const double c : {q.x(), q.y(), q.z(), q.w()}) rotations.push_back(static_cast<float>(c));
}

}  // namespace detail
}  // namespace sweep::assets
