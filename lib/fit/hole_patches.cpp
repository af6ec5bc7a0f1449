// One of the translation units that include CGAL (see hole_patches.h).
#include "fit/hole_patches.h"

#include "core/fp_environment.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/utility.h>

#include <algorithm>
#include <array>
#include <iterator>
#include <unordered_map>

namespace sweep::fit {
namespace {

using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;

}  // namespace

std::vector<std::uint32_t> hole_patches(const Mesh& mesh, const Topology& topology) {
  std::vector<std::uint32_t> out;
  const std::vector<std::vector<std::uint32_t>> rims = hole_rims(topology);
  if (rims.empty()) return out;
  QuietFpEnvironment quiet;  // CGAL's interval arithmetic raises FP flags by design (slicer.h)
  // A rim's triangulation knows nothing of the surface around it: a diagonal may be an edge the
  // mesh (or an earlier patch, where two holes touch) already has. A triangle that would give an
  // edge a third triangle is left out, a gap of a triangle in the patch.
  std::unordered_map<std::uint64_t, int> edge_uses;
  const auto edge = [](std::uint32_t a, std::uint32_t b) {
    return std::uint64_t{std::min(a, b)} << 32 | std::max(a, b);
  };
  for (std::size_t t = 0; t + 2 < topology.triangles.size(); t += 3) {
    for (std::size_t k = 0; k < 3; ++k)
      ++edge_uses[edge(topology.triangles[t + k], topology.triangles[t + (k + 1) % 3])];
  }
  Vec3 lo = mesh.positions[0], hi = lo;
  for (const Vec3& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double widest = kMaxPatchedHoleShare * (hi - lo).norm();
  for (const std::vector<std::uint32_t>& rim : rims) {
    if (rim.size() > kMaxTriangulatedRim) continue;
    double extent = 0;  // the rim's diameter
    for (std::size_t i = 0; i < rim.size() && extent <= widest; ++i) {
      for (std::size_t j = i + 1; j < rim.size(); ++j)
        extent = std::max(extent, (mesh.positions[rim[i]] - mesh.positions[rim[j]]).norm());
    }
    if (extent > widest) continue;
    std::vector<Point> polyline;
    polyline.reserve(rim.size());
    for (const std::uint32_t v : rim) {
      const Vec3& p = mesh.positions[v];
      polyline.emplace_back(p.x(), p.y(), p.z());
    }
    std::vector<CGAL::Triple<int, int, int>> patch;
    CGAL::Polygon_mesh_processing::triangulate_hole_polyline(polyline, std::back_inserter(patch));
    for (const CGAL::Triple<int, int, int>& tri : patch) {
      // A triangle of a polygon's triangulation taken in increasing rim order runs the way the
      // rim does (either side of a diagonal meets it once each way), as the rim's own triangles
      // do: reversed, the patch meets each rim edge the other way, as a closed surface does.
      std::array<int, 3> k{tri.first, tri.second, tri.third};
      std::sort(k.begin(), k.end());
      const std::array<std::uint32_t, 3> t{rim[static_cast<std::size_t>(k[2])],
                                           rim[static_cast<std::size_t>(k[1])],
                                           rim[static_cast<std::size_t>(k[0])]};
      const std::uint64_t e[3] = {edge(t[0], t[1]), edge(t[1], t[2]), edge(t[2], t[0])};
      if (edge_uses[e[0]] >= 2 || edge_uses[e[1]] >= 2 || edge_uses[e[2]] >= 2) continue;
      for (const std::uint64_t x : e) ++edge_uses[x];
      out.insert(out.end(), t.begin(), t.end());
    }
  }
  return out;
}

Topology patched_topology(const Mesh& mesh, const Topology& topology) {
  Topology patched = topology;
  add_triangles(patched, hole_patches(mesh, topology));
  return patched;
}

}  // namespace sweep::fit
