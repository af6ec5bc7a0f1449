#include "sim/fast_deform.h"

#include <omp.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace sweep::sim {
namespace {

// Station row layout: centre, the three frame axes, then 4 cubic coefficients per angle cell.
constexpr int kCenter = 0, kAxisX = 3, kAxisY = 6, kAxisZ = 9, kCells = 12;

// Cubic Hermite basis at u.
void hermite(double u, double* h) {
  const double u2 = u * u, u3 = u2 * u;
  h[0] = 2 * u3 - 3 * u2 + 1;
  h[1] = u3 - 2 * u2 + u;
  h[2] = -2 * u3 + 3 * u2;
  h[3] = u3 - u2;
}

using Run = FastDeformer::Run;
// The radii loop runs in whole vectors of kPad floats (AVX2's 8; baseline's 4 divides it), so a
// short angle-cell segment costs no scalar remainder (BENCHMARKS.md, section "Layout and
// thread thresholds"); u_ and w_ carry kPad floats of padding for the reads past the end.
constexpr std::ptrdiff_t kPad = 8;
using Segment = FastDeformer::Segment;

// What the per-block kernel reads and writes (FastDeformer's arrays).
struct Kernel {
  float floor;
  const float *u, *w, *a, *b, *z;
  const std::uint32_t* vertex;
  float* out;
};

// One block of one station span (stations A and B): vertices [begin, end) of the grouped arrays,
// in angle-cell segments `seg` (the first starts at `begin`, the last ends at `end`). With kAxial
// the vertices' axial offsets z are read (only blocks holding cap vertices need them); without,
// z = 0 and the loop reads 16 bytes a vertex instead of 20.
//
// Compiled twice (target_clones): for AVX2 and for baseline x86-64, picked at load time. Neither
// enables FMA, and the vectorized and scalar forms do the same IEEE operations in the same order,
// so both give the same bits.
template <bool kAxial>
[[gnu::always_inline]] inline void deform_block_impl(const Kernel& k, const float* A,
                                                     const float* B, const Segment* seg,
                                                     std::uint32_t begin, std::uint32_t end,
                                                     const Run* runs) {
  const std::uint32_t m = end - begin;
  float r[kBlockVertices + kPad], ox[kBlockVertices], oy[kBlockVertices], oz[kBlockVertices];

  // 1. Radii, one angle-cell segment at a time: the cell's cubic at both stations is loop
  // invariant.
  for (std::uint32_t lo = begin;; ++seg) {
    const std::uint32_t hi = seg->end;
    const float* pa = A + kCells + 4 * seg->cell;
    const float* pb = B + kCells + 4 * seg->cell;
    const float a0 = pa[0], a1 = pa[1], a2 = pa[2], a3 = pa[3];
    const float d0 = pb[0] - a0, d1 = pb[1] - a1, d2 = pb[2] - a2, d3 = pb[3] - a3;
    // Pointer-and-count form (not uint32 indices, whose wrap-around defeats the vectorizer).
    const float* cw = k.w + lo;
    const float* cu = k.u + lo;
    float* cr = r + (lo - begin);
    // Rounded up to whole vectors: the extra radii are overwritten by the next segment's or lie
    // past the block (the arrays are padded for the reads).
    const std::ptrdiff_t len =
        (static_cast<std::ptrdiff_t>(hi) - static_cast<std::ptrdiff_t>(lo) + kPad - 1) & -kPad;
    for (std::ptrdiff_t i = 0; i < len; ++i) {
      const float w = cw[i], u = cu[i];
      const float ra = a0 + w * (a1 + w * (a2 + w * a3));
      const float rd = d0 + w * (d1 + w * (d2 + w * d3));
      cr[i] = std::max(ra + u * rd, k.floor);
    }
    if (hi >= end) break;
    lo = hi;
  }

  // 2. Positions over the block: station A and the difference to B are loop invariants.
  float ca[12], cd[12];
  for (int c = 0; c < 12; ++c) {
    ca[c] = A[c];
    cd[c] = B[c] - A[c];
  }
  const float* bu = k.u + begin;
  const float* ba = k.a + begin;
  const float* bb = k.b + begin;
  const float* bz = k.z + begin;
  const auto positions = [&](auto store) {
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(m); ++i) {
      const float u = bu[i];
      const float x = r[i] * ba[i], y = r[i] * bb[i];
      float px = (ca[0] + u * cd[0]) + (ca[3] + u * cd[3]) * x + (ca[6] + u * cd[6]) * y;
      float py = (ca[1] + u * cd[1]) + (ca[4] + u * cd[4]) * x + (ca[7] + u * cd[7]) * y;
      float pz = (ca[2] + u * cd[2]) + (ca[5] + u * cd[5]) * x + (ca[8] + u * cd[8]) * y;
      if constexpr (kAxial) {
        const float z = bz[i];
        px += (ca[9] + u * cd[9]) * z;
        py += (ca[10] + u * cd[10]) * z;
        pz += (ca[11] + u * cd[11]) * z;
      }
      store(i, px, py, pz);
    }
  };
  // A block whose mesh indices are one contiguous run is written straight to the mesh.
  if (runs != nullptr && runs->length == m) {
    float* o = k.out + 3 * static_cast<std::size_t>(k.vertex[begin]);
    positions([o](std::ptrdiff_t i, float x, float y, float z) {
      o[3 * i] = x;
      o[3 * i + 1] = y;
      o[3 * i + 2] = z;
    });
    return;
  }
  positions([&](std::ptrdiff_t i, float x, float y, float z) {
    ox[i] = x;
    oy[i] = y;
    oz[i] = z;
  });

  // 3. Back to mesh order: run by run where the block's mesh indices come in long contiguous runs
  // (a ring-ordered mesh: each run is an interleaving copy the compiler vectorizes), else vertex by
  // vertex.
  if (runs != nullptr) {
    for (; runs->length != 0; ++runs) {
      const std::ptrdiff_t off = static_cast<std::ptrdiff_t>(runs->start - begin);
      const std::ptrdiff_t len = runs->length;
      float* o = k.out + 3 * static_cast<std::size_t>(k.vertex[runs->start]);
      const float* rx = ox + off;
      const float* ry = oy + off;
      const float* rz = oz + off;
      for (std::ptrdiff_t i = 0; i < len; ++i) {
        o[3 * i] = rx[i];
        o[3 * i + 1] = ry[i];
        o[3 * i + 2] = rz[i];
      }
    }
    return;
  }
  const std::uint32_t* bv = k.vertex + begin;
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(m); ++i) {
    float* o = k.out + 3 * static_cast<std::size_t>(bv[i]);
    o[0] = ox[i];
    o[1] = oy[i];
    o[2] = oz[i];
  }
}

__attribute__((target_clones("avx2", "default"))) void deform_block(
    const Kernel& k, const float* A, const float* B, const Segment* seg, std::uint32_t begin,
    std::uint32_t end, const Run* runs) {
  deform_block_impl<false>(k, A, B, seg, begin, end, runs);
}

__attribute__((target_clones("avx2", "default"))) void deform_block_axial(
    const Kernel& k, const float* A, const float* B, const Segment* seg, std::uint32_t begin,
    std::uint32_t end, const Run* runs) {
  deform_block_impl<true>(k, A, B, seg, begin, end, runs);
}

// The same kernels compiled for one target only, for tests that compare the forms
// (FastDeformer::force_kernel_form); production calls the target_clones above.
using BlockFunction = void (*)(const Kernel&, const float*, const float*, const Segment*,
                               std::uint32_t, std::uint32_t, const Run*);

void deform_block_baseline(const Kernel& k, const float* A, const float* B, const Segment* seg,
                           std::uint32_t begin, std::uint32_t end, const Run* runs) {
  deform_block_impl<false>(k, A, B, seg, begin, end, runs);
}

void deform_block_axial_baseline(const Kernel& k, const float* A, const float* B,
                                 const Segment* seg, std::uint32_t begin, std::uint32_t end,
                                 const Run* runs) {
  deform_block_impl<true>(k, A, B, seg, begin, end, runs);
}

__attribute__((target("avx2"))) void deform_block_avx2(const Kernel& k, const float* A,
                                                       const float* B, const Segment* seg,
                                                       std::uint32_t begin, std::uint32_t end,
                                                       const Run* runs) {
  deform_block_impl<false>(k, A, B, seg, begin, end, runs);
}

__attribute__((target("avx2"))) void deform_block_axial_avx2(const Kernel& k, const float* A,
                                                             const float* B, const Segment* seg,
                                                             std::uint32_t begin,
                                                             std::uint32_t end, const Run* runs) {
  deform_block_impl<true>(k, A, B, seg, begin, end, runs);
}

}  // namespace

bool cpu_has_avx2() {
  return __builtin_cpu_supports("avx2");
}

void FastDeformer::force_kernel_form(KernelForm form) {
  if (form == KernelForm::avx2 && !cpu_has_avx2())
    fail(ErrorCategory::unsupported, "this CPU has no AVX2: the AVX2 kernel cannot run");
  form_ = form;
}

FastDeformer::FastDeformer(const SweepShape& rest, const bind::SweepBinding& bound,
                           std::span<const Vec3f> rest_positions, int stations_per_span)
    : n_(rest.radial_count), stations_per_span_(stations_per_span) {
  assert(stations_per_span >= 1 && rest.section_count() >= 2 && n_ >= 3);
  const int k = rest.section_count();
  const int per = stations_per_span;
  station_count_ = (k - 1) * per + 1;
  row_ = kCells + 4 * n_;
  stations_.assign(static_cast<std::size_t>(station_count_) * row_, 0.0f);
  basis_.resize(4 * (per + 1));
  for (int q = 0; q <= per; ++q) hermite(static_cast<double>(q) / per, &basis_[4 * q]);
  section_cells_.resize(static_cast<std::size_t>(k) * 4 * n_);
  slopes_.resize(8 * static_cast<std::size_t>(n_));
  sines_.resize(per + 1);

  // Station parameters, as the table places them: t_s + (t_{s+1} − t_s)·q/S.
  std::vector<double> station_t;
  station_t.reserve(station_count_);
  for (int s = 0; s + 1 < k; ++s) {
    for (int q = 0; q < per; ++q)
      station_t.push_back(rest.t[s] + (rest.t[s + 1] - rest.t[s]) * q / per);
  }
  station_t.push_back(rest.length());

  // Span p (clamped, so cap vertices beyond the ends join the end spans) and angle cell j of each
  // vertex, in binding order (= mesh order).
  const std::size_t count = bound.size();
  // Grouped positions are uint32 with room for a block and the padding past the last one.
  constexpr std::size_t kMaxVertices =
      std::numeric_limits<std::uint32_t>::max() - kBlockVertices - static_cast<std::size_t>(kPad);
  if (count > kMaxVertices) {
    fail(ErrorCategory::unsupported, "a sweep binds " + std::to_string(count) +
                                         " vertices; the fast path takes at most " +
                                         std::to_string(kMaxVertices));
  }
  const std::size_t spans = station_t.size() - 1;
  std::vector<std::uint32_t> span_of(count), cell_of(count);
  std::vector<float> u(count), w(count);
  for (std::size_t v = 0; v < count; ++v) {
    const double t = bound.t[v];
    const auto it = std::upper_bound(station_t.begin(), station_t.end(), t);
    const std::size_t p =
        std::min<std::size_t>(std::max<std::ptrdiff_t>(it - station_t.begin() - 1, 0), spans - 1);
    const AngleCoord ac = locate_angle(n_, bound.theta[v]);
    span_of[v] = static_cast<std::uint32_t>(p);
    cell_of[v] = static_cast<std::uint32_t>(ac.j);
    u[v] = static_cast<float>(
        std::clamp((t - station_t[p]) / (station_t[p + 1] - station_t[p]), 0.0, 1.0));
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
  std::vector<std::uint32_t> piece_size(pieces, 0), piece_segments(pieces, 0),
      last_cell(pieces, n_);
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
    for (std::size_t v = 0; v < count; ++v)
      order[fill[piece_of(v)]++] = static_cast<std::uint32_t>(v);
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
        if (i + 1 == blk.end || grouped_cell[i + 1] != grouped_cell[i])
          segments_.push_back({i + 1, grouped_cell[i]});
      }
      blk.axial = std::any_of(z_.begin() + blk.begin, z_.begin() + blk.end,
                              [](float z) { return z != 0.0f; });
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

void FastDeformer::tabulate(const SweepShape& shape) {
  tabulate(shape, parallel_);
}

void FastDeformer::tabulate(const SweepShape& shape, bool split) {
  assert(shape.section_count() * stations_per_span_ - stations_per_span_ + 1 == station_count_);
  assert(shape.radial_count == n_);
  const int k = shape.section_count(), n = n_, per = stations_per_span_;
  double lowest =
      shape.radii.empty() ? 0.0 : *std::min_element(shape.radii.begin(), shape.radii.end());
  radius_floor_ = static_cast<float>(kMinRadiusFraction * lowest);
  // Scratch for one span at a time: slopes (8n floats) and slerp sines (S + 1), one set a thread.
  const std::size_t w4 = 4 * static_cast<std::size_t>(n);
  const int slots = split ? omp_get_max_threads() : 1;
  if (slopes_.size() < slots * 2 * w4) slopes_.resize(slots * 2 * w4);
  if (sines_.size() < static_cast<std::size_t>(slots * (per + 1))) sines_.resize(slots * (per + 1));
  // Each section's periodic Catmull-Rom, cell j through samples p0..p3 = r_{j-1}..r_{j+2}, as the
  // cubic p1 + w·c1 + w²·c2 + w³·c3 in the cell's coordinate w.
  for (int i = 0; i < k; ++i) {
    const double* r = shape.radii.data() + static_cast<std::size_t>(i) * n;
    float* cell = section_cells_.data() + static_cast<std::size_t>(i) * 4 * n;
    for (int j = 0; j < n; ++j) {
      const double p0 = r[(j + n - 1) % n], p1 = r[j], p2 = r[(j + 1) % n], p3 = r[(j + 2) % n];
      cell[4 * j] = static_cast<float>(p1);
      cell[4 * j + 1] = static_cast<float>(0.5 * (p2 - p0));
      cell[4 * j + 2] = static_cast<float>(p0 - 2.5 * p1 + 2 * p2 - 0.5 * p3);
      cell[4 * j + 3] = static_cast<float>(0.5 * (p3 - p0) + 1.5 * (p1 - p2));
    }
  }

  // Each span's stations, from its two sections and their neighbours: spans are independent.
  const auto span = [&](int s, int slot) {
    double* const sines = sines_.data() + static_cast<std::size_t>(slot) * (per + 1);
    const Frame& fa = shape.frames[s];
    const Frame& fb = shape.frames[s + 1];
    const double h = shape.t[s + 1] - shape.t[s];
    const Vec3 ca = fa.center, cb = fb.center;
    const Vec3 ta = h * fa.axis(), tb = h * fb.axis();
    // Slerp as Eigen does it (rotation_at), with sin(q·δ), δ = θ/S, from the angle-addition
    // recurrence sin((q+1)δ) = 2 cos δ · sin(qδ) − sin((q−1)δ): four transcendentals a span, not a
    // station.
    const double d = fa.rotation.dot(fb.rotation);
    const double abs_d = std::abs(d);
    const bool linear = abs_d >= 1.0 - Eigen::NumTraits<double>::epsilon();
    double inv_sin = 0;
    if (!linear) {
      const double theta = std::acos(abs_d);
      const double delta = theta / per;
      const double c2 = 2 * std::cos(delta);
      sines[0] = 0;
      sines[1] = std::sin(delta);
      for (int q = 1; q < per; ++q) sines[q + 1] = c2 * sines[q] - sines[q - 1];
      sines[per] = std::sin(theta);  // exact at the end
      inv_sin = 1.0 / sines[per];
    }
    const Eigen::Vector4d qa = fa.rotation.coeffs();
    const Eigen::Vector4d qb = (d < 0 ? -1.0 : 1.0) * fb.rotation.coeffs();
    // The radius cubics are linear in the radii, and so is the Hermite in t: the station's cubics
    // are the Hermite combination of the sections' cubics and of their finite-difference slopes
    // (one-sided at the end sections) times h, exactly as radii_at_samples interpolates the radii.
    const int lo0 = std::max(s - 1, 0), hi0 = std::min(s + 1, k - 1);
    const int lo1 = s, hi1 = std::min(s + 2, k - 1);
    const float g0 = static_cast<float>(h / (shape.t[hi0] - shape.t[lo0]));
    const float g1 = static_cast<float>(h / (shape.t[hi1] - shape.t[lo1]));
    const float* k0 = section_cells_.data() + s * w4;
    const float* k1 = k0 + w4;
    const float *l0 = section_cells_.data() + lo0 * w4, *u0 = section_cells_.data() + hi0 * w4;
    const float *l1 = section_cells_.data() + lo1 * w4, *u1 = section_cells_.data() + hi1 * w4;
    float* const m0 = slopes_.data() + static_cast<std::size_t>(slot) * 2 * w4;
    float* const m1 = m0 + w4;
    for (std::size_t e = 0; e < w4; ++e) {
      m0[e] = g0 * (u0[e] - l0[e]);
      m1[e] = g1 * (u1[e] - l1[e]);
    }

    const int last = s + 2 == k ? per : per - 1;  // the last span also writes the tip station
    for (int q = 0; q <= last; ++q) {
      const double* hb = &basis_[4 * q];
      float* row = stations_.data() + static_cast<std::size_t>(s * per + q) * row_;
      const Vec3 c = hb[0] * ca + hb[1] * ta + hb[2] * cb + hb[3] * tb;
      Quat rot;
      if (linear) {
        const double uq = static_cast<double>(q) / per;
        rot.coeffs() = (1 - uq) * qa + uq * qb;
      } else {
        rot.coeffs() = (sines[per - q] * inv_sin) * qa + (sines[q] * inv_sin) * qb;
      }
      const Mat3 r = rot.normalized().toRotationMatrix();
      for (int e = 0; e < 3; ++e) {
        row[kCenter + e] = static_cast<float>(c[e]);
        row[kAxisX + e] = static_cast<float>(r(e, 0));
        row[kAxisY + e] = static_cast<float>(r(e, 1));
        row[kAxisZ + e] = static_cast<float>(r(e, 2));
      }
      const float b0 = static_cast<float>(hb[0]), b1 = static_cast<float>(hb[1]);
      const float b2 = static_cast<float>(hb[2]), b3 = static_cast<float>(hb[3]);
      float* cell = row + kCells;
      for (std::size_t e = 0; e < w4; ++e)
        cell[e] = b0 * k0[e] + b1 * m0[e] + b2 * k1[e] + b3 * m1[e];
    }
  };
  if (split && k > 2) {
#pragma omp parallel for schedule(static)
    for (int s = 0; s < k - 1; ++s) span(s, omp_get_thread_num());
  } else {
    for (int s = 0; s < k - 1; ++s) span(s, 0);
  }
}

std::size_t FastDeformer::direct_block_count() const {
  return static_cast<std::size_t>(
      std::count_if(blocks_.begin(), blocks_.end(), [&](const Block& b) {
        return b.runs != kNoRuns && runs_[b.runs].length == b.end - b.begin;
      }));
}

void FastDeformer::deform(const SweepShape& deformed, std::span<Vec3f> out) {
  deform(deformed, out, parallel_);
}

void FastDeformer::deform(const SweepShape& deformed, std::span<Vec3f> out, bool split) {
  tabulate(deformed, split);
  deform_vertices(out, split);
}

void FastDeformer::deform_vertices(std::span<Vec3f> out, bool split) const {
  const std::ptrdiff_t blocks = static_cast<std::ptrdiff_t>(blocks_.size());
  Kernel k;
  k.floor = radius_floor_;
  k.u = u_.data();
  k.w = w_.data();
  k.a = a_.data();
  k.b = b_.data();
  k.z = z_.data();
  k.vertex = vertex_.data();
  k.out = out.data()->data();
  const float* const tab = stations_.data();
#pragma omp parallel for schedule(static) if (split)
  for (std::ptrdiff_t bi = 0; bi < blocks; ++bi) {
    const Block& blk = blocks_[bi];
    const float* A = tab + static_cast<std::size_t>(blk.span) * row_;
    const Segment* seg = segments_.data() + blk.segments;
    const Run* runs = blk.runs == kNoRuns ? nullptr : runs_.data() + blk.runs;
    if (form_ != KernelForm::automatic) {
      const bool avx2 = form_ == KernelForm::avx2;
      const BlockFunction forced =
          blk.axial ? (avx2 ? deform_block_axial_avx2 : deform_block_axial_baseline)
                    : (avx2 ? deform_block_avx2 : deform_block_baseline);
      forced(k, A, A + row_, seg, blk.begin, blk.end, runs);
    } else if (blk.axial) {
      deform_block_axial(k, A, A + row_, seg, blk.begin, blk.end, runs);
    } else {
      deform_block(k, A, A + row_, seg, blk.begin, blk.end, runs);
    }
  }
  for (std::size_t b = 0; b < blend_index_.size(); ++b) {
    Vec3f& o = out[vertex_[blend_index_[b]]];
    o = blend_rest_[b] + blend_weight_[b] * (o - blend_rest_[b]);
  }
}

void deform_sweeps(std::span<const DeformJob> jobs, std::span<Vec3f> out) {
  const bool side_by_side =
      jobs.size() > 1 && std::none_of(jobs.begin(), jobs.end(),
                                      [](const DeformJob& j) { return j.fast->is_parallel(); });
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(jobs.size());
  if (side_by_side) {
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t j = 0; j < count; ++j) jobs[j].fast->deform(*jobs[j].shape, out);
  } else if (count == 1 && jobs[0].fast->vertex_count() >= kSplitLoneSweepVertices) {
    jobs[0].fast->deform(*jobs[0].shape, out, true);
  } else {
    for (const DeformJob& j : jobs) j.fast->deform(*j.shape, out);
  }
}

}  // namespace sweep::sim
