#pragma once
// Binding (the paper's §III): every vertex of each sweep's part gets sweep coordinates (t, θ, s, z)
// on that sweep's rest shape, so the deformed vertex is
//     v' = C'(t) + R'(t)·(s r'(θ,t) cos θ, s r'(θ,t) sin θ, z)
// and, with an optional blend zone at the part's root, v'' = v + w·(v' − v).
//
//   Binding b = bind_rig(rig, mesh, {.blend = 0.02});
//
// Which vertices a sweep binds:
//  - a sweep with part seeds (SweepDef::part, written by sweep-fit): the vertices of
//    select_part (core/topology.h) from part->tip, bounded by section 0's disc
//    (root_disc_radius), i.e. the surface reached from the tip without crossing the root section;
//    with part->tip_cut, select_part_between: bounded by the last section's disc too
//    (tip_disc_radius), so the tube beyond it stays unbound and never moves; and the loose pieces
//    lying against the part (bind/loose_pieces.h: a tuft of separate quads, unwelded vertices);
//  - a sweep without seeds (a rig written by hand): every vertex on the tip side of section 0's
//    plane whose located plane lies within the sweep (0 ≤ t ≤ L) and which lies inside the tube
//    widened by `seedless_radius_factor` (s ≤ factor), plus cap vertices beyond the tip section no
//    farther than factor × the tip section's largest radius along its axis. Nothing behind the
//    root plane is ever bound.
// Ownership where parts overlap: a vertex claimed by several sweeps belongs to the one whose
// surface it is nearest to, measured as |s − 1|·r(θ,t) + |z| in mesh units (the radial distance
// from the surface, plus the axial distance beyond an end section); exact ties go to the sweep
// that comes first in the rig. Vertices that no sweep binds stay unbound and never move.
// Blend: with blend = D > 0, a vertex at distance g beyond its sweep's root plane has weight
// w = smoothstep(g / D) = x²(3 − 2x) with x = clamp(g / D, 0, 1); w = 1 everywhere when D = 0. A
// part with a tip cut is blended out towards that cut too: w is then the product of the root's
// smoothstep and the same smoothstep of the distance g' before the last section's plane (with
// D = 0 the cut is a seam that opens as the tip moves: bind such a part with a blend).
// The result does not depend on the number of OpenMP threads (each vertex is independent).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "sweep/core/deform_point.h"
#include "sweep/core/mesh.h"
#include "sweep/core/rig.h"

namespace sweep::bind {

// The per-vertex loops of bind() (over a sweep's part) and of deform_exact and max_rebuild_error
// (over its bound vertices) run on one thread below this many vertices, across the OpenMP threads
// otherwise; the results are the same either way (measurements: BENCHMARKS.md, section "Layout
// and thread thresholds").
inline constexpr std::ptrdiff_t kMinParallelVertices = 16384;

struct BindOptions {
  // Depth of the blend zone beyond each part's root plane, mesh units; 0 = no blend (w = 1). Choose
  // about one root radius to hide the seam where a tail or neck leaves the body.
  double blend = 0;
  // Sweeps without part seeds only: how far outside the fitted surface a vertex may lie and still
  // be bound, as a multiple of the local radius (s ≤ factor). Unitless, ≥ 1; 1.5 takes the whole
  // tube and its skin folds while leaving distant body parts alone.
  double seedless_radius_factor = 1.5;
  // Stations per span of the locator's scan for cross-section planes (SweepLocator). More finds
  // planes in more strongly curved spans; 16 is plenty for fitted sweeps.
  int stations_per_span = 16;
};

// One sweep's table, structure of arrays in ascending mesh-vertex order. Coordinates are stored
// in float32 (the file keeps exactly these values; rebuilding the rest pose from them is exact to
// float precision).
struct SweepBinding {
  std::string name;                     // the sweep's name in the rig
  std::vector<std::uint32_t> vertices;  // bound mesh-vertex indices, strictly increasing
  std::vector<float> t;                 // arc-length parameter, [0, L] (mesh units)
  std::vector<float> theta;             // angle in the cross-section plane, [0, 2π) radians
  std::vector<float> s;                 // distance from the axis / surface radius (1 on the surface)
  std::vector<float> z;                 // axial offset beyond an end section, mesh units (0 inside)
  std::vector<float> weight;            // blend weight w ∈ [0, 1] (1 outside the blend zone)

  std::size_t size() const { return vertices.size(); }
  SweepCoords coords(std::size_t k) const { return {t[k], theta[k], s[k], z[k]}; }
};

struct Binding {
  std::uint64_t vertex_count = 0;    // vertices of the mesh it was made for
  std::uint64_t mesh_hash = 0;       // hash_positions of that mesh
  std::uint64_t rig_hash = 0;        // hash_sweeps of the rig it was made for
  std::vector<SweepBinding> sweeps;  // one per rig sweep, in rig order

  std::size_t bound_count() const;  // vertices bound by any sweep
};

struct SweepBindStats {
  std::string name;
  std::size_t part_vertex_count = 0;     // vertices the sweep's part selection claimed
  std::size_t bound_vertex_count = 0;    // of those, the ones it kept (after ownership)
  std::size_t blended_vertex_count = 0;  // bound vertices with weight < 1
  double length = 0;                     // the sweep's length L, mesh units
  // Largest distance between a bound vertex and its rest position rebuilt from the stored float32
  // coordinates (deform_point on the rest shape, no blend), mesh units.
  double rest_max_error = 0;
  // Loose pieces (bind/loose_pieces.h) that go with this sweep's part, and their vertices (counted
  // in part_vertex_count too).
  std::size_t loose_piece_count = 0;
  std::size_t loose_vertex_count = 0;
  double seconds = 0;  // wall time of this sweep's selection and location
};

struct BindResult {
  Binding binding;
  std::vector<SweepBindStats> sweeps;  // one per rig sweep, in rig order
  std::size_t unbound_vertex_count = 0;
  // Things the user should know; the binding holds: a loose piece next to a part left unbound
  // (it will not move with the part), named by its vertices.
  std::vector<std::string> warnings;
  double seconds = 0;  // wall time of the whole binding (hashes, selection, location, checks)
};

// Throws Error(usage) for bad options and Error(bad_input) when the mesh is empty, a sweep's shape
// is invalid, or a seeded part cannot be selected (its tip lies behind its root plane).
BindResult bind(const Rig& rig, const Mesh& mesh, const BindOptions& options = {});
inline Binding bind_rig(const Rig& rig, const Mesh& mesh, const BindOptions& options = {}) {
  return bind(rig, mesh, options).binding;
}

// FNV-1a 64 over the positions' exact bytes (x, y, z of each vertex as little-endian doubles).
std::uint64_t hash_positions(const std::vector<Vec3>& positions);
// FNV-1a 64 of what binding depends on, and only that (not the mesh path, springs, materials or
// force scales, so retuning a rig or moving its mesh keeps a binding valid), as numbers, not as
// any file's text: the bytes of kSweepHashTag, then u32 sweep count, then per sweep in rig order
//   u32 name length, the name's UTF-8 bytes, u32 K, u32 n,
//   per section i: f64 t_i, f64 quaternion w x y z, f64 centre x y z, f64 radii[i*n .. i*n+n-1],
//   u8 1 (u8 2 with a tip cut) and f64 part root x y z, tip x y z when the sweep has part seeds,
//   else u8 0;
// u32 and f64 little-endian (f64 as its IEEE-754 bits). Binding format 2 and later store it.
inline constexpr std::string_view kSweepHashTag = "sweep-rig-hash-2";
std::uint64_t hash_sweeps(const Rig& rig);

}  // namespace sweep::bind
