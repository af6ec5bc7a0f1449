#include "sweep/sim/collider.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sweep::sim {
namespace {

// The direction of `v`, or `fallback` where it has none (a point exactly on a sphere's centre or
// a capsule's segment: every direction leads out equally far).
Vec3 direction_or(const Vec3& v, const Vec3& fallback) {
  const double n = v.norm();
  return n > 0 ? Vec3(v / n) : fallback;
}

}  // namespace

const char* shape_name(ColliderShape shape) {
  switch (shape) {
    case ColliderShape::sphere:
      return "sphere";
    case ColliderShape::capsule:
      return "capsule";
    case ColliderShape::box:
      return "box";
    case ColliderShape::plane:
      return "plane";
  }
  return "?";
}

Collider Collider::sphere(const Vec3& center, double radius) {
  Collider c;
  c.shape = ColliderShape::sphere;
  c.pose.center = center;
  c.radius = radius;
  return c;
}

Collider Collider::capsule(const Vec3& a, const Vec3& b, double radius) {
  Collider c;
  c.shape = ColliderShape::capsule;
  c.pose.center = 0.5 * (a + b);
  // Ends a rounding apart make a sphere: FromTwoVectors would square a vanishing length.
  if ((b - a).norm() > 1e-12 * std::max({1.0, a.norm(), b.norm()})) {
    c.pose.rotation = Quat::FromTwoVectors(Vec3::UnitZ(), b - a);
    c.half_length = 0.5 * (b - a).norm();
  }
  c.radius = radius;
  return c;
}

Collider Collider::box(const Vec3& center, const Vec3& half_size, const Quat& rotation) {
  Collider c;
  c.shape = ColliderShape::box;
  c.pose = Frame{rotation, center};
  c.half_size = half_size;
  return c;
}

Collider Collider::plane(const Vec3& point, const Vec3& normal) {
  Collider c;
  c.shape = ColliderShape::plane;
  c.pose.center = point;
  // No normal, no plane: a zero rotation, which check() refuses.
  c.pose.rotation = normal.norm() > 0 ? Quat::FromTwoVectors(Vec3::UnitZ(), normal) : Quat(0, 0, 0, 0);
  return c;
}

double Collider::local_distance(const Vec3& x, Vec3* outward) const {
  switch (shape) {
    case ColliderShape::sphere:
      *outward = direction_or(x, Vec3::UnitZ());
      return x.norm() - radius;
    case ColliderShape::capsule: {
      const Vec3 off = x - Vec3(0, 0, std::clamp(x.z(), -half_length, half_length));
      *outward = direction_or(off, Vec3::UnitX());
      return off.norm() - radius;
    }
    case ColliderShape::box: {
      const Vec3 q = x.cwiseAbs() - half_size;
      const Vec3 sign(x.x() < 0 ? -1.0 : 1.0, x.y() < 0 ? -1.0 : 1.0, x.z() < 0 ? -1.0 : 1.0);
      const Vec3 out = q.cwiseMax(0.0);
      if (out != Vec3::Zero()) {
        *outward = sign.cwiseProduct(out / out.norm());
        return out.norm();
      }
      // Inside: out through the nearest face.
      int a = 0;
      if (q.y() > q[a]) a = 1;
      if (q.z() > q[a]) a = 2;
      *outward = Vec3::Zero();
      (*outward)[a] = sign[a];
      return q[a];
    }
    case ColliderShape::plane:
      *outward = Vec3::UnitZ();
      return x.z();
  }
  return 0;
}

double Collider::bounding_radius() const {
  switch (shape) {
    case ColliderShape::sphere:
      return radius;
    case ColliderShape::capsule:
      return half_length + radius;
    case ColliderShape::box:
      return half_size.norm();
    case ColliderShape::plane:
      return std::numeric_limits<double>::infinity();
  }
  return 0;
}

std::string Collider::check() const {
  if (!is_finite(pose.center) || !is_finite(pose.rotation.coeffs())) return "its place is not finite";
  if (std::abs(pose.rotation.norm() - 1) > 1e-9)
    return shape == ColliderShape::plane ? "its normal must not be zero" : "its rotation must be a unit quaternion";
  if (!(margin >= 0) || !std::isfinite(margin)) return "its margin must be a finite number ≥ 0";
  if (!(friction >= 0) || !std::isfinite(friction)) return "its friction must be a finite number ≥ 0";
  switch (shape) {
    case ColliderShape::sphere:
    case ColliderShape::capsule:
      if (!(radius > 0) || !std::isfinite(radius)) return "its radius must be a positive number";
      break;
    case ColliderShape::box:
      if (!(half_size.minCoeff() > 0) || !is_finite(half_size))
        return "every half size must be a positive number (a plate is a thin box, not a flat one)";
      break;
    case ColliderShape::plane:
      break;
  }
  return "";
}

}  // namespace sweep::sim
