#include "sweep/fit/geodesic.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <queue>

namespace sweep::fit {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Distance to C across triangle ABC from a front known at A (dA) and B (dB): unfold the triangle
// into the plane with A at the origin and B on the x axis, put the virtual source S below AB where
// |SA| = dA and |SB| = dB, and take |SC| when the straight line from S to C passes through AB
// (otherwise the front reaches C around A or B, which the edge updates cover). Infinity when there
// is no such source.
double across_triangle(const Vec3& a, const Vec3& b, const Vec3& c, double da, double db) {
  const double ab = (b - a).norm();
  if (!(ab > 0)) return kInf;
  const double sx = (da * da - db * db + ab * ab) / (2 * ab);
  const double sy2 = da * da - sx * sx;
  if (!(sy2 >= 0)) return kInf;
  const double sy = -std::sqrt(sy2);
  const double ac2 = (c - a).squaredNorm(), bc2 = (c - b).squaredNorm();
  const double cx = (ac2 - bc2 + ab * ab) / (2 * ab);
  const double cy2 = ac2 - cx * cx;
  if (!(cy2 > 0)) return kInf;
  const double cy = std::sqrt(cy2);
  const double x = sx + (cx - sx) * (-sy) / (cy - sy);  // where S→C crosses the line AB
  if (!(x >= 0 && x <= ab)) return kInf;
  return std::hypot(cx - sx, cy - sy);
}

}  // namespace

std::vector<double> surface_distances(const Mesh& mesh, const Topology& topology,
                                      std::span<const std::uint32_t> sources) {
  const std::size_t nv = mesh.vertex_count();
  const auto& p = mesh.positions;
  std::vector<double> d(nv, kInf);
  std::vector<char> done(nv, 0);
  using Entry = std::pair<double, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap;
  for (const std::uint32_t s : sources) {
    const std::uint32_t r = topology.weld[s];
    if (d[r] != 0) heap.push({d[r] = 0, r});
  }
  const auto offer = [&](std::uint32_t w, double x) {
    if (x < d[w]) heap.push({d[w] = x, w});
  };
  while (!heap.empty()) {
    const auto [dv, v] = heap.top();
    heap.pop();
    if (done[v] || dv > d[v]) continue;
    done[v] = 1;
    for (const std::uint32_t w : topology.adjacency.of(v)) {
      if (!done[w]) offer(w, dv + (p[w] - p[v]).norm());
    }
    for (const std::uint32_t f : topology.vertex_triangles.of(v)) {
      const std::uint32_t* t = &topology.triangles[3 * static_cast<std::size_t>(f)];
      const int i = t[0] == v ? 0 : t[1] == v ? 1 : 2;
      const std::uint32_t x = t[(i + 1) % 3], y = t[(i + 2) % 3];
      if (done[x] && !done[y]) offer(y, across_triangle(p[v], p[x], p[y], dv, d[x]));
      if (done[y] && !done[x]) offer(x, across_triangle(p[v], p[y], p[x], dv, d[y]));
    }
  }
  for (std::size_t v = 0; v < nv; ++v) d[v] = d[topology.weld[v]];
  return d;
}

double LevelLoop::radius() const {
  return std::sqrt(vector_area.norm() / std::numbers::pi);
}

LevelSets::LevelSets(const Mesh& mesh, const Topology& topology, const std::vector<double>& distance, double spacing,
                     double max_level)
    : mesh_(mesh), topology_(topology), distance_(distance), spacing_(spacing) {
  const auto levels = static_cast<std::int64_t>(std::floor(max_level / spacing));
  const std::size_t nt = topology.triangles.size() / 3;
  // Level k (value spacing·(k+1)) crosses triangle f when min d < value <= max d.
  auto for_each_pair = [&](auto&& visit) {
    for (std::size_t f = 0; f < nt; ++f) {
      const std::uint32_t* t = &topology.triangles[3 * f];
      const double a = distance[t[0]], b = distance[t[1]], c = distance[t[2]];
      const double lo = std::min({a, b, c}), hi = std::max({a, b, c});
      if (!std::isfinite(hi)) continue;
      const auto m_lo = static_cast<std::int64_t>(std::floor(lo / spacing)) + 1;
      const auto m_hi = std::min(static_cast<std::int64_t>(std::floor(hi / spacing)), levels);
      for (std::int64_t m = m_lo; m <= m_hi; ++m) {
        visit(static_cast<std::uint32_t>(m - 1), static_cast<std::uint32_t>(f));
      }
    }
  };
  // Rows of (level, triangle): a counting sort like the adjacency's, rows already sorted.
  buckets_.offsets.assign(static_cast<std::size_t>(std::max<std::int64_t>(levels, 0)) + 1, 0);
  for_each_pair([&](std::uint32_t k, std::uint32_t) { ++buckets_.offsets[k + 1]; });
  for (std::size_t k = 1; k < buckets_.offsets.size(); ++k) buckets_.offsets[k] += buckets_.offsets[k - 1];
  buckets_.neighbours.resize(buckets_.offsets.back());
  std::vector<std::uint32_t> fill(buckets_.offsets.begin(), buckets_.offsets.end() - 1);
  for_each_pair([&](std::uint32_t k, std::uint32_t f) { buckets_.neighbours[fill[k]++] = f; });
}

std::vector<LevelLoop> LevelSets::loops(int k) const {
  const double value = level(k);
  const auto& p = mesh_.positions;
  // One segment per crossed triangle, between points on two of its edges; an edge's point is
  // keyed by the edge's vertex pair, which the two triangles of the edge share.
  struct Segment {
    std::uint64_t key[2];
  };
  std::vector<Segment> segments;
  std::vector<std::pair<std::uint64_t, Vec3>> points;
  const auto edge_point = [&](std::uint32_t a, std::uint32_t b) {
    const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
    const double da = distance_[a], db = distance_[b];
    const double u = (value - da) / (db - da);
    points.emplace_back(key, p[a] + u * (p[b] - p[a]));
    return key;
  };
  for (const std::uint32_t f : buckets_.of(static_cast<std::uint32_t>(k))) {
    const std::uint32_t* t = &topology_.triangles[3 * static_cast<std::size_t>(f)];
    const bool in[3] = {distance_[t[0]] < value, distance_[t[1]] < value, distance_[t[2]] < value};
    // The vertex alone on its side: the segment joins the points on its two edges.
    for (int i = 0; i < 3; ++i) {
      if (in[i] == in[(i + 1) % 3] || in[i] == in[(i + 2) % 3]) continue;
      const std::uint32_t a = t[i], b = t[(i + 1) % 3], c = t[(i + 2) % 3];
      segments.push_back({{edge_point(a, b), edge_point(a, c)}});
      break;
    }
  }
  // Nodes: the distinct edge keys, sorted; segments between them in compressed rows.
  std::sort(points.begin(), points.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  points.erase(
      std::unique(points.begin(), points.end(), [](const auto& x, const auto& y) { return x.first == y.first; }),
      points.end());
  const auto node = [&](std::uint64_t key) {
    return static_cast<std::uint32_t>(std::lower_bound(points.begin(), points.end(), key,
                                                       [](const auto& x, std::uint64_t k2) { return x.first < k2; }) -
                                      points.begin());
  };
  const std::size_t nn = points.size(), ns = segments.size();
  std::vector<std::uint32_t> ends(2 * ns);
  for (std::size_t s = 0; s < ns; ++s) {
    ends[2 * s] = node(segments[s].key[0]);
    ends[2 * s + 1] = node(segments[s].key[1]);
  }
  std::vector<std::uint32_t> start(nn + 1, 0), incident(2 * ns);
  for (const std::uint32_t n : ends) ++start[n + 1];
  for (std::size_t n = 0; n < nn; ++n) start[n + 1] += start[n];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t e = 0; e < 2 * ns; ++e) incident[fill[ends[e]]++] = static_cast<std::uint32_t>(e / 2);

  std::vector<char> used(ns, 0);
  std::vector<LevelLoop> out;
  const auto walk = [&](std::uint32_t first) {
    LevelLoop loop;
    std::uint32_t cur = first;
    loop.points.push_back(points[cur].second);
    for (;;) {
      std::uint32_t next_segment = UINT32_MAX;
      for (std::uint32_t i = start[cur]; i < start[cur + 1]; ++i) {
        if (!used[incident[i]]) {
          next_segment = incident[i];
          break;
        }
      }
      if (next_segment == UINT32_MAX) break;
      used[next_segment] = 1;
      cur = ends[2 * next_segment] == cur ? ends[2 * next_segment + 1] : ends[2 * next_segment];
      if (cur == first) {
        loop.closed = true;
        break;
      }
      loop.points.push_back(points[cur].second);
    }
    if (loop.points.size() < 2) return;
    const std::size_t m = loop.points.size();
    const std::size_t edges = loop.closed ? m : m - 1;
    Vec3 weighted = Vec3::Zero();
    for (std::size_t i = 0; i < edges; ++i) {
      const Vec3& x = loop.points[i];
      const Vec3& y = loop.points[(i + 1) % m];
      const double len = (y - x).norm();
      weighted += len * 0.5 * (x + y);
      loop.length += len;
    }
    loop.centroid = loop.length > 0 ? Vec3(weighted / loop.length) : loop.points[0];
    for (std::size_t i = 0; i < m; ++i) {
      loop.vector_area += 0.5 * (loop.points[i] - loop.centroid).cross(loop.points[(i + 1) % m] - loop.centroid);
    }
    out.push_back(std::move(loop));
  };
  // Open pieces from their ends first, then the closed loops.
  for (std::uint32_t n = 0; n < nn; ++n) {
    if (start[n + 1] - start[n] == 1 && !used[incident[start[n]]]) walk(n);
  }
  for (std::uint32_t n = 0; n < nn; ++n) {
    for (std::uint32_t i = start[n]; i < start[n + 1]; ++i) {
      if (!used[incident[i]]) walk(n);
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const LevelLoop& a, const LevelLoop& b) { return a.length > b.length; });
  return out;
}

}  // namespace sweep::fit
