#pragma once
// Colliders: convex shapes the parts may not enter — spheres, capsules, boxes and
// planes — each fixed in the world or carried by the body. A collider is a shape in its own local
// coordinates and a pose (local → world, or local → mesh for one the body carries); the contact
// solver (sim/contact.h) only asks a shape its signed distance and the direction out of it.
//
// Local shapes (all convex, so the signed distance is a convex function of the point, and its
// minimum along a segment is found by a bracketing search):
//   sphere   radius r about the origin
//   capsule  points within r of the segment from (0,0,−h) to (0,0,h)
//   box      |x| ≤ e componentwise
//   plane    z ≤ 0 (the solid side; the free side is z > 0)
#include <string>
#include <vector>

#include "sweep/core/frame.h"

namespace sweep::sim {

enum class ColliderShape { sphere, capsule, box, plane };

struct Collider {
  std::string name;  // for messages: the scene's "name", or "collider N"
  ColliderShape shape = ColliderShape::sphere;
  Frame pose;                     // local → world (or → mesh, when carried by the body)
  bool carried = false;           // moves with the body (a leg), rather than fixed in the world
  double radius = 0;              // sphere, capsule
  double half_length = 0;         // capsule: half the length of its segment
  Vec3 half_size = Vec3::Zero();  // box
  double margin = 0;              // extra clearance the part keeps (mesh units)
  double friction = 0.5;          // Coulomb coefficient against the part's surface

  // A sphere (mesh units), a capsule from `a` to `b`, a box with its rotation, a plane through
  // `point` whose solid side is opposite `normal`.
  static Collider sphere(const Vec3& center, double radius);
  static Collider capsule(const Vec3& a, const Vec3& b, double radius);
  static Collider box(const Vec3& center, const Vec3& half_size, const Quat& rotation = Quat::Identity());
  static Collider plane(const Vec3& point, const Vec3& normal);

  // Signed distance of a local point to the shape (negative inside), and the unit direction out
  // of the shape at its nearest surface point (the gradient of the distance).
  double local_distance(const Vec3& x, Vec3* outward) const;
  // A radius about the local origin that holds the whole shape; infinite for a plane.
  double bounding_radius() const;
  // What is wrong with the shape ("" if nothing): non-positive sizes, a zero normal.
  std::string check() const;
};

const char* shape_name(ColliderShape shape);

}  // namespace sweep::sim
