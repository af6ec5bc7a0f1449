#include "sweep/core/topology.h"

#include <algorithm>
#include <cassert>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>

#include "sweep/core/error.h"

namespace sweep {
namespace {

// Rows from (source, target) pairs: a counting sort on the source, then sort + unique within each
// (short) row. On the diplodocus a few ms, where sorting every pair took ~40.
VertexAdjacency rows_from_pairs(std::size_t nv, const auto& for_each_pair) {
  std::vector<std::uint32_t> start(nv + 1, 0);
  for_each_pair([&](std::uint32_t a, std::uint32_t) { ++start[a + 1]; });
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> all(start[nv]);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for_each_pair([&](std::uint32_t a, std::uint32_t b) { all[fill[a]++] = b; });
  VertexAdjacency adj;
  adj.offsets.assign(nv + 1, 0);
  adj.neighbours.reserve(all.size());
  for (std::size_t v = 0; v < nv; ++v) {
    const auto first = all.begin() + start[v], last = all.begin() + start[v + 1];
    std::sort(first, last);
    const auto unique_end = std::unique(first, last);
    adj.neighbours.insert(adj.neighbours.end(), first, unique_end);
    adj.offsets[v + 1] = static_cast<std::uint32_t>(adj.neighbours.size());
  }
  return adj;
}

// Calls visit(a, b) for every polygon edge in both directions, through `map` (identity or weld).
template <class Map, class Visit>
void for_each_edge(const Mesh& mesh, const Map& map, Visit&& visit) {
  const std::size_t nv = mesh.vertex_count();
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    for (std::uint32_t k = begin; k < end; ++k) {
      const std::uint32_t a0 = mesh.face_vertices[k];
      const std::uint32_t b0 = mesh.face_vertices[k + 1 < end ? k + 1 : begin];
      if (a0 >= nv || b0 >= nv) continue;
      const std::uint32_t a = map(a0), b = map(b0);
      if (a == b) continue;
      visit(a, b);
      visit(b, a);
    }
  }
}

// Representatives by exact position: sort indices by (x, y, z, index) and give each run of equal
// positions its first (lowest) index.
std::vector<std::uint32_t> weld_exact(const Mesh& mesh, std::size_t& welded) {
  const std::size_t nv = mesh.vertex_count();
  std::vector<std::uint32_t> order(nv);
  std::iota(order.begin(), order.end(), 0u);
  const auto& p = mesh.positions;
  auto less = [&](std::uint32_t a, std::uint32_t b) {
    if (p[a].x() != p[b].x()) return p[a].x() < p[b].x();
    if (p[a].y() != p[b].y()) return p[a].y() < p[b].y();
    if (p[a].z() != p[b].z()) return p[a].z() < p[b].z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<std::uint32_t> weld(nv);
  welded = 0;
  for (std::size_t k = 0; k < nv;) {
    std::size_t e = k + 1;
    while (e < nv && p[order[e]] == p[order[k]]) ++e;
    for (std::size_t i = k; i < e; ++i) weld[order[i]] = order[k];
    welded += e - k - 1;
    k = e;
  }
  return weld;
}

// Rows of the triangles around each vertex.
VertexAdjacency triangle_rows(std::size_t nv, const std::vector<std::uint32_t>& triangles) {
  const std::size_t nt = triangles.size() / 3;
  return rows_from_pairs(nv, [&](auto&& visit) {
    for (std::size_t f = 0; f < nt; ++f) {
      for (int c = 0; c < 3; ++c) visit(triangles[3 * f + c], static_cast<std::uint32_t>(f));
    }
  });
}

}  // namespace

std::uint32_t nearest_vertex(const Mesh& mesh, const Vec3& p) {
  assert(mesh.vertex_count() > 0);
  std::uint32_t best = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const double d2 = (mesh.positions[v] - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = static_cast<std::uint32_t>(v);
    }
  }
  return best;
}

VertexAdjacency vertex_adjacency(const Mesh& mesh) {
  return rows_from_pairs(mesh.vertex_count(), [&](auto&& visit) {
    for_each_edge(
        mesh, [](std::uint32_t v) { return v; }, visit);
  });
}

Topology build_topology(const Mesh& mesh) {
  Topology t;
  const std::size_t nv = mesh.vertex_count();
  t.weld = weld_exact(mesh, t.welded_count);
  const auto rep = [&](std::uint32_t v) { return t.weld[v]; };
  t.adjacency = rows_from_pairs(nv, [&](auto&& visit) { for_each_edge(mesh, rep, visit); });
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    for (std::uint32_t k = begin + 1; k + 1 < end; ++k) {
      const std::uint32_t ids[3] = {mesh.face_vertices[begin], mesh.face_vertices[k], mesh.face_vertices[k + 1]};
      if (ids[0] >= nv || ids[1] >= nv || ids[2] >= nv) continue;
      const std::uint32_t a = rep(ids[0]), b = rep(ids[1]), c = rep(ids[2]);
      if (a == b || b == c || a == c) continue;
      t.triangles.insert(t.triangles.end(), {a, b, c});
    }
  }
  t.vertex_triangles = triangle_rows(nv, t.triangles);
  return t;
}

namespace {

// The edges only one triangle uses, each as that triangle runs along it (a → b), sorted by a.
std::vector<std::pair<std::uint32_t, std::uint32_t>> rim_edges(const Topology& topology) {
  struct Use {
    std::uint64_t key;  // the undirected edge
    std::uint32_t a, b;
  };
  std::vector<Use> uses;
  uses.reserve(topology.triangles.size());
  for (std::size_t t = 0; t + 2 < topology.triangles.size(); t += 3) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t a = topology.triangles[t + k], b = topology.triangles[t + (k + 1) % 3];
      uses.push_back({std::uint64_t{std::min(a, b)} << 32 | std::max(a, b), a, b});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const Use& x, const Use& y) { return x.key < y.key; });
  std::vector<std::pair<std::uint32_t, std::uint32_t>> once;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    if (j - i == 1) once.emplace_back(uses[i].a, uses[i].b);
    i = j;
  }
  std::sort(once.begin(), once.end());
  return once;
}

}  // namespace

std::size_t hole_edge_count(const Topology& topology) {
  return rim_edges(topology).size();
}

std::vector<std::vector<std::uint32_t>> hole_rims(const Topology& topology) {
  const auto edges = rim_edges(topology);
  std::vector<bool> used(edges.size(), false);
  // The first unused rim edge leaving vertex a (edges are sorted by a), or edges.size().
  const auto leaving = [&](std::uint32_t a) {
    auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(a, std::uint32_t{0}));
    for (; it != edges.end() && it->first == a; ++it) {
      const auto k = static_cast<std::size_t>(it - edges.begin());
      if (!used[k]) return k;
    }
    return edges.size();
  };
  std::vector<std::vector<std::uint32_t>> rims;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (used[e]) continue;
    used[e] = true;
    std::vector<std::uint32_t> rim{edges[e].first};
    std::uint32_t at = edges[e].second;
    while (at != rim.front()) {
      const std::size_t next = leaving(at);
      if (next == edges.size()) break;  // the chain does not close (triangles oriented both ways)
      used[next] = true;
      rim.push_back(at);
      at = edges[next].second;
    }
    if (at != rim.front()) continue;
    // Two holes that touch at a vertex may chain into one figure-eight through it: each simple
    // loop of the chain is a rim of its own (its patch must not fold over the surface between).
    std::vector<std::uint32_t> loop;
    std::unordered_map<std::uint32_t, std::size_t> place;  // vertex → index in `loop`
    for (const std::uint32_t v : rim) {
      const auto seen = place.find(v);
      if (seen == place.end()) {
        place.emplace(v, loop.size());
        loop.push_back(v);
        continue;
      }
      const std::size_t k = seen->second;
      if (loop.size() - k >= 3) rims.emplace_back(loop.begin() + static_cast<std::ptrdiff_t>(k), loop.end());
      for (std::size_t i = k + 1; i < loop.size(); ++i) place.erase(loop[i]);
      loop.resize(k + 1);
    }
    if (loop.size() >= 3) rims.push_back(std::move(loop));
  }
  return rims;
}

void add_triangles(Topology& topology, std::span<const std::uint32_t> triangles) {
  if (triangles.empty()) return;
  const std::size_t nv = topology.weld.size();
  const VertexAdjacency before = std::move(topology.adjacency);
  topology.adjacency = rows_from_pairs(nv, [&](auto&& visit) {
    for (std::uint32_t v = 0; v < nv; ++v) {
      for (const std::uint32_t w : before.of(v)) visit(v, w);
    }
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
      for (std::size_t k = 0; k < 3; ++k) {
        const std::uint32_t a = triangles[t + k], b = triangles[t + (k + 1) % 3];
        visit(a, b);
        visit(b, a);
      }
    }
  });
  topology.triangles.insert(topology.triangles.end(), triangles.begin(), triangles.end());
  topology.vertex_triangles = triangle_rows(nv, topology.triangles);
}

namespace {

// A section a part may not be crossed through: a disc in a plane (normal = the frame's axis).
struct Disc {
  const Mesh& mesh;
  const Frame& plane;
  double radius;
  double height(std::uint32_t v) const { return (mesh.positions[v] - plane.center).dot(plane.axis()); }
  // Does the edge a → b pass through the disc? Only edges with ends on both sides (or one end on
  // the plane, behind counting as < 0) can; the crossing point is where the height is 0.
  bool crossed_by(std::uint32_t a, std::uint32_t b) const {
    const double ha = height(a), hb = height(b);
    if ((ha >= 0) == (hb >= 0)) return false;
    const double u = ha / (ha - hb);
    const Vec3 x = mesh.positions[a] + u * (mesh.positions[b] - mesh.positions[a]);
    return (x - plane.center).squaredNorm() <= radius * radius;
  }
};

// Where `within` stopped the flood, what lies beyond is either a bridge to the body (a trunk
// against a tusk that leads into the head) or the part's own protrusion (a spike, a fin, a toe):
// each region beyond, walked without the bound (never through a disc), is a bridge when it
// reaches behind the root plane, reaches farther from where it left the bound than the bound's
// protrusion_reach there (a root plane tilted across the body leaves some of it in front: the body
// is far bigger than any protrusion) or meets a bridge found before; otherwise it joins the part,
// carried along as the feet past the tip section are.
void keep_protrusions(const Topology& topology, const Disc& root, const Disc* tip, const PartBound& within,
                      const std::vector<std::uint32_t>& bounded, std::vector<char>& seen) {
  constexpr char kPart = 1, kBridge = 2, kRegion = 3;
  const std::vector<Vec3>& positions = root.mesh.positions;
  std::vector<std::uint32_t> region, stack;
  for (const std::uint32_t v : bounded) {
    for (const std::uint32_t start : topology.adjacency.of(v)) {
      if (seen[start] || root.crossed_by(v, start) || (tip && tip->crossed_by(v, start))) continue;
      if (within.within(positions[start])) continue;  // (reached some other way since)
      const double reach = within.protrusion_reach(positions[v]);
      const Vec3 left_at = positions[v];
      region.assign(1, start);
      stack.assign(1, start);
      seen[start] = kRegion;
      bool bridge = root.height(start) < 0 || (positions[start] - left_at).norm() > reach;
      while (!stack.empty() && !bridge) {
        const std::uint32_t a = stack.back();
        stack.pop_back();
        for (const std::uint32_t b : topology.adjacency.of(a)) {
          if (seen[b] == kBridge) bridge = true;  // joins a bridge found from another start
          if (seen[b] || root.crossed_by(a, b) || (tip && tip->crossed_by(a, b))) continue;
          seen[b] = kRegion;
          region.push_back(b);
          stack.push_back(b);
          if (root.height(b) < 0 || (positions[b] - left_at).norm() > reach) bridge = true;
        }
      }
      for (const std::uint32_t r : region) seen[r] = bridge ? kBridge : kPart;
    }
  }
  // A bridge's foot inside the bound (where a tusk is fused to the trunk it lies against) is not
  // the part's surface either: from each bridge, part vertices off the sweep's surface, reached
  // through such vertices, go with it.
  if (within.on_surface) {
    stack.clear();
    for (std::uint32_t v = 0; v < seen.size(); ++v) {
      if (seen[v] == kBridge) stack.push_back(v);
    }
    while (!stack.empty()) {
      const std::uint32_t a = stack.back();
      stack.pop_back();
      for (const std::uint32_t b : topology.adjacency.of(a)) {
        if (seen[b] != kPart || within.on_surface(positions[b])) continue;
        seen[b] = kBridge;
        stack.push_back(b);
      }
    }
  }
  for (char& x : seen) x = x == kPart ? 1 : 0;
}

// The flood over representatives from `stack`, never over an edge through the root disc nor
// (when given) the tip disc; the sorted file vertices whose representative it reached.
std::vector<std::uint32_t> flood_part(const Mesh& mesh, const Topology& topology, const Disc& root, const Disc* tip,
                                      const PartBound& within, std::vector<std::uint32_t> stack,
                                      const std::string& seed_label) {
  std::vector<char> seen(mesh.vertex_count(), 0);
  for (const std::uint32_t v : stack) seen[v] = 1;
  std::vector<std::uint32_t> bounded;  // part vertices with a neighbour `within` rejected
  // Where the region is stopped by the disc, which side is it on? A part leaves the root section
  // forwards, so its region meets the disc from the front; a region that meets it only from
  // behind is the body (or a part on the wrong side): the tip was given behind the root. (A curled
  // part's tip may well lie behind the root *plane*; only the side at the disc counts.)
  bool meets_disc_from_front = false, meets_disc_from_behind = false;
  while (!stack.empty()) {
    const std::uint32_t v = stack.back();
    stack.pop_back();
    for (const std::uint32_t w : topology.adjacency.of(v)) {
      if (seen[w]) continue;
      if (root.crossed_by(v, w)) {
        (root.height(v) >= 0 ? meets_disc_from_front : meets_disc_from_behind) = true;
        continue;
      }
      if (tip && tip->crossed_by(v, w)) continue;
      if (within && !within.within(mesh.positions[w])) {
        bounded.push_back(v);
        continue;
      }
      seen[w] = 1;
      stack.push_back(w);
    }
  }
  if (!bounded.empty()) keep_protrusions(topology, root, tip, within, bounded, seen);
  if (meets_disc_from_behind && !meets_disc_from_front) {
    fail(ErrorCategory::bad_input, seed_label +
                                       " lies behind the root section (on the body's side): the surface reached from "
                                       "it meets the root section from behind");
  }
  std::vector<std::uint32_t> part;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (seen[topology.weld[v]]) part.push_back(static_cast<std::uint32_t>(v));
  }
  return part;
}

}  // namespace

std::vector<std::uint32_t> select_part(const Mesh& mesh, const Topology& topology, const Frame& root_plane,
                                       double root_radius, const Vec3& tip, const PartBound& within) {
  if (mesh.vertex_count() == 0) fail(ErrorCategory::bad_input, "the mesh has no vertices");
  const std::uint32_t start = topology.weld[nearest_vertex(mesh, tip)];
  return flood_part(mesh, topology, Disc{mesh, root_plane, root_radius}, nullptr, within, {start},
                    "the tip's nearest vertex " + std::to_string(start));
}

std::vector<std::uint32_t> select_part_between(const Mesh& mesh, const Topology& topology, const Frame& root_plane,
                                               double root_radius, const Frame& tip_plane, double tip_radius,
                                               const PartBound& within) {
  if (mesh.vertex_count() == 0) fail(ErrorCategory::bad_input, "the mesh has no vertices");
  const Disc root{mesh, root_plane, root_radius}, tip{mesh, tip_plane, tip_radius};
  // Seeds: the root-side ends of the edges through the tip disc (the tip point itself may lie
  // beyond it, on the surface that goes on).
  std::vector<std::uint32_t> seeds;
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    if (topology.weld[v] != v || tip.height(v) >= 0) continue;
    for (const std::uint32_t w : topology.adjacency.of(v)) {
      if (tip.crossed_by(v, w) && !root.crossed_by(v, w)) {
        seeds.push_back(v);
        break;
      }
    }
  }
  if (seeds.empty()) {
    fail(ErrorCategory::bad_input,
         "no edge of the surface passes through the last key section (the tip-side cut): there is "
         "no tube there to cut");
  }
  return flood_part(mesh, topology, root, &tip, within, std::move(seeds), "the tip-side cut");
}

}  // namespace sweep
