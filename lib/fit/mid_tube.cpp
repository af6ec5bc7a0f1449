#include "sweep/fit/mid_tube.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sweep/fit/geodesic.h"
#include "sweep/fit/loop.h"

namespace sweep::fit {
namespace {

// The path's direction at a vertex: the chord over this many path vertices either side.
constexpr std::size_t kChordHalfWidth = 3;

}  // namespace

bool rings_run_both_ways(const Mesh& mesh, const Topology& topology, const std::vector<double>& from_tip,
                         double level) {
  if (!(level > 0) || !std::isfinite(level)) return false;
  const LevelSets levels(mesh, topology, from_tip, level, level);
  if (levels.level_count() < 1) return false;
  const std::vector<LevelLoop> loops = levels.loops(0);  // longest first
  return loops.size() >= 2 && loops[1].length >= kBothWaysShare * loops[0].length;
}

void path_axis_points(const Mesh& mesh, const Topology& topology, const MeshSlicer& slicer,
                      const std::vector<double>& from_root, std::uint32_t tip_vertex, std::vector<Vec3>& points,
                      std::vector<double>& radii) {
  points.clear();
  radii.clear();
  // Steepest descent over the edges: every vertex but the source has a nearer neighbour (its
  // distance came across an edge or a triangle of nearer vertices).
  std::vector<std::uint32_t> path{topology.weld[tip_vertex]};
  for (;;) {
    const std::uint32_t v = path.back();
    std::uint32_t next = v;
    for (const std::uint32_t w : topology.adjacency.of(v)) {
      if (from_root[w] < from_root[next]) next = w;
    }
    if (next == v) break;
    path.push_back(next);
  }
  const std::size_t m = path.size();
  if (m < 2) return;
  for (std::size_t i = m; i-- > 0;) {  // root first
    const std::size_t a = i >= kChordHalfWidth ? i - kChordHalfWidth : 0;
    const std::size_t b = std::min(i + kChordHalfWidth, m - 1);
    const Vec3 direction = mesh.positions[path[a]] - mesh.positions[path[b]];  // towards the tip
    if (!(direction.norm() > 0)) continue;
    const Vec3& p = mesh.positions[path[i]];
    const std::optional<Loop> loop =
        loop_around(slicer.slice(p, direction), p, direction.normalized(), std::numeric_limits<double>::infinity());
    if (!loop || !(loop->radius > 0)) continue;
    points.push_back(loop->centroid);
    radii.push_back(loop->radius);
  }
}

}  // namespace sweep::fit
