// The fast deformation path, per frame: rebuilding the bound vertices from the station table
// (fast_deform.h) — the per-block kernel in its compiled forms (AVX2 and baseline x86-64), the
// blend-zone fix-up, and the drivers that tabulate and rebuild one sweep or a frame's sweeps.
#include <omp.h>

#include <algorithm>
#include <cassert>
#include <cstdint>

#include "sweep/bind/fast_deform.h"
#include "sweep/bind/fast_deform_detail.h"
#include "sweep/core/error.h"

namespace sweep::bind {
namespace {

using detail::kCells;
using detail::kPad;
using Run = FastDeformer::Run;
using Segment = FastDeformer::Segment;

// What the per-block kernel reads and writes (FastDeformer's arrays).
struct Kernel {
  float floor;
  const float *u, *w, *a, *b, *z;
  const std::uint32_t* vertex;
  float* out;
  bool grouped;  // out in the grouped order (vertex i of the arrays at out + 3i), not the mesh's
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
[[gnu::always_inline]] inline void deform_block_impl(const Kernel& k, const float* A, const float* B,
                                                     const Segment* seg, std::uint32_t begin, std::uint32_t end,
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
    const std::ptrdiff_t len = (static_cast<std::ptrdiff_t>(hi) - static_cast<std::ptrdiff_t>(lo) + kPad - 1) & -kPad;
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
  // A block whose mesh indices are one contiguous run is written straight to the mesh, and every
  // block straight to an output in the grouped order.
  if (k.grouped || (runs != nullptr && runs->length == m)) {
    float* o = k.out + 3 * static_cast<std::size_t>(k.grouped ? begin : k.vertex[begin]);
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

__attribute__((target_clones("avx2", "default"))) void deform_block(const Kernel& k, const float* A, const float* B,
                                                                    const Segment* seg, std::uint32_t begin,
                                                                    std::uint32_t end, const Run* runs) {
  deform_block_impl<false>(k, A, B, seg, begin, end, runs);
}

__attribute__((target_clones("avx2", "default"))) void deform_block_axial(const Kernel& k, const float* A,
                                                                          const float* B, const Segment* seg,
                                                                          std::uint32_t begin, std::uint32_t end,
                                                                          const Run* runs) {
  deform_block_impl<true>(k, A, B, seg, begin, end, runs);
}

// The same kernels compiled for one target only, for tests that compare the forms
// (FastDeformer::force_kernel_form); production calls the target_clones above.
using BlockFunction = void (*)(const Kernel&, const float*, const float*, const Segment*, std::uint32_t, std::uint32_t,
                               const Run*);

void deform_block_baseline(const Kernel& k, const float* A, const float* B, const Segment* seg, std::uint32_t begin,
                           std::uint32_t end, const Run* runs) {
  deform_block_impl<false>(k, A, B, seg, begin, end, runs);
}

void deform_block_axial_baseline(const Kernel& k, const float* A, const float* B, const Segment* seg,
                                 std::uint32_t begin, std::uint32_t end, const Run* runs) {
  deform_block_impl<true>(k, A, B, seg, begin, end, runs);
}

__attribute__((target("avx2"))) void deform_block_avx2(const Kernel& k, const float* A, const float* B,
                                                       const Segment* seg, std::uint32_t begin, std::uint32_t end,
                                                       const Run* runs) {
  deform_block_impl<false>(k, A, B, seg, begin, end, runs);
}

__attribute__((target("avx2"))) void deform_block_axial_avx2(const Kernel& k, const float* A, const float* B,
                                                             const Segment* seg, std::uint32_t begin, std::uint32_t end,
                                                             const Run* runs) {
  deform_block_impl<true>(k, A, B, seg, begin, end, runs);
}

}  // namespace

// Plain loops over the flat floats, which the compiler vectorizes (the Eigen per-vertex product
// did not).
__attribute__((target_clones("avx2", "default"))) void transform_flat(const float* in, std::size_t count,
                                                                      const float* m, float* out) {
  const float r00 = m[0], r10 = m[1], r20 = m[2], r01 = m[3], r11 = m[4], r21 = m[5];
  const float r02 = m[6], r12 = m[7], r22 = m[8], t0 = m[9], t1 = m[10], t2 = m[11];
  for (std::size_t v = 0; v < count; ++v) {
    const float x = in[3 * v], y = in[3 * v + 1], z = in[3 * v + 2];
    out[3 * v] = r00 * x + r01 * y + r02 * z + t0;
    out[3 * v + 1] = r10 * x + r11 * y + r12 * z + t1;
    out[3 * v + 2] = r20 * x + r21 * y + r22 * z + t2;
  }
}

void transform_positions(std::span<const Vec3f> in, const Eigen::Matrix3f& rotation, const Vec3f& translation,
                         float* out) {
  float m[12];
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) m[3 * c + r] = rotation(r, c);
    m[9 + c] = translation[c];
  }
  transform_flat(in.data()->data(), in.size(), m, out);
}

bool cpu_has_avx2() {
  return __builtin_cpu_supports("avx2");
}

void FastDeformer::force_kernel_form(KernelForm form) {
  if (form == KernelForm::avx2 && !cpu_has_avx2())
    fail(ErrorCategory::unsupported, "this CPU has no AVX2: the AVX2 kernel cannot run");
  form_ = form;
}

void FastDeformer::deform(const SweepShape& deformed, std::span<Vec3f> out) {
  deform(deformed, out, parallel_);
}

void FastDeformer::deform(const SweepShape& deformed, std::span<Vec3f> out, bool split) {
  tabulate(deformed, split);
  deform_vertices(out, split);
}

void FastDeformer::deform_vertices(std::span<Vec3f> out, bool split) const {
  run_blocks(out.data()->data(), false, split);
  for (std::size_t b = 0; b < blend_index_.size(); ++b) {
    Vec3f& o = out[vertex_[blend_index_[b]]];
    o = blend_rest_[b] + blend_weight_[b] * (o - blend_rest_[b]);
  }
}

void FastDeformer::deform_grouped(const SweepShape& deformed, std::span<Vec3f> out) {
  assert(out.size() == vertex_.size());
  tabulate(deformed, false);
  run_blocks(out.data()->data(), true, false);
  for (std::size_t b = 0; b < blend_index_.size(); ++b) {
    Vec3f& o = out[blend_index_[b]];
    o = blend_rest_[b] + blend_weight_[b] * (o - blend_rest_[b]);
  }
}

void FastDeformer::run_blocks(float* out, bool grouped, bool split) const {
  const std::ptrdiff_t blocks = static_cast<std::ptrdiff_t>(blocks_.size());
  Kernel k;
  k.floor = radius_floor_;
  k.u = u_.data();
  k.w = w_.data();
  k.a = a_.data();
  k.b = b_.data();
  k.z = z_.data();
  k.vertex = vertex_.data();
  k.out = out;
  k.grouped = grouped;
  const float* const tab = stations_.data();
  const auto run_block = [&](std::ptrdiff_t bi) {
    const Block& blk = blocks_[bi];
    const float* A = tab + static_cast<std::size_t>(blk.span) * row_;
    const Segment* seg = segments_.data() + blk.segments;
    const Run* runs = blk.runs == kNoRuns ? nullptr : runs_.data() + blk.runs;
    if (form_ != KernelForm::automatic) {
      const bool avx2 = form_ == KernelForm::avx2;
      const BlockFunction forced = blk.axial ? (avx2 ? deform_block_axial_avx2 : deform_block_axial_baseline)
                                             : (avx2 ? deform_block_avx2 : deform_block_baseline);
      forced(k, A, A + row_, seg, blk.begin, blk.end, runs);
    } else if (blk.axial) {
      deform_block_axial(k, A, A + row_, seg, blk.begin, blk.end, runs);
    } else {
      deform_block(k, A, A + row_, seg, blk.begin, blk.end, runs);
    }
  };
  // Serial without entering a parallel region: even on one thread, libgomp allocates a team for
  // each region entered, and a game's frame must not allocate.
  if (split) {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t bi = 0; bi < blocks; ++bi) run_block(bi);
  } else {
    for (std::ptrdiff_t bi = 0; bi < blocks; ++bi) run_block(bi);
  }
}

void deform_sweeps(std::span<const DeformJob> jobs, std::span<Vec3f> out) {
  const bool side_by_side = jobs.size() > 1 && std::none_of(jobs.begin(), jobs.end(),
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

}  // namespace sweep::bind
