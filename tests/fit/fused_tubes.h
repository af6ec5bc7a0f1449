#pragma once
// Surfaces that are not one sweep: tubes fused to each other and to a body (a tusk along a
// trunk, fused to it along a seam the way CGAL's elephants are), as the zero level set of the
// smallest of their signed distances, meshed by marching tetrahedra (a cube grid, each cube cut
// into six tetrahedra around its main diagonal, so the cut faces match between cubes: the surface
// is closed and manifold, its vertices on the grid's edges). The seam is a crease, as on a mesh
// made by fusing two.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

#include "sweep/core/mesh.h"

namespace sweep::test {

// Distance from p to a polyline.
inline double distance_to_polyline(const std::vector<Vec3>& points, const Vec3& p) {
  double best = 1e300;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const Vec3 ab = points[i + 1] - points[i];
    const double u = std::clamp((p - points[i]).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
    best = std::min(best, (points[i] + u * ab - p).norm());
  }
  return best;
}

// The surface f = 0 inside [lo, hi] (f < 0 inside; f must be > 0 on the box's boundary), cells
// of size h. Triangles face outwards (towards f > 0).
inline Mesh mesh_level_set(const std::function<double(const Vec3&)>& f, const Vec3& lo, const Vec3& hi, double h) {
  const int nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / h));
  const int ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / h));
  const int nz = static_cast<int>(std::ceil((hi.z() - lo.z()) / h));
  const auto node = [&](int i, int j, int k) {
    return static_cast<std::uint64_t>((static_cast<std::int64_t>(k) * (ny + 1) + j) * (nx + 1) + i);
  };
  const auto at = [&](std::uint64_t n) {
    const auto i = static_cast<int>(n % static_cast<std::uint64_t>(nx + 1));
    const auto j = static_cast<int>(n / static_cast<std::uint64_t>(nx + 1) % static_cast<std::uint64_t>(ny + 1));
    const auto k = static_cast<int>(n / static_cast<std::uint64_t>((nx + 1) * (ny + 1)));
    return Vec3(lo + h * Vec3(i, j, k));
  };
  std::vector<double> value(static_cast<std::size_t>(nx + 1) * (ny + 1) * (nz + 1));
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        double v = f(at(node(i, j, k)));
        if (std::abs(v) < 1e-9 * h) v = 1e-9 * h;  // never on a node: no zero-area triangles
        value[node(i, j, k)] = v;
      }
  Mesh m;
  std::unordered_map<std::uint64_t, std::uint32_t> on_edge;  // node pair → vertex
  const std::uint64_t nodes = value.size();
  const auto cross = [&](std::uint64_t a, std::uint64_t b) {
    if (a > b) std::swap(a, b);
    const auto [it, added] = on_edge.try_emplace(a * nodes + b, static_cast<std::uint32_t>(m.positions.size()));
    if (added) {
      const double u = value[a] / (value[a] - value[b]);
      m.positions.push_back((1 - u) * at(a) + u * at(b));
    }
    return it->second;
  };
  // The triangle a, b, c turned to face from `inside` towards `outside`.
  const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, const Vec3& inside, const Vec3& outside) {
    const Vec3 n = (m.positions[b] - m.positions[a]).cross(m.positions[c] - m.positions[a]);
    if (n.dot(outside - inside) < 0) std::swap(b, c);
    m.add_face({a, b, c});
  };
  static constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7},
                                      {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        std::uint64_t corner[8];
        for (int c = 0; c < 8; ++c) corner[c] = node(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1));
        for (const auto& tet : kTets) {
          std::vector<std::uint64_t> in, out;
          for (const int c : tet) (value[corner[c]] < 0 ? in : out).push_back(corner[c]);
          if (in.empty() || out.empty()) continue;
          Vec3 ci = Vec3::Zero(), co = Vec3::Zero();
          for (const auto n : in) ci += at(n) / static_cast<double>(in.size());
          for (const auto n : out) co += at(n) / static_cast<double>(out.size());
          if (in.size() == 1 || out.size() == 1) {
            const auto& lone = in.size() == 1 ? in : out;
            const auto& rest = in.size() == 1 ? out : in;
            add(cross(lone[0], rest[0]), cross(lone[0], rest[1]), cross(lone[0], rest[2]), ci, co);
          } else {  // two and two: a quad
            const std::uint32_t a = cross(in[0], out[0]), b = cross(in[0], out[1]);
            const std::uint32_t c = cross(in[1], out[1]), d = cross(in[1], out[0]);
            add(a, b, c, ci, co);
            add(a, c, d, ci, co);
          }
        }
      }
  return m;
}

}  // namespace sweep::test
