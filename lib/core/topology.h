#pragma once
// Mesh topology for the algorithms that walk the surface (part selection, geodesic distance, level
// sets): neighbours over the mesh's edges, built over positions welded for the purpose. Exporters
// split vertices along UV and normal seams; the file's vertices stay as they are (their order and
// count are what a point cache and a binding index), but the walk must not see a seam as a hole.
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "sweep/core/frame.h"
#include "sweep/core/mesh.h"

namespace sweep {

// Index of the vertex nearest to p (the lowest index among equals). The mesh must have vertices.
std::uint32_t nearest_vertex(const Mesh& mesh, const Vec3& p);

// Neighbours in compressed rows: vertex v's neighbours are neighbours[offsets[v] .. offsets[v+1]),
// sorted and unique.
struct VertexAdjacency {
  std::vector<std::uint32_t> offsets;
  std::vector<std::uint32_t> neighbours;
  std::span<const std::uint32_t> of(std::uint32_t v) const {
    return {neighbours.data() + offsets[v], neighbours.data() + offsets[v + 1]};
  }
};

struct Topology {
  // weld[v]: the representative of vertex v, the lowest index with exactly v's position. Every
  // row below is over representatives; a non-representative vertex has no neighbours of its own.
  std::vector<std::uint32_t> weld;
  VertexAdjacency adjacency;
  // Triangles over representatives (polygons fanned from their first vertex), degenerate ones
  // (a repeated representative) left out.
  std::vector<std::uint32_t> triangles;
  // The triangles around each representative, in compressed rows like the adjacency.
  VertexAdjacency vertex_triangles;
  std::size_t welded_count = 0;  // vertices that share their position with a lower index
};
Topology build_topology(const Mesh& mesh);

// Edges (over representatives) that only one triangle uses: the rims of the mesh's holes. A mesh
// with holes is an open surface to the walks over it (rings of surface distance run into them).
std::size_t hole_edge_count(const Topology& topology);

// The rims of the mesh's holes: closed chains of those edges, each in the direction its triangles
// run along it (a patch over the hole runs the other way), at least three vertices long, each
// through a vertex once (two holes touching at a vertex are two rims). A rim whose triangles
// disagree on their orientation does not chain and is left out.
std::vector<std::vector<std::uint32_t>> hole_rims(const Topology& topology);

// Adds `triangles` (three representatives each) to the topology: its triangles, neighbours and
// the rows of triangles around each vertex (fit/hole_patches.h patches holes so).
void add_triangles(Topology& topology, std::span<const std::uint32_t> triangles);

// Neighbours over the mesh's own polygon edges, no welding (what the tests compare against).
VertexAdjacency vertex_adjacency(const Mesh& mesh);

// The part a sweep drives (the paper's §III), sorted: the vertices reached over the surface from the
// vertex nearest to `tip` without crossing the root section — the disc of radius `root_radius`
// around root_plane.center in the plane with normal root_plane.axis(). Walking over an edge that
// passes through that plane inside the disc is crossing it; elsewhere the plane may be crossed,
// so a part that curls back behind its root plane stays whole while the body, reached from the
// part only through the root section, stays out. Throws Error(bad_input) when the tip's nearest
// vertex lies behind the plane inside the disc.
// `within`, when given, bounds the walk geometrically too (select_sweep_part: near the sweep; a
// part that touches another surface mid-length, a trunk against a tusk, must not flood through the
// contact into the head). Each region beyond the bound is then judged: a bridge (it reaches behind
// the root plane, or farther than `protrusion_reach` from where it leaves the bound) stays out,
// with its foot inside the bound where `on_surface` is given; a protrusion (a claw, a spike, a
// fin) joins the part.
struct PartBound {
  std::function<bool(const Vec3&)> within;
  // How far (mesh units) a region that leaves the bound at a point may reach from there and still
  // be the part's own protrusion. A length, not a share of the part's vertices: a quarter of a
  // big part is a limb, and a count depends on how finely the mesh is cut.
  std::function<double(const Vec3&)> protrusion_reach;
  // Optional: whether a point inside the bound lies on the part's own surface. A bridge's foot —
  // part vertices off that surface reached from a bridge through such vertices — goes with the
  // bridge (a tusk fused to the trunk along a seam: without this its stretch inside the bound
  // stays in the part, and no sweep of the trunk fits it).
  std::function<bool(const Vec3&)> on_surface;
  explicit operator bool() const { return static_cast<bool>(within); }
};
std::vector<std::uint32_t> select_part(const Mesh& mesh, const Topology& topology, const Frame& root_plane,
                                       double root_radius, const Vec3& tip, const PartBound& within = {});

// The part of a stretch of a tube that goes on past its last key section (PartSeeds::tip_cut),
// sorted: the vertices reached from the tip-side cut — the disc of radius `tip_radius` in
// tip_plane — towards the root without crossing either disc (the root disc as above). The flood
// starts at the root-side ends of the edges through the tip disc, so the tip point itself may lie
// on the surface beyond. Throws Error(bad_input) when no edge passes through the tip disc or the
// region meets the root disc only from behind.
std::vector<std::uint32_t> select_part_between(const Mesh& mesh, const Topology& topology, const Frame& root_plane,
                                               double root_radius, const Frame& tip_plane, double tip_radius,
                                               const PartBound& within = {});

}  // namespace sweep
