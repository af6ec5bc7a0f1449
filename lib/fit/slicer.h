#pragma once
// Plane slices of a mesh, as plain point lists. One of two doors to CGAL (with surface_distance.h)
// (Polygon_mesh_slicer over one AABB tree of the mesh's edges, built once in the constructor and
// shared by every slice: ~22 ms to build for 24k vertices, then ~0.4 ms a slice).
//
// Floating-point environment: CGAL's interval arithmetic raises overflow and invalid flags by
// design. The constructor and slice() save the caller's environment, run with every exception
// masked, and restore it afterwards, so they are safe under callers that trap FP exceptions.
#include <cstdint>
#include <memory>
#include <vector>

#include "sweep/core/mesh.h"

namespace sweep::fit {

// One connected piece of a slice. Closed loops do not repeat their first point at the end.
struct SlicePolyline {
  std::vector<Vec3> points;
  bool closed = false;
};

class MeshSlicer {
 public:
  // Slices the surface of `triangles` over `points` (indices into it, three a triangle). Vertices
  // a seam splits (the same position twice, as exporters write UV and normal seams) must come
  // welded, as Topology::triangles has them: a slice does not pass from one copy to the other, so
  // across an unwelded seam it comes out as an open polyline, a hole that is not in the surface.
  // Faces the halfedge structure cannot take as they are (non-manifold vertices or edges,
  // inconsistent orientation) are repaired by duplicating vertices; that changes nothing for
  // slicing, which only returns positions.
  MeshSlicer(const std::vector<Vec3>& points, const std::vector<std::uint32_t>& triangles);
  // The mesh's polygons fanned into triangles over its vertices welded by position
  // (build_topology).
  explicit MeshSlicer(const Mesh& mesh);
  ~MeshSlicer();
  MeshSlicer(MeshSlicer&&) noexcept;
  MeshSlicer& operator=(MeshSlicer&&) noexcept;
  MeshSlicer(const MeshSlicer&) = delete;
  MeshSlicer& operator=(const MeshSlicer&) = delete;

  // The intersection of the mesh with the plane through `point` with normal `normal` (any
  // nonzero length). Thread-safe: slices share the tree read-only.
  std::vector<SlicePolyline> slice(const Vec3& point, const Vec3& normal) const;

  // How many triangles needed the repair above (0 for a clean manifold mesh).
  std::size_t repaired_face_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sweep::fit
