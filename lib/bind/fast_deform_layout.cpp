// The fast deformation path, at construction: the layout of the bound vertices (fast_deform.h) —
// each vertex's station span and angle cell, the tiles and pieces, the grouped order, the work
// blocks with their angle-cell segments and mesh-index runs — and the sizes of the station table.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "sweep/bind/fast_deform.h"
#include "sweep/bind/fast_deform_detail.h"
#include "sweep/core/error.h"

namespace sweep::bind {

using detail::kCells;
using detail::kPad;

FastDeformer::FastDeformer(const SweepShape& rest, const bind::SweepBinding& bound,
                           std::span<const Vec3f> rest_positions, int stations_per_span)
    : n_(rest.radial_count), stations_per_span_(stations_per_span) {
  assert(stations_per_span >= 1 && rest.section_count() >= 2 && n_ >= 3);
  const int k = rest.section_count();
  const int per = stations_per_span;
  station_count_ = (k - 1) * per + 1;
  row_ = kCells + 4 * n_;
  stations_.assign(static_cast<std::size_t>(station_count_) * row_, 0.0f);
  basis_.reserve(per + 1);
  for (int q = 0; q <= per; ++q) basis_.emplace_back(static_cast<double>(q) / per);
  section_cells_.resize(static_cast<std::size_t>(k) * 4 * n_);
  slopes_.resize(8 * static_cast<std::size_t>(n_));
  rotations_.resize(per + 1);

  // Station parameters, as the table places them: t_s + (t_{s+1} − t_s)·q/S.
  const std::vector<double> station_t = station_parameters(rest, per);

  // Span p (clamped, so cap vertices beyond the ends join the end spans) and angle cell j of each
  // vertex, in binding order (= mesh order).
  const std::size_t count = bound.size();
  // Grouped positions are uint32 with room for a block and the padding past the last one.
  constexpr std::size_t kMaxVertices =
      std::numeric_limits<std::uint32_t>::max() - kBlockVertices - static_cast<std::size_t>(kPad);
  if (count > kMaxVertices) {
    fail(ErrorCategory::unsupported, "a sweep binds " + std::to_string(count) +
                                         " vertices; the fast path takes at most " + std::to_string(kMaxVertices));
  }
  const std::size_t spans = station_t.size() - 1;
  std::vector<std::uint32_t> span_of(count), cell_of(count);
  std::vector<float> u(count), w(count);
  for (std::size_t v = 0; v < count; ++v) {
    const double t = bound.t[v];
    const auto it = std::upper_bound(station_t.begin(), station_t.end(), t);
    const std::size_t p = std::min<std::size_t>(std::max<std::ptrdiff_t>(it - station_t.begin() - 1, 0), spans - 1);
    const AngleCoord ac = locate_angle(n_, bound.theta[v]);
    span_of[v] = static_cast<std::uint32_t>(p);
    cell_of[v] = static_cast<std::uint32_t>(ac.j);
    u[v] = static_cast<float>(std::clamp((t - station_t[p]) / (station_t[p + 1] - station_t[p]), 0.0, 1.0));
    w[v] = static_cast<float>(ac.w);
  }

  // Pieces: the bound vertices in tiles of kTileVertices consecutive ones (mesh order), each tile
  // split by span; piece q = tile·spans + p. Tiles keep the stores of a mesh in no useful order
  // (random numbering) inside a window that stays in cache until it is complete.
  // Order within a piece: mesh order where it already keeps the angle cells together in long
  // segments (a ring-ordered mesh: each block is then one contiguous range of the mesh), else by
  // angle cell.
  const std::size_t tiles = (count + kTileVertices - 1) / kTileVertices;
  const std::size_t pieces = std::max<std::size_t>(tiles, 1) * spans;
  const auto piece_of = [&](std::size_t v) { return (v / kTileVertices) * spans + span_of[v]; };
  std::vector<std::uint32_t> piece_size(pieces, 0), piece_segments(pieces, 0), last_cell(pieces, n_);
  for (std::size_t v = 0; v < count; ++v) {
    const std::size_t q = piece_of(v);
    ++piece_size[q];
    if (cell_of[v] != last_cell[q]) ++piece_segments[q];
    last_cell[q] = cell_of[v];
  }
  // The grouped order: a stable counting sort by piece, then, inside each piece not kept in mesh
  // order, a stable counting sort by angle cell. order[o] = the binding index at grouped place o.
  std::vector<std::uint32_t> piece_begin(pieces + 1, 0);
  for (std::size_t v = 0; v < count; ++v) ++piece_begin[piece_of(v) + 1];
  for (std::size_t q = 0; q < pieces; ++q) piece_begin[q + 1] += piece_begin[q];
  std::vector<std::uint32_t> order(count);
  {
    std::vector<std::uint32_t> fill(piece_begin.begin(), piece_begin.end() - 1);
    for (std::size_t v = 0; v < count; ++v) order[fill[piece_of(v)]++] = static_cast<std::uint32_t>(v);
  }
  std::vector<std::uint32_t> cell_fill(n_ + 1), sorted;
  for (std::size_t q = 0; q < pieces; ++q) {
    if (piece_size[q] >= kMinMeanSegmentLength * piece_segments[q]) continue;  // mesh order
    const auto lo = order.begin() + piece_begin[q], hi = order.begin() + piece_begin[q + 1];
    std::fill(cell_fill.begin(), cell_fill.end(), 0);
    for (auto it = lo; it != hi; ++it) ++cell_fill[cell_of[*it] + 1];
    for (int j = 0; j < n_; ++j) cell_fill[j + 1] += cell_fill[j];
    sorted.resize(hi - lo);
    for (auto it = lo; it != hi; ++it) sorted[cell_fill[cell_of[*it]]++] = *it;
    std::copy(sorted.begin(), sorted.end(), lo);
  }

  for (auto* a : {&u_, &w_}) a->resize(count + kPad);
  for (auto* a : {&a_, &b_, &z_}) a->resize(count);
  vertex_.resize(count);
  std::vector<std::uint32_t> grouped_cell(count);
  for (std::size_t o = 0; o < count; ++o) {
    const std::uint32_t v = order[o];
    const SweepCoords c = bound.coords(v);
    vertex_[o] = bound.vertices[v];
    grouped_cell[o] = cell_of[v];
    u_[o] = u[v];
    w_[o] = w[v];
    a_[o] = static_cast<float>(c.s * std::cos(c.theta));
    b_[o] = static_cast<float>(c.s * std::sin(c.theta));
    z_[o] = static_cast<float>(c.z);
    // Blend vertices in grouped order: the fix-up pass then walks the arrays forwards.
    if (!bound.weight.empty() && bound.weight[v] < 1.0f) {
      blend_index_.push_back(static_cast<std::uint32_t>(o));
      blend_weight_.push_back(bound.weight[v]);
      blend_rest_.push_back(rest_positions[bound.vertices[v]]);
    }
  }

  // Work blocks: each piece's vertices in runs of at most kBlockVertices, each cut into segments of
  // one angle cell.
  for (std::size_t q = 0; q < pieces; ++q) {
    const std::size_t p = q % spans;
    const std::uint32_t first = piece_begin[q], last = piece_begin[q + 1];
    for (std::uint32_t b = first; b < last; b += kBlockVertices) {
      Block blk;
      blk.begin = b;
      blk.end = std::min(last, b + kBlockVertices);
      blk.span = static_cast<std::uint32_t>(p);
      blk.segments = static_cast<std::uint32_t>(segments_.size());
      for (std::uint32_t i = blk.begin; i < blk.end; ++i) {
        if (i + 1 == blk.end || grouped_cell[i + 1] != grouped_cell[i]) segments_.push_back({i + 1, grouped_cell[i]});
      }
      blk.axial = std::any_of(z_.begin() + blk.begin, z_.begin() + blk.end, [](float z) { return z != 0.0f; });
      // Contiguous runs of mesh indices; kept (terminated by a zero-length run) when they are long
      // enough on average for the run-by-run copy to beat the vertex-by-vertex one.
      const std::size_t first_run = runs_.size();
      for (std::uint32_t i = blk.begin; i < blk.end; ++i) {
        if (i == blk.begin || vertex_[i] != vertex_[i - 1] + 1) {
          runs_.push_back({i, 0});
        }
        ++runs_.back().length;
      }
      const std::size_t run_count = runs_.size() - first_run;
      if ((blk.end - blk.begin) >= kMinMeanRunLength * run_count) {
        runs_.push_back({0, 0});
        blk.runs = static_cast<std::uint32_t>(first_run);
      } else {
        runs_.resize(first_run);
      }
      blocks_.push_back(blk);
    }
  }
  parallel_ = count >= kParallelVertexThreshold;
}

std::size_t FastDeformer::direct_block_count() const {
  return static_cast<std::size_t>(std::count_if(blocks_.begin(), blocks_.end(), [&](const Block& b) {
    return b.runs != kNoRuns && runs_[b.runs].length == b.end - b.begin;
  }));
}

}  // namespace sweep::bind
