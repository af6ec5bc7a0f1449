#pragma once
// A rigid frame M = [R | c]: maps local coordinates to world, x_world = R x_local + c.
// R is kept as a unit quaternion so that interpolation (slerp) and composition stay orthonormal.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace sweep {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

// Whether every coefficient of `v` is finite, tested one by one: Eigen's allFinite() computes
// x - x, which raises FE_INVALID on an infinity (the tests trap it). For any data that could hold
// an infinity (a file's, a user's, a solver's result).
template <typename Derived>
bool is_finite(const Eigen::MatrixBase<Derived>& v) {
  for (Eigen::Index c = 0; c < v.cols(); ++c) {
    for (Eigen::Index r = 0; r < v.rows(); ++r) {
      if (!std::isfinite(v(r, c))) return false;
    }
  }
  return true;
}

struct Frame {
  Quat rotation = Quat::Identity();
  Vec3 center = Vec3::Zero();

  Mat3 matrix() const { return rotation.toRotationMatrix(); }
  Vec3 axis() const { return rotation * Vec3::UnitZ(); }  // the sweep direction at this frame
  Vec3 to_world(const Vec3& local) const { return rotation * local + center; }
  Vec3 to_local(const Vec3& world) const { return rotation.conjugate() * (world - center); }

  Frame operator*(const Frame& b) const {  // this ∘ b
    return {(rotation * b.rotation).normalized(), rotation * b.center + center};
  }
  Frame inverse() const {
    const Quat qi = rotation.conjugate();
    return {qi, -(qi * center)};
  }
};

// [a]×, the cross-product matrix: skew(a) b = a × b.
inline Mat3 skew(const Vec3& a) {
  Mat3 s;
  s << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return s;
}

// Rotation by the rotation vector phi (axis phi/|phi|, angle |phi|); exact for every angle.
Quat rotation_from_vector(const Vec3& phi);

}  // namespace sweep
