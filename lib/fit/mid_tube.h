#pragma once
// A tip given mid-tube: a stretch of a tube that goes on past its tip (a hose, a knot,
// a torus) has no end to climb to and no cap; the rings of surface distance from such a tip run
// both ways along the tube. There the part is the stretch from the root to the tip, cut on the tip
// side too (PartSeeds::tip_cut), and its axis comes from slices along the surface path between
// them rather than from the rings.
#include <cstdint>
#include <vector>

#include "sweep/core/topology.h"
#include "sweep/fit/slicer.h"

namespace sweep::fit {

// Do the rings from the tip run both ways? The level set at `level` of `from_tip` (the surface
// distance from the tip vertex; pass a level a little short of the root's) holds a second loop at
// least kBothWaysShare as long as the longest: the tube goes on beyond the tip at least as far as
// the root lies before it. A part with an end (a tail, a neck and head) has one loop there.
inline constexpr double kBothWaysShare = 0.5;
bool rings_run_both_ways(const Mesh& mesh, const Topology& topology, const std::vector<double>& from_tip, double level);

// Axis points of the stretch from `root_vertex` to `tip_vertex`, root first, with the radius of
// each: the centroids of the slice loops through the vertices of the surface path that descends
// `from_root` (the surface distance from the root vertex) from the tip, each slice normal to the
// path's local direction. Points whose slice finds no loop are left out.
void path_axis_points(const Mesh& mesh, const Topology& topology, const MeshSlicer& slicer,
                      const std::vector<double>& from_root, std::uint32_t tip_vertex, std::vector<Vec3>& points,
                      std::vector<double>& radii);

}  // namespace sweep::fit
