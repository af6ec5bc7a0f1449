// One of the translation units that include CGAL (see hole_patches.h).
#include "sweep/fit/hole_patches.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/utility.h>

#include <algorithm>
#include <array>
#include <iterator>
#include <unordered_map>

#include "sweep/core/fp_environment.h"

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
  // mesh (or an earlier patch) already has between two rim vertices. A patch that would give such
  // an edge a third triangle is left out whole: the hole stays open rather than half closed.
  std::vector<char> on_rim(mesh.vertex_count(), 0);
  for (const std::vector<std::uint32_t>& rim : rims) {
    for (const std::uint32_t v : rim) on_rim[v] = 1;
  }
  const auto edge = [](std::uint32_t a, std::uint32_t b) {
    return std::uint64_t{std::min(a, b)} << 32 | std::max(a, b);
  };
  std::unordered_map<std::uint64_t, int> edge_uses;  // edges between rim vertices (never iterated)
  for (std::size_t t = 0; t + 2 < topology.triangles.size(); t += 3) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t a = topology.triangles[t + k], b = topology.triangles[t + (k + 1) % 3];
      if (on_rim[a] && on_rim[b]) ++edge_uses[edge(a, b)];
    }
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
    try {
      CGAL::Polygon_mesh_processing::triangulate_hole_polyline(polyline, std::back_inserter(patch));
    } catch (const std::exception&) {  // a CGAL precondition (Debug builds): this hole stays open
      continue;
    }
    std::vector<std::uint32_t> triangles;
    std::vector<std::uint64_t> edges;
    for (const CGAL::Triple<int, int, int>& tri : patch) {
      // A triangle of a polygon's triangulation taken in increasing rim order runs the way the
      // rim does (either side of a diagonal meets it once each way), as the rim's own triangles
      // do: reversed, the patch meets each rim edge the other way, as a closed surface does.
      std::array<int, 3> k{tri.first, tri.second, tri.third};
      std::sort(k.begin(), k.end());
      const std::array<std::uint32_t, 3> t{rim[static_cast<std::size_t>(k[2])], rim[static_cast<std::size_t>(k[1])],
                                           rim[static_cast<std::size_t>(k[0])]};
      triangles.insert(triangles.end(), t.begin(), t.end());
      edges.insert(edges.end(), {edge(t[0], t[1]), edge(t[1], t[2]), edge(t[2], t[0])});
    }
    std::unordered_map<std::uint64_t, int> uses;  // this patch's
    for (const std::uint64_t e : edges) ++uses[e];
    const bool fits = patch.size() == rim.size() - 2 && std::all_of(edges.begin(), edges.end(), [&](std::uint64_t e) {
                        const auto before = edge_uses.find(e);
                        return (before == edge_uses.end() ? 0 : before->second) + uses[e] <= 2;
                      });
    if (!fits) continue;
    for (const std::uint64_t e : edges) ++edge_uses[e];
    out.insert(out.end(), triangles.begin(), triangles.end());
  }
  return out;
}

std::optional<Topology> patched_topology(const Mesh& mesh, const Topology& topology) {
  const std::vector<std::uint32_t> patches = hole_patches(mesh, topology);
  if (patches.empty()) return std::nullopt;
  Topology patched = topology;
  add_triangles(patched, patches);
  return patched;
}

}  // namespace sweep::fit
