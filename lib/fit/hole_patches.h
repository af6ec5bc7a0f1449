#pragma once
// Patches over a mesh's holes, for the walks of the fit only. Rings of surface distance and plane
// slices run round a tube; where the tube has a hole (a scan's gap, an eye socket left open, a
// mesh cut from a bigger one) they run into it, and a ring that is not closed measures nothing:
// the part is lost (CGAL's elephant-with-holes listed no part). Patched, the rings close over the
// hole as over the missing surface. One of the doors to CGAL (with slicer.h and
// surface_distance.h): each hole is filled by CGAL's minimal-area triangulation of its rim, over
// the rim's own vertices, so no vertex is added and every index stays the mesh's.
//
// The patches serve tracing only: the part a sweep drives is still walked over the mesh's own
// edges (core/rig.cpp), as sweep-bind walks it, so the fit and the binding agree.
#include <cstdint>
#include <optional>
#include <vector>

#include "sweep/core/mesh.h"
#include "sweep/core/topology.h"

namespace sweep::fit {

// Triangles (three representatives each) covering the holes of `topology` whose rims have at
// most kMaxTriangulatedRim edges and span at most kMaxPatchedHoleShare of the mesh's bounding
// box diagonal, oriented with the surface around them. A larger rim is an open side of the model
// (a cut-off base, a sheet's edge), not a gap in a part: it stays open, as does a hole CGAL finds
// no triangulation for and one whose patch would give an edge a third triangle (a diagonal the
// mesh already has between two rim vertices): a hole is patched whole or not at all.
std::vector<std::uint32_t> hole_patches(const Mesh& mesh, const Topology& topology);

// CGAL's search is cubic in the rim's length where its Delaunay shortcut fails.
inline constexpr std::size_t kMaxTriangulatedRim = 200;
// A gap in a part is at most about as wide as the part: elephant-with-holes' 141 holes span up to
// 0.143 of its diagonal (its legs and trunk 0.06–0.1 wide); lion.off's open mouth spans 0.19 and
// its base 0.53, openings of the model that stay open.
inline constexpr double kMaxPatchedHoleShare = 0.15;

// The mesh's topology with those holes patched (a copy: the mesh's own is left as it was), or
// nothing where no hole was patched (a closed mesh: the topology serves as it is).
std::optional<Topology> patched_topology(const Mesh& mesh, const Topology& topology);

}  // namespace sweep::fit
