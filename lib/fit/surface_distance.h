#pragma once
// Point-to-surface and ray-to-surface distances for a triangle soup (CGAL's AABB tree, behind plain arrays): the true
// distance of a point to the nearest point of any triangle.
#include <cstdint>
#include <memory>
#include <vector>

#include "sweep/core/frame.h"

namespace sweep::fit {

class TriangleDistance {
 public:
  // `triangles` holds 3 indices into `points` per triangle; degenerate triangles are skipped.
  TriangleDistance(const std::vector<Vec3>& points, const std::vector<std::uint32_t>& triangles);
  ~TriangleDistance();
  TriangleDistance(const TriangleDistance&) = delete;
  TriangleDistance& operator=(const TriangleDistance&) = delete;

  bool empty() const;
  // Distance from p to the nearest triangle (infinity when there are none). Thread-safe.
  double distance(const Vec3& p) const;
  // Distance from `origin` along the unit `direction` to the first triangle the ray meets
  // (infinity when it meets none). Thread-safe.
  double ray_distance(const Vec3& origin, const Vec3& direction) const;
  // Whether p lies inside a closed surface: the parity of the triangles a ray from p crosses, the
  // majority over three rays in unrelated directions (one ray through an edge counts it twice;
  // three rarely all do). Meaningless for an open surface. Thread-safe.
  bool inside(const Vec3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sweep::fit
