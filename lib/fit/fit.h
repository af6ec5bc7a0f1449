#pragma once
// Fitting a sweep to a tubular part of a mesh (the work behind sweep-fit): trace the part's axis
// by plane slices from a root point to a tip point, place K key sections along it with
// rotation-minimizing frames (no added twist), sample n radii per section by rays in the section
// plane, select the part's vertices, and measure how far they lie from the fitted surface.
//
//   FitResult r = fit_sweep(mesh, {.name = "tail", .root = {...}, .tip = {...}});
//
// SweepFitter keeps the slicer (CGAL AABB tree) and the vertex adjacency for fitting several parts
// of one mesh, or one part at several K and n.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/rig.h"
#include "fit/trace.h"

namespace sweep::fit {

struct FitOptions {
  std::string name = "part";  // the sweep's name in the rig, e.g. "tail"
  Vec3 root = Vec3::Zero();   // where the part leaves the body, near its axis (mesh units)
  Vec3 tip = Vec3::Zero();    // at or near the part's end (mesh units)
  // An explicit axis polyline from root to tip (mesh units). When given it replaces the traced
  // axis; root and tip above are still used for the part selection and the rig.
  std::vector<Vec3> axis;
  // Key sections K ≥ 2, evenly spaced in arc length. 16 fits a diplodocus tail to ~1% of its
  // mean radius; error falls roughly as 1/K² on smooth parts.
  int sections = 24;
  // Radius samples n ≥ 3 per section. Error falls as n grows until the mesh's own facets dominate.
  int radial = 24;
  // When > 0: use the fewest sections (at most max_sections) whose fit_rms is at most
  // tolerance × mean_radius; `sections` is then ignored. Unitless (0.01 = 1% of the mean radius).
  double tolerance = 0;
  int max_sections = 256;
  // Root and tip may lie at most this far from the mesh's nearest vertex, as a fraction of the
  // bounding box diagonal; farther means the request names a point off the mesh.
  double seed_distance = 0.1;
  TraceOptions trace;
  bool measure_error = true;  // locate every part vertex on the fitted sweep (costs ~2 µs a vertex)
};

// A key section whose loop is not star-shaped about its centre: some rays cross it more than
// once (the outermost crossing is used), or miss it (the centre lies outside the loop).
struct StarViolation {
  int section = 0;
  int multi_crossing_rays = 0;
  int missed_rays = 0;
};

struct FitError {
  double rms = 0;                  // RMS of |ρ − r(θ,t)| over the measured vertices, mesh units
  double max = 0;                  // largest |ρ − r(θ,t)|, mesh units
  std::size_t measured_count = 0;  // vertices with z == 0 (their plane lies within [0, L])
  std::size_t beyond_ends_count = 0;  // vertices past the end sections (z ≠ 0), not measured
};

struct FitResult {
  SweepDef sweep;  // name, rest shape (K sections, n radii), default springs, part seeds
  std::vector<std::uint32_t> part_vertices;  // the part's vertex indices, sorted
  AxisTrace axis;                            // the traced (or given) axis polyline
  double length = 0;       // arc length of the axis from section 0 to K-1, mesh units
  double mean_radius = 0;  // mean of the K·n radius samples, mesh units
  FitError error;          // distance of the part's vertices from the fitted surface
  std::vector<StarViolation> star_violations;  // sections that are not star-shaped
  std::vector<std::string> warnings;           // things a user should know; the fit still holds
  double seconds = 0;  // wall time of the fit (tracing, sections, selection, error), seconds
};

class SweepFitter {
 public:
  // Checks the mesh (vertices, faces, finite coordinates: Error(bad_input) otherwise), and builds
  // the slicer and adjacency. Keeps a reference to `mesh`, which must outlive the fitter.
  explicit SweepFitter(const Mesh& mesh);
  ~SweepFitter();
  SweepFitter(SweepFitter&&) noexcept;
  SweepFitter& operator=(SweepFitter&&) = delete;

  // Throws Error(usage) for bad options (K < 2, n < 3, non-finite points) and Error(bad_input)
  // for a request the mesh cannot meet (root or tip far from the mesh, tip not reachable from
  // the root, empty part).
  FitResult fit(const FitOptions& options) const;

  const MeshSlicer& slicer() const;

 private:
  const Mesh& mesh_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

FitResult fit_sweep(const Mesh& mesh, const FitOptions& options);

// The K-section, n-radius sweep along an axis: sections evenly spaced in arc length, frames
// rotation-minimizing from the axis start, radii by rays (sample_radii). Star-shape violations
// and warnings are appended when the pointers are given.
SweepShape sections_along(const MeshSlicer& slicer, const AxisTrace& axis, int sections, int radial,
                          std::vector<StarViolation>* violations = nullptr,
                          std::vector<std::string>* warnings = nullptr);

// Radial distance |ρ − r(θ,t)| = |s − 1|·r(θ,t) of the given vertices from the sweep surface,
// using SweepLocator; vertices beyond the end sections (z ≠ 0) are counted but not measured.
FitError measure_fit_error(const SweepShape& shape, const Mesh& mesh,
                           const std::vector<std::uint32_t>& vertices);

}  // namespace sweep::fit
