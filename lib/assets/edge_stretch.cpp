#include "assets/edge_stretch.h"

#include <algorithm>
#include <utility>

namespace sweep::sim {
namespace {

double length(const Vec3f& p, const Vec3f& q) { return (p.cast<double>() - q.cast<double>()).norm(); }

}  // namespace

EdgeStretchMeter::EdgeStretchMeter(const Mesh& mesh, std::span<const std::uint32_t> animated,
                                   std::span<const Vec3f> rest) {
  const std::size_t nv = mesh.vertex_count();
  std::vector<char> moves(nv, 0);
  for (const std::uint32_t v : animated) {
    if (v < nv) moves[v] = 1;
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    for (std::uint32_t k = begin; k < end; ++k) {
      std::uint32_t a = mesh.face_vertices[k], b = mesh.face_vertices[k + 1 < end ? k + 1 : begin];
      if (a >= nv || b >= nv || a == b || !(moves[a] || moves[b])) continue;
      if (b < a) std::swap(a, b);
      edges.emplace_back(a, b);
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& [a, b] : edges) {
    const double l = length(rest[a], rest[b]);
    if (!(l > 0)) continue;  // coincident ends (a seam split): no ratio to take
    a_.push_back(a);
    b_.push_back(b);
    rest_length_.push_back(l);
  }
}

EdgeStretch EdgeStretchMeter::measure(std::span<const Vec3f> positions) const {
  EdgeStretch worst;
  for (std::size_t e = 0; e < a_.size(); ++e) {
    const double ratio = length(positions[a_[e]], positions[b_[e]]) / rest_length_[e];
    if (ratio > worst.ratio) worst = {ratio, a_[e], b_[e], true};
  }
  return worst;
}

}  // namespace sweep::sim
