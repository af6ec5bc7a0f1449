#include "fit/part.h"

#include <algorithm>
#include <cassert>
#include <limits>
#include <sstream>

#include "core/error.h"

namespace sweep::fit {

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

// A counting sort on the source vertex, then a sort within each (short) row: on the diplodocus a few
// ms, where sorting every edge pair took ~40 and dominated binding.
VertexAdjacency vertex_adjacency(const Mesh& mesh) {
  const std::size_t nv = mesh.vertex_count();
  VertexAdjacency adj;
  std::vector<std::uint32_t> start(nv + 1, 0);
  auto for_each_edge = [&](auto&& visit) {
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
      const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
      for (std::uint32_t k = begin; k < end; ++k) {
        const std::uint32_t a = mesh.face_vertices[k];
        const std::uint32_t b = mesh.face_vertices[k + 1 < end ? k + 1 : begin];
        if (a == b || a >= nv || b >= nv) continue;
        visit(a, b);
        visit(b, a);
      }
    }
  };
  for_each_edge([&](std::uint32_t a, std::uint32_t) { ++start[a + 1]; });
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> all(start[nv]);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for_each_edge([&](std::uint32_t a, std::uint32_t b) { all[fill[a]++] = b; });
  adj.offsets.assign(nv + 1, 0);
  adj.neighbours.reserve(all.size() / 2);
  for (std::size_t v = 0; v < nv; ++v) {
    const auto first = all.begin() + start[v], last = all.begin() + start[v + 1];
    std::sort(first, last);
    const auto unique_end = std::unique(first, last);
    adj.neighbours.insert(adj.neighbours.end(), first, unique_end);
    adj.offsets[v + 1] = static_cast<std::uint32_t>(adj.neighbours.size());
  }
  return adj;
}

std::vector<std::uint32_t> select_part(const Mesh& mesh, const Frame& root_plane, const Vec3& tip) {
  return select_part(mesh, vertex_adjacency(mesh), root_plane, tip);
}

std::vector<std::uint32_t> select_part(const Mesh& mesh, const VertexAdjacency& adjacency,
                                       const Frame& root_plane, const Vec3& tip) {
  if (mesh.vertex_count() == 0) fail(ErrorCategory::bad_input, "the mesh has no vertices");
  const Vec3 normal = root_plane.axis();
  auto in_front = [&](std::uint32_t v) {
    return (mesh.positions[v] - root_plane.center).dot(normal) >= 0;
  };
  const std::uint32_t start = nearest_vertex(mesh, tip);
  if (!in_front(start)) {
    std::ostringstream s;
    s << "the tip's nearest vertex " << start << " lies behind the root plane (on the body's side)";
    fail(ErrorCategory::bad_input, s.str());
  }
  std::vector<bool> seen(mesh.vertex_count(), false);
  std::vector<std::uint32_t> part{start}, stack{start};
  seen[start] = true;
  while (!stack.empty()) {
    const std::uint32_t v = stack.back();
    stack.pop_back();
    for (std::uint32_t k = adjacency.offsets[v]; k < adjacency.offsets[v + 1]; ++k) {
      const std::uint32_t w = adjacency.neighbours[k];
      if (seen[w] || !in_front(w)) continue;
      seen[w] = true;
      part.push_back(w);
      stack.push_back(w);
    }
  }
  std::sort(part.begin(), part.end());
  return part;
}

}  // namespace sweep::fit
