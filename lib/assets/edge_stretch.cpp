#include "sweep/assets/edge_stretch.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace sweep::assets {
namespace {

double squared_length(const bind::Vec3f& p, const bind::Vec3f& q) {
  return (p.cast<double>() - q.cast<double>()).squaredNorm();
}

}  // namespace

EdgeStretchMeter::EdgeStretchMeter(const Mesh& mesh, std::span<const std::uint32_t> animated,
                                   std::span<const bind::Vec3f> rest) {
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
    const double l2 = squared_length(rest[a], rest[b]);
    if (!(l2 > 0)) continue;  // coincident ends (a seam split): no ratio to take
    a_.push_back(a);
    b_.push_back(b);
    rest_squared_.push_back(l2);
  }
}

EdgeStretch EdgeStretchMeter::measure(std::span<const bind::Vec3f> positions) const {
  // Squared ratios (no square root an edge): the largest ratio is the root of the largest.
  double worst = 1;
  std::size_t at = a_.size();
  for (std::size_t e = 0; e < a_.size(); ++e) {
    const double ratio2 = squared_length(positions[a_[e]], positions[b_[e]]) / rest_squared_[e];
    if (ratio2 > worst) {
      worst = ratio2;
      at = e;
    }
  }
  if (at == a_.size()) return {};
  return {std::sqrt(worst), a_[at], b_[at], true};
}

}  // namespace sweep::assets
