#include "sweep/fit/interior_spheres.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "sweep/fit/surface_distance.h"

namespace sweep::fit {

InteriorSpheres fit_interior_spheres(const std::vector<Vec3>& points, const std::vector<std::uint32_t>& triangles,
                                     const InteriorSpheresOptions& options,
                                     const std::function<double(const Vec3&)>& room) {
  InteriorSpheres out;
  if (points.empty() || triangles.empty() || options.max_spheres < 1 || options.cells < 1) return out;
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double h = (hi - lo).maxCoeff() / options.cells;
  if (!(h > 0)) return out;
  out.spacing = h;
  const TriangleDistance surface(points, triangles);

  // The candidates: grid points inside, with the sphere each may hold. Cell centres, so no point
  // lies on the bounding box (where a ray from it may run along a face).
  struct Candidate {
    Vec3 p;
    double radius;
  };
  std::vector<Candidate> candidates;
  const Eigen::Vector3i n = ((hi - lo) / h).array().ceil().cast<int>().cwiseMax(1);
  for (int i = 0; i < n.x(); ++i) {
    for (int j = 0; j < n.y(); ++j) {
      for (int k = 0; k < n.z(); ++k) {
        const Vec3 p = lo + h * Vec3(i + 0.5, j + 0.5, k + 0.5);
        if (!surface.inside(p)) continue;
        const double free = room(p);
        if (!(free > 0)) continue;
        candidates.push_back({p, std::min(surface.distance(p), free)});
      }
    }
  }
  out.points = candidates.size();

  // Largest first; stable, so the grid order breaks ties and the result never depends on the sort.
  std::vector<std::size_t> order(candidates.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return candidates[a].radius > candidates[b].radius; });
  std::vector<char> covered(candidates.size(), 0);
  for (const std::size_t c : order) {
    if (covered[c]) continue;
    if (static_cast<int>(out.spheres.size()) == options.max_spheres) break;
    const Sphere s{candidates[c].p, candidates[c].radius};
    out.spheres.push_back(s);
    // A point within one spacing of the sphere counts as covered: the grid cannot see finer, and
    // without the allowance a point at a narrow place would take a sphere of its own.
    for (std::size_t q = 0; q < candidates.size(); ++q) {
      if (!covered[q] && (candidates[q].p - s.centre).norm() <= s.radius + h) {
        covered[q] = 1;
        ++out.covered;
      }
    }
  }
  return out;
}

}  // namespace sweep::fit
