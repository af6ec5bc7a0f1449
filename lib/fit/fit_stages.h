#pragma once
// The stages of SweepFitter::fit (fit.h), private to lib/fit. Each stage is a function of what the
// stages before it found, returned as a plain struct; the fit as far as it got (FitResult) travels
// with them, since a refusal at any stage reports it (FitFailure).
//   0. resolve_seeds      the tip (and root) the user gave, as vertices of the mesh
//   1. find_tip           the part's end: climbed to from the tip given, or the tip itself mid-tube
//   2. find_root          rings of surface distance from the end, and the ring section 0 is cut at
//   3. trace_axis         the axis through the rings (or slices, or the polyline given)
//   4. key_section_span   the stretch of the axis the key sections cover
//   5. fit_sections       the key sections (a fixed K or the fewest that meet the tolerance), the
//                         part's vertices, the radii and the fit's error
//   6. cut_ends           an end that is not a tube (a foot, a head, a hand) cut off and carried
//   7. finish             the sweep, and the warnings and problems the user must know
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sweep/core/mesh.h"
#include "sweep/core/topology.h"
#include "sweep/fit/fit.h"
#include "sweep/fit/rings.h"
#include "sweep/fit/slicer.h"
#include "sweep/fit/surface_distance.h"
#include "sweep/fit/trace.h"
#include "sweep/fit/tube_end.h"

namespace sweep::fit::detail {

// What every stage reads: the mesh and the structures SweepFitter built over it once.
struct FitInputs {
  const Mesh& mesh;
  const Topology& own;     // the mesh's own topology: the part is walked over it
  const Topology& traced;  // patched where the mesh has holes: distances, rings and slices
  const MeshSlicer& slicer;
  const TriangleDistance& surface;  // the whole mesh: seeds off the surface, the axis' end inside it
  double diagonal = 0;              // of the mesh's bounding box
};

// 0. The seeds given.
struct Seeds {
  std::optional<Vec3> root;  // given, or the axis polyline's first point
  Vec3 tip_point = Vec3::Zero();
  std::uint32_t tip = 0;  // the vertex nearest the tip given (welded), or the tip vertex given
};

// 1. The part's end.
struct TipSearch {
  std::uint32_t root_vertex = 0;  // with a root: its vertex (welded)
  std::vector<double> field;      // surface distance from the body (the root, or the far point)
  std::vector<double> from_tip;   // with a root and no axis: the distance from the seed tip
  bool mid_tube = false;          // the tube goes on past the tip given
  double tip_moved = 0;           // how far the end lies from the tip asked for
};

// 2. The rings from the end, and the root ring among them.
struct RootChoice {
  std::vector<double> d;  // surface distance from the part's end
  RingTrace rings;
  int root_ring = 0;
  bool far_end = false;  // no body: the rings ran to the far end of the surface
  // Where the part leaks past its root (finish): farther from the tip than this, by radii.
  double root_distance = 0, root_radius = 0;
};

// 5. The sections' by-products the later stages read.
struct SectionFit {
  std::vector<std::pair<double, double>> along;  // (t, distance) of each measured part vertex
  std::vector<std::string> warnings_before;      // r.warnings before the sections added theirs
};

class FitRun {
 public:
  FitRun(const FitInputs& in, const FitOptions& options);

  Seeds resolve_seeds();
  TipSearch find_tip(const Seeds& seeds);
  RootChoice find_root(const Seeds& seeds, TipSearch& tip);
  void trace_axis(const Seeds& seeds, const TipSearch& tip, RootChoice& root);
  AxisTrace key_section_span(const RootChoice& root);
  SectionFit fit_sections(const AxisTrace& span);
  void cut_ends(const TipSearch& tip, const RootChoice& root, AxisTrace& span, SectionFit& sections);
  FitResult finish(const TipSearch& tip, const RootChoice& root);

 private:
  [[noreturn]] void refuse(ErrorCategory category, const std::string& message) const;
  std::uint32_t seed_vertex(const Vec3& p, const char* what, double& off_surface) const;
  // The sections, part, radii and error for K sections over `span` (fills r_ and `sections`).
  void build_sections(int k, const AxisTrace& span, SectionFit& sections);
  // Cuts the sweep where `tube_end` begins and fits it again; kept (true) only if the cut fit
  // meets the limits, else the fit is put back as it was.
  bool cut_end(const TubeEnd& tube_end, const char* kind, const RootChoice& root, AxisTrace& span,
               SectionFit& sections);
  bool too_far() const;

  const FitInputs& in_;
  const FitOptions& o_;
  FitResult r_;
};

}  // namespace sweep::fit::detail
