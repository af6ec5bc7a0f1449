#pragma once
// Distance over the surface, and the loops where it takes a given value (level sets). Rings of
// equal distance from a part's tip run around the part whatever its curl: their
// centroids are axis points, and their size shows where the part meets the body.
#include <cstdint>
#include <span>
#include <vector>

#include "sweep/core/topology.h"

namespace sweep::fit {

// Distance over the surface from the nearest of `sources` (vertex indices), for every vertex
// (infinity where the surface does not reach). Dijkstra's order, with each vertex updated across
// the triangles whose other two vertices are known (the planar unfolding of the front, as in fast
// marching) as well as along edges: edge paths alone overestimate by up to ~8% on regular meshes
// and make level sets jagged; the triangle update brings that to about 1%.
std::vector<double> surface_distances(const Mesh& mesh, const Topology& topology,
                                      std::span<const std::uint32_t> sources);

// A connected piece of a level set.
struct LevelLoop {
  std::vector<Vec3> points;         // in walking order; closed loops do not repeat the first point
  bool closed = false;              // false: the level set runs into a hole of the mesh
  Vec3 centroid = Vec3::Zero();     // length-weighted centroid of the polyline
  double length = 0;                // mesh units
  Vec3 vector_area = Vec3::Zero();  // ½ Σ pᵢ × pᵢ₊₁ about the centroid (closed by the gap)
  double radius() const;            // √(|vector_area| / π): the size of a ring around a tube
};

// Level sets of a distance field at many values: triangles are bucketed once by the levels
// they span, so each level costs only the triangles it crosses.
class LevelSets {
 public:
  // Levels spacing·1, spacing·2, ... up to `max_level`.
  LevelSets(const Mesh& mesh, const Topology& topology, const std::vector<double>& distance, double spacing,
            double max_level);
  int level_count() const { return static_cast<int>(buckets_.offsets.size()) - 1; }
  double level(int k) const { return spacing_ * (k + 1); }
  // The loops of level k, longest first.
  std::vector<LevelLoop> loops(int k) const;

 private:
  const Mesh& mesh_;
  const Topology& topology_;
  const std::vector<double>& distance_;
  double spacing_;
  VertexAdjacency buckets_;  // row k: the triangles that level k crosses
};

}  // namespace sweep::fit
