#pragma once
// The body's motion over time: a keyframed rigid transform of the whole mesh, world =
// rotation · mesh + translation. Keys give a time, a translation (mesh units) and a rotation (unit
// quaternion); between keys:
//  - linear: translation straight from key to key, rotation by slerp — each piece at constant
//    velocity and angular velocity, which jump at the keys (the parts feel those jumps as kicks);
//  - cubic: translation by cubic Hermite pieces with Catmull-Rom tangents, zero at the first and
//    last key (the body starts from rest and comes to rest), rotation the same way on the
//    rotation vector from the first key's rotation (exact for turns about one axis) — velocity and
//    angular velocity continuous, no kicks.
// Before the first key and after the last the body holds still. An empty path is a body at rest.
// A pivot c (mesh coordinates) makes the keys' translation the pivot's world position p, so that
//     world = rotation · (mesh − c) + p
// and the body turns about c, not about the mesh's origin: a glTF node's animation (rotation
// about the node) is then exactly linear pieces (assets/gltf_motion.h). No pivot: c = 0.
#include <vector>

#include "sweep/core/frame.h"

namespace sweep::sim {

enum class BodyInterpolation { linear, cubic };

struct BodyKey {
  double time = 0;
  Vec3 translation = Vec3::Zero();
  Quat rotation = Quat::Identity();
};

// The body at one time: its pose, and its motion in the body's own axes (what the parts feel).
struct BodyState {
  Quat rotation = Quat::Identity();
  Vec3 translation = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();              // of the origin, world axes, mesh units/s
  Vec3 acceleration = Vec3::Zero();          // of the origin, body axes, mesh units/s²
  Vec3 angular_velocity = Vec3::Zero();      // body axes, rad/s
  Vec3 angular_acceleration = Vec3::Zero();  // body axes, rad/s²
};

class BodyPath {
 public:
  BodyPath() = default;
  // Keys in strictly increasing time (checked by the scene reader), rotations unit.
  BodyPath(std::vector<BodyKey> keys, BodyInterpolation interpolation, const Vec3& pivot = Vec3::Zero());
  // The same path as BodyPath(keys, interpolation, pivot) would make, made in place: the keys are
  // swapped in and the old ones handed back in `keys`, so a caller rebuilding the path every frame
  // reuses both buffers (a linear path then allocates nothing).
  void swap_keys(std::vector<BodyKey>& keys, BodyInterpolation interpolation, const Vec3& pivot);

  bool empty() const { return keys_.empty(); }
  const std::vector<BodyKey>& keys() const { return keys_; }
  BodyInterpolation interpolation() const { return interpolation_; }
  const Vec3& pivot() const { return pivot_; }

  // Whether the body ever moves (keys that differ).
  bool moves() const { return moves_; }
  BodyState at(double t) const;

  // Linear paths: the keys where velocity jumps (every key of a moving path after time 0: at 0 the
  // scene starts with the body in motion and its parts at rest), and the jump at key `key` (after −
  // before) of the origin's velocity and of the angular velocity, both in body axes.
  // (Into `out`, its capacity reused.)
  void kink_keys(std::vector<std::size_t>& out) const;
  void jump_at(std::size_t key, Vec3& dv, Vec3& dw) const;

  // Whether the parts feel anything during (from, to): acceleration, rotation or a kink.
  bool loads_between(double from, double to) const;

 private:
  void prepare();                     // from keys_, interpolation_ and pivot_: moves_, and the cubic's splines
  std::size_t piece(double t) const;  // keys_[p] ≤ t < keys_[p+1]
  BodyState about_pivot(double t) const;
  std::vector<BodyKey> keys_;
  BodyInterpolation interpolation_ = BodyInterpolation::linear;
  bool moves_ = false;
  Vec3 pivot_ = Vec3::Zero();
  // Cubic: the rotation vectors ρ_k (from the first key's rotation, unwrapped to be continuous)
  // and the tangents of both splines.
  std::vector<Vec3> rho_, rho_tangent_, tangent_;
};

}  // namespace sweep::sim
