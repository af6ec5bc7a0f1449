#pragma once
// The fast deformation path, in three parts: the layout of the bound vertices,
// planned at construction (fast_deform_layout.cpp); the per-frame station table (tabulate,
// fast_deform_stations.cpp); and the kernel that rebuilds the vertices from it (deform_vertices,
// fast_deform_kernel.cpp).
//
// Each frame the moving sweep is evaluated once at `stations_per_span` stations per span of its
// key sections (tabulate, with the core's interpolants): centre, the three frame
// axes, and for every angle cell [θ_j, θ_{j+1}) the cubic in the cell's local coordinate w that
// the periodic Catmull-Rom through the station's radii reduces to. A bound vertex is then rebuilt
// (deform_vertices) from the two stations around it, linear in t between them:
//     r  = max(floor, P_A(w) + u·(P_B(w) − P_A(w)))        (P_A, P_B: the cell's cubics at A, B)
//     v' = C(u) + X(u)·(r·s cos θ) + Y(u)·(r·s sin θ) + Z(u)·z,   C(u) = C_A + u·(C_B − C_A), ...
//
// Layout is deliberate: layout wins, arithmetic does not. At construction the bound
// vertices are cut into tiles of kTileVertices consecutive ones (mesh order) and each tile is
// grouped by station span, so the two stations a vertex needs are loop invariants of its block (no
// gathers) and the stores of a tile stay within a window that is in cache until it is complete.
// Within a piece (a span's vertices of one tile) they keep mesh order when that order already
// holds the angle cells together in long segments (a ring-ordered mesh, as generated tubes and
// many scanned parts are): each block is then one contiguous range of the mesh, computed straight
// into it, and the stores stream like a copy. Otherwise they are sorted by angle cell (mesh order
// kept within a cell) and written back from L1 scratch run by run or vertex by vertex. Per vertex
// the loop reads only u, w, s·cos θ and s·sin θ (16 bytes; z too in blocks with cap vertices) and
// writes 12. Each block of at most kBlockVertices vertices of one piece is done in short loops —
// radii segment by segment (each segment's cubic is loop invariant), then positions over the
// block — vectorized by the compiler, 8 vertices a vector with AVX2 (no FMA) and 4 on baseline
// x86-64; both forms give the same bits (KernelForm). Layout and thresholds were chosen by
// measurement (measurements: BENCHMARKS.md, section "Layout and thread thresholds").
//
// Results do not depend on the thread count, the vertex order or the kernel form: every vertex is
// computed on its own, by the same IEEE operations in the same order, whichever thread, layout or
// form runs its block.
//
// Error against the exact path (deform_point in double, same binding, same shape): at the stations
// the fast path is the exact sweep to float precision; between them it interpolates linearly in t,
// so the error falls as the square of the station spacing until float rounding (~1e-6 of the
// part's size) is reached. That holds for the rest shape too: a bound vertex comes back to its
// rest position to float precision only on a station plane, elsewhere to that interpolation error
// (tests/bind/fast_deform_test.cpp). The default is 8 stations per span (measurements:
// BENCHMARKS.md, section "Deformation: stations per span against error").
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "sweep/bind/bind.h"
#include "sweep/core/sweep_shape.h"

namespace sweep::bind {

using Vec3f = Eigen::Vector3f;

// Below this many bound vertices deform() runs on one thread (waking a thread team costs more than
// the loop saves; measurements: BENCHMARKS.md, section "Layout and thread thresholds").
inline constexpr std::size_t kParallelVertexThreshold = 40000;
// A sweep that is the only one moving in a frame is split across the threads (deform_sweeps) from
// this many bound vertices (same section).
inline constexpr std::size_t kSplitLoneSweepVertices = 4096;

// Vertices of one work block (one station span): the block's scratch (4 floats a vertex) stays in
// L1.
inline constexpr std::uint32_t kBlockVertices = 256;

// The compiled forms of the per-vertex kernel (deform_vertices). `automatic` is what production
// runs: the AVX2 form on a CPU with AVX2, baseline x86-64 otherwise, picked once at load time.
// Neither form uses FMA and both do the same IEEE operations in the same order, so they give the
// same bits; forcing one form is how the tests check that (tests/bind/fast_deform_test.cpp).
enum class KernelForm { automatic, baseline, avx2 };
// Whether this CPU can run KernelForm::avx2.
bool cpu_has_avx2();

class FastDeformer {
 public:
  // Consecutive bound vertices (mesh order) laid out together: their 768 KB of output stays in
  // cache while it is written, whatever the mesh order (the size: BENCHMARKS.md, section "Layout
  // and thread thresholds").
  static constexpr std::uint32_t kTileVertices = 65536;
  // A piece (a span's vertices within a tile) keeps mesh order when its angle-cell segments in
  // that order are at least this long on average. (A block of such a piece may still hold some
  // short segments; each costs a whole vector of radii, kPad, which the average bounds.)
  static constexpr std::uint32_t kMinMeanSegmentLength = 8;

  // A run of grouped vertices [start, start + length) whose mesh indices are consecutive.
  struct Run {
    std::uint32_t start = 0, length = 0;
  };
  // Grouped vertices from the previous segment's end (or the block's begin) up to `end`, all in
  // angle cell `cell`.
  struct Segment {
    std::uint32_t end = 0, cell = 0;
  };

  // `rest_positions` is the whole mesh in float (blend-zone vertices need their rest position).
  FastDeformer(const SweepShape& rest, const bind::SweepBinding& bound, std::span<const Vec3f> rest_positions,
               int stations_per_span = 8);

  // Writes the deformed positions of this sweep's vertices into `out` (the whole mesh, mesh order):
  // tabulate(deformed), then deform_vertices(out). `split`: the blocks across the threads
  // (default: from kParallelVertexThreshold vertices).
  void deform(const SweepShape& deformed, std::span<Vec3f> out);
  void deform(const SweepShape& deformed, std::span<Vec3f> out, bool split);

  // The two halves, separately timed by the benchmarks: evaluate the station table of `deformed`
  // (same K, n and parameters as the rest shape), and rebuild the vertices from the current table.
  void tabulate(const SweepShape& deformed);
  void tabulate(const SweepShape& deformed, bool split);  // split: spans across the threads
  void deform_vertices(std::span<Vec3f> out) const { deform_vertices(out, parallel_); }
  void deform_vertices(std::span<Vec3f> out, bool split) const;

  // The live runtime's form (sim/live_positions.h): tabulate(deformed) on this thread, then this
  // sweep's vertices into `out` in the grouped order — out[i] is mesh vertex grouped_vertices()[i],
  // vertex_count() of them — each by the same operations as deform() (the same bits), its stores
  // contiguous whatever the mesh's vertex order.
  void deform_grouped(const SweepShape& deformed, std::span<Vec3f> out);
  std::span<const std::uint32_t> grouped_vertices() const { return vertex_; }

  std::size_t vertex_count() const { return vertex_.size(); }
  // Whether deform_vertices splits its blocks across the threads (kParallelVertexThreshold).
  bool is_parallel() const { return parallel_; }
  int station_count() const { return station_count_; }
  // Work blocks, and those among them written straight into the mesh (one contiguous run of mesh
  // indices): a diagnostic of the layout the vertex order allowed.
  std::size_t block_count() const { return blocks_.size(); }
  std::size_t direct_block_count() const;

  // For tests: run deform_vertices with one compiled form of the kernel from now on (default
  // automatic). Throws Error(unsupported) for KernelForm::avx2 when !cpu_has_avx2().
  void force_kernel_form(KernelForm form);
  KernelForm kernel_form() const { return form_; }

 private:
  struct Block {
    std::uint32_t begin = 0, end = 0;  // vertices [begin, end) of the grouped arrays
    std::uint32_t span = 0;            // station span: stations span and span + 1
    std::uint32_t segments = 0;        // first of the block's angle-cell segments in segments_
    bool axial = false;                // some vertex has an axial offset z ≠ 0 (a cap vertex)
    std::uint32_t runs = kNoRuns;      // first of the block's runs in runs_, or kNoRuns
  };
  static constexpr std::uint32_t kNoRuns = 0xffffffffu;
  // The kernel over every block into `out` (flat floats): in mesh order, or (grouped) in the
  // grouped order; the blend fix-up is the caller's.
  void run_blocks(float* out, bool grouped, bool split) const;
  // Blocks whose mesh indices come in runs at least this long on average write back run by run.
  static constexpr std::uint32_t kMinMeanRunLength = 8;

  int n_ = 0;                        // radial samples = angle cells
  int stations_per_span_ = 0;        // S
  int station_count_ = 0;            // (K − 1)·S + 1
  int row_ = 0;                      // floats per station: 12 (C, X, Y, Z) + 4 per angle cell
  std::vector<HermiteBasis> basis_;  // at u = q/S, q = 0..S
  std::vector<float> stations_;      // row_ floats a station, rewritten each frame
  // Per-frame scratch of tabulate: each section's cell cubics (K·4n); and, one set for each
  // thread working on a span, its cubics' slopes in t at both ends (2·4n) and the slerped
  // rotations of its stations (S + 1).
  std::vector<float> section_cells_, slopes_;
  std::vector<Quat> rotations_;

  // Per vertex, grouped by station span (then by angle cell, or in mesh order). Hot fields first.
  std::vector<float> u_;               // position between the span's two stations, [0, 1]
  std::vector<float> w_;               // position in the angle cell, [0, 1)
  std::vector<float> a_, b_, z_;       // s·cos θ, s·sin θ, axial offset
  std::vector<std::uint32_t> vertex_;  // mesh index
  std::vector<Segment> segments_;      // each block's, in order
  std::vector<Block> blocks_;
  std::vector<Run> runs_;  // each run-wise block's runs, ended by a zero-length run
  bool parallel_ = false;
  // Blend-zone vertices (weight < 1): indices into the arrays above, with weight and rest position.
  std::vector<std::uint32_t> blend_index_;
  std::vector<float> blend_weight_;
  std::vector<Vec3f> blend_rest_;
  float radius_floor_ = 0;
  KernelForm form_ = KernelForm::automatic;
};

// One sweep's share of a frame: its fast path and its deformed shape.
struct DeformJob {
  FastDeformer* fast = nullptr;
  const SweepShape* shape = nullptr;
};

// Deforms every job into `out` (the whole mesh; sweeps own disjoint vertices). When there are
// several and none is big enough to split (kParallelVertexThreshold), they run side by side on the
// threads — a diplodocus's tail and neck; a lone one is split across the threads from
// kSplitLoneSweepVertices; otherwise one after another, each split across the threads if large.
// Either way the results do not depend on the thread count.
void deform_sweeps(std::span<const DeformJob> jobs, std::span<Vec3f> out);

// out[v] = rotation · in[v] + translation for every vertex, as flat x y z floats: the world-space copy
// of a mesh an engine uploads (compiled as the kernel is: -O3, AVX2 or baseline x86-64, no FMA).
void transform_positions(std::span<const Vec3f> in, const Eigen::Matrix3f& rotation, const Vec3f& translation,
                         float* out);
// The loop behind it on flat floats: out = R · p + t for `count` points, `m` the rotation column by
// column (9 floats) then the translation (3). Callers that must match transform_positions' bits (the
// live positions' band kernel at its ends) call this one.
void transform_flat(const float* in, std::size_t count, const float* m, float* out);

}  // namespace sweep::bind
