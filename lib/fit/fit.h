#pragma once
// Fitting a sweep to a tubular part of a mesh (the work behind sweep-fit):
//  1. the tip: the vertex nearest to the given point (or the given vertex), moved to the part's
//     end by climbing the surface distance from the body (a tip a few radii off is fine);
//  2. rings of equal surface distance from it (fit/rings.h) up to the root — the given root
//     (on the axis, on the surface or inside the body near where the part leaves it), or, when
//     none is given, where the ring size jumps as the rings spread over the body;
//  3. the ring centroids, smoothed and moved to the centroids of plane slices normal to them
//     (fit/trace.h), are the axis; K key sections are cut by planes normal to it, evenly spaced
//     in arc length, with rotation-minimizing frames (no added twist), n radii each by rays;
//  4. the part: the surface reached from the tip without crossing the root section
//     (select_part), and the fit's error as true distances both ways (fit/surface_distance.h).
// A fit that stops short of the tip, a part that leaks past its root into the body, or an error
// above the limits below is returned with `problems`, which the tool turns into an error unless
// the user forces it: never a silently wrong rig.
//
//   FitResult r = fit_sweep(mesh, {.name = "tail", .tip = {...}});
//
// SweepFitter keeps the slicer (CGAL AABB tree) and the topology for fitting several parts of
// one mesh, or one part at several K and n.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "sweep/core/error.h"
#include "sweep/core/rig.h"
#include "sweep/core/topology.h"
#include "sweep/fit/rings.h"
#include "sweep/fit/trace.h"

namespace sweep::fit {

struct FitOptions {
  std::string name = "part";  // the sweep's name in the rig, e.g. "tail"
  // Where the part leaves the body: on its axis, on its surface, or inside the body near the
  // junction (mesh units). Absent: found where the ring size jumps (fit/rings.h).
  std::optional<Vec3> root;
  Vec3 tip = Vec3::Zero();       // at or near the part's end, a few radii off is fine
  std::int64_t tip_vertex = -1;  // >= 0: the part's end as a vertex index (no climb), not `tip`
  // An explicit axis polyline from root to tip (mesh units). When given it replaces the rings;
  // its first and last points are the root and the tip.
  std::vector<Vec3> axis;
  // Key sections K ≥ 2, evenly spaced in arc length. The fit error falls as K grows until the
  // radius samples and the mesh's own facets dominate (measurements: BENCHMARKS.md, section
  // "Fitting: K × n against fit time and fit error").
  int sections = 24;
  // Radius samples n ≥ 3 per section. Error falls as n grows until the mesh's own facets dominate
  // (same section).
  int radial = 24;
  // When > 0: use the fewest sections (at most max_sections) whose fit RMS is at most
  // tolerance × mean_radius; `sections` is then ignored. Unitless (0.01 = 1% of the mean radius).
  double tolerance = 0;
  int max_sections = 256;
  // Root and tip may lie at most this far from the mesh, as a fraction of the bounding box
  // diagonal; farther means the request names a point off the mesh.
  double seed_distance = 0.1;
  RingOptions rings;
  // The two-way distances (~5 ms for a 5,000-vertex part); they also tell where an end that is
  // not a tube begins (FitResult::end_cut): without them the sweep runs to the tip.
  bool measure_error = true;
  // Limits beyond which the fit is a problem (FitResult::problems):
  // the traced axis, root to tip, against the surface distance from the tip to the root ring
  // (a tube's axis is a little shorter than its surface over the tip's cap; far shorter is a
  // trace that stopped early, unless the axis ends within max_tip_gap mean radii of the tip);
  double min_length_ratio = 0.8;
  double max_tip_gap = 2;
  // the part's vertices that lie before the root section (those beyond the tip section, a foot or
  // a head, are carried along by it; those before the root are not the part);
  double max_beyond_root_share = 0.25;
  // the part's vertices farther from the tip than the root ring by more than two root radii: the
  // flood leaked past the root section into the body;
  double max_leak_share = 0.05;
  // The 90th percentile of the part vertices' distances from the fitted surface (FitError::p90),
  // over the mean radius.
  double max_error = 0.1;
  // The same the other way (FitError::surface_p90): the sweep's own surface against the part's
  // faces. Radii are fitted to the vertices, so a sweep that wanders off the mesh between them
  // (lion.off's second --all part: vertices 1.6 %, surface 55 %) shows only here. Twice
  // max_error: the sweep's caps and a flat part's rims sit a little off the faces where the
  // vertices do not (the parts --all accepts on 12 CGAL meshes reach 15 %, BENCHMARKS.md).
  double max_surface_error = 0.2;
};
// A key section whose loop is not star-shaped about its centre: some rays cross it more than
// once (the outermost crossing is used), or miss it (the centre lies outside the loop).
struct StarViolation {
  int section = 0;
  int multi_crossing_rays = 0;
  int missed_rays = 0;
};

// Distances between the part and the fitted surface, mesh units. The surface is the sweep's tube
// between its end sections, tessellated finely (its own interpolation error is < 0.2% of r).
struct FitError {
  double rms = 0;  // RMS distance of the measured part vertices to the surface
  double max = 0;  // largest such distance
  // The 90th percentile of those distances: what "most of the part" is off by. Unlike the RMS it
  // is blind to a few stray vertices (a fin, a spike), and still large when the axis strays.
  double p90 = 0;
  // The other way: samples of the sweep surface to the part's faces (a surface bulging where the
  // mesh does not shows here, not above).
  double surface_rms = 0;
  double surface_max = 0;
  // The 90th percentile of the surface samples' distances: a sweep that wanders off the part
  // (radii fitted to the vertices cannot show it) has a tenth of its surface far from every face.
  double surface_p90 = 0;
  double radial_rms = 0;              // RMS of |ρ − r(θ,t)|: the distance along the section's ray
  std::size_t measured_count = 0;     // part vertices whose section plane lies in [0, L]
  std::size_t beyond_ends_count = 0;  // part vertices past the end sections (caps), not measured
  std::size_t beyond_root_count = 0;  // ... of them, before section 0
  // Part vertices between the end sections but more than kPartReachRadii radii from the axis: a
  // protrusion the part carries along (a claw, a spike), not measured, as the caps are not.
  std::size_t protrusion_count = 0;
  std::size_t surface_samples = 0;
};

struct FitResult {
  SweepDef sweep;                            // name, rest shape (K sections, n radii), default springs, part seeds
  std::vector<std::uint32_t> part_vertices;  // the part's vertex indices, sorted
  AxisTrace axis;                            // the refined axis, root to tip end
  std::uint32_t tip_vertex = 0;              // the part's end: where the rings start
  Vec3 root = Vec3::Zero();                  // centre of section 0
  bool root_found = false;                   // true: no root was given; found where the rings meet the body
  std::string root_reason;                   // how the root was placed, for messages
  // The tube goes on past the tip (a hose, a knot, a torus): the tip was given mid-tube, so the
  // part is cut at the last key section too (PartSeeds::tip_cut) and the tip stays where it was
  // given; tip_cut_reason says how that was seen ("" when there is no tip-side cut).
  bool tip_cut = false;
  std::string tip_cut_reason;
  // The part's end is not a tube (a foot that spreads sideways, a hoof, a tuft): the sweep
  // fitted through it was far off there alone, so the sweep ends where the tube does, and the
  // part's vertices past its last section are carried rigidly by it, as a head is; traced_length
  // and surface_length are then the axis and the surface distance to there. end_cut_reason says
  // where and with what numbers ("" when the sweep runs to the tip).
  bool end_cut = false;
  std::string end_cut_reason;
  double length = 0;          // arc length of the axis from section 0 to K-1, mesh units
  double traced_length = 0;   // the axis from the root to the tip vertex, mesh units
  double surface_length = 0;  // surface distance from the tip vertex to the root ring
  double tip_gap = 0;         // from the axis' end to the tip vertex, mesh units
  // How far the given tip and root lie from the mesh's surface (its triangles), mesh units: 0
  // for a point on it (and for a tip given as a vertex, or no root); seeds farther than
  // seed_limit (FitOptions::seed_distance of the bounding box diagonal) are refused.
  double tip_off_surface = 0;
  double root_off_surface = 0;
  double seed_limit = 0;
  double mean_radius = 0;                      // mean of the K·n radius samples, mesh units
  std::size_t leaked_count = 0;                // part vertices far past the root ring (see max_leak_share)
  FitError error;                              // distances between the part's vertices and the fitted surface
  std::vector<StarViolation> star_violations;  // sections that are not star-shaped
  std::vector<std::string> warnings;           // things a user should know; the fit still holds
  // Limits of FitOptions that the fit breaks, with the numbers and what to try. Empty: a good fit.
  std::vector<std::string> problems;
  double seconds = 0;  // wall time of the fit (tracing, sections, selection, error), seconds
  double in_range_share() const {
    return part_vertices.empty()
               ? 0.0
               : static_cast<double>(error.measured_count) / static_cast<double>(part_vertices.size());
  }
  double beyond_root_share() const {
    return part_vertices.empty()
               ? 0.0
               : static_cast<double>(error.beyond_root_count) / static_cast<double>(part_vertices.size());
  }
};

class SweepFitter {
 public:
  // Checks the mesh (vertices, faces, finite coordinates: Error(bad_input) otherwise), and builds
  // the slicer and topology. Keeps a reference to `mesh`, which must outlive the fitter.
  explicit SweepFitter(const Mesh& mesh);
  ~SweepFitter();
  SweepFitter(SweepFitter&&) noexcept;
  SweepFitter& operator=(SweepFitter&&) = delete;

  // Throws Error(usage) naming the option's field for bad options (sections < 2, radial < 3,
  // non-finite points) and FitFailure (an Error(bad_input), or usage for a tip_vertex out of
  // range) for a request the mesh cannot meet (root or tip far from the mesh, no ring around the
  // tip, empty part). A fit that breaks a limit is returned with `problems`.
  FitResult fit(const FitOptions& options) const;

  const MeshSlicer& slicer() const;  // over the patched surface
  const Topology& topology() const;  // the mesh's own: parts are walked over it, as sweep-bind does
  // The topology with the mesh's holes patched (fit/hole_patches.h): what the surface distances,
  // their rings and the slices run over, and what find_parts searches.
  const Topology& patched_topology() const;
  double diagonal() const;  // of the mesh's bounding box

 private:
  const Mesh& mesh_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

FitResult fit_sweep(const Mesh& mesh, const FitOptions& options);

// What SweepFitter::fit throws for a request the mesh cannot meet (a seed far from the mesh, a
// tip not reachable, no rings, no length): an Error of its category with the message, and the
// fit as far as it got (`partial`: name, seeds and their distances from the surface, tip vertex,
// lengths, the axis when traced; no sections), so that a report can show the numbers.
class FitFailure : public Error {
 public:
  FitFailure(ErrorCategory category, const std::string& message, FitResult partial)
      : Error(category, message), partial_(std::make_shared<const FitResult>(std::move(partial))) {}
  const FitResult& partial() const { return *partial_; }

 private:
  std::shared_ptr<const FitResult> partial_;  // shared: an exception is copied as it is thrown
};

// The K-section, n-radius sweep along an axis (sections.cpp): sections evenly spaced in arc
// length, frames rotation-minimizing from the axis start, radii by rays (sample_radii). A section
// whose plane also cuts another surface (its loop over 1.5 local radii) is moved along the axis
// within 3/8 of the spacing, an end section inwards by up to a quarter of the length, to a plane
// that cuts the part alone; failing that, an interior section's radii are interpolated from its
// neighbours. An end section is moved too where its loop was pinched around another tube fused to
// the part (loop_around's necks); an interior one takes the part's piece of such a loop. Star-shape
// violations and warnings are appended when the pointers are given.
SweepShape sections_along(const MeshSlicer& slicer, const AxisTrace& axis, int sections, int radial,
                          std::vector<StarViolation>* violations = nullptr,
                          std::vector<std::string>* warnings = nullptr);

// Fits the radius samples of `shape` to the given part vertices by least squares (radii_fit.cpp):
// the radius r(θ, t) the samples give against each vertex's distance from the axis, with a
// small pull to the current (slice) radii and a second, robust pass. Centres and frames are kept.
// Returns the number of vertices used (0: nothing changed).
int fit_radii(SweepShape& shape, const Mesh& mesh, const std::vector<std::uint32_t>& vertices);

// Distances between the given part vertices and the sweep's surface, both ways (see FitError).
// The way back measures to the part's faces, and to `patches` (triangles over representatives:
// fit/hole_patches.h, `weld` the topology's) touching the part: over a hole, the patch is the
// surface's best stand-in, and without it a sample there is the hole's radius from any face.
// With `along`, each measured vertex's section parameter t and distance are appended to it.
FitError measure_fit_error(const SweepShape& shape, const Mesh& mesh, const std::vector<std::uint32_t>& vertices,
                           std::span<const std::uint32_t> patches = {}, std::span<const std::uint32_t> weld = {},
                           std::vector<std::pair<double, double>>* along = nullptr);

}  // namespace sweep::fit
