#pragma once
// Which vertices a sweep drives (DESIGN.md §2.4): the region of the surface on the tip side of the
// root plane that is reached from the tip without crossing that plane. Not a half-space: a plane
// through a tail's root also cuts the hind legs, which the flood never reaches because it would
// have to pass behind the plane to get there. Plain C++ (sweep-bind uses it too).
#include <cstdint>
#include <vector>

#include "core/frame.h"
#include "core/mesh.h"

namespace sweep::fit {

// Index of the vertex nearest to p (the lowest index among equals). The mesh must have vertices.
std::uint32_t nearest_vertex(const Mesh& mesh, const Vec3& p);

// Vertex neighbours over the mesh's polygon edges, in compressed rows: vertex v's neighbours are
// neighbours[offsets[v] .. offsets[v+1]), sorted and unique.
struct VertexAdjacency {
  std::vector<std::uint32_t> offsets;
  std::vector<std::uint32_t> neighbours;
};
VertexAdjacency vertex_adjacency(const Mesh& mesh);

// The part's vertices, sorted: a flood over mesh edges from the vertex nearest to `tip`, never
// entering a vertex behind the plane through root_plane.center with normal root_plane.axis()
// (signed distance < 0). Throws Error(bad_input) when the vertex nearest to the tip lies behind
// that plane (the tip is on the body's side of the root).
std::vector<std::uint32_t> select_part(const Mesh& mesh, const Frame& root_plane, const Vec3& tip);
std::vector<std::uint32_t> select_part(const Mesh& mesh, const VertexAdjacency& adjacency,
                                       const Frame& root_plane, const Vec3& tip);

}  // namespace sweep::fit
