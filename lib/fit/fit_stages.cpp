#include "sweep/fit/fit_stages.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "sweep/core/error.h"
#include "sweep/core/locate.h"
#include "sweep/core/text.h"
#include "sweep/fit/loop.h"
#include "sweep/fit/mid_tube.h"

namespace sweep::fit::detail {
namespace {

// A given root whose ring is this share wider than the junction's is warned about.
constexpr double kWidenedRootShare = 0.25;
// Section counts tried by the tolerance search, about √2 apart.
constexpr int kSectionLadder[] = {2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64, 91, 128, 181, 256};
// The last key section sits where the axis is at least this many local radii from the tip vertex
// (a blunt end's cap beyond it is carried rigidly; a sharp tip's last section is at the point).
constexpr double kCapRadii = 0.15;
// Part vertices farther from the tip than the root ring by more than this many root radii have
// leaked past the root section.
constexpr double kLeakRadii = 2;
// A tip is mid-tube when the level set of the distance from it this share of the way to the root
// still runs both ways (rings_run_both_ways): short of the root, whose own ring may touch others.
constexpr double kBothWaysLevel = 0.9;
// A fitted part shorter than this many mean radii is warned about (a stub: the root found next to
// the tip, as on a muzzle before the head widens).
constexpr double kStubRadii = 1;
// A tube's axis bends no tighter than its radius (curvature × radius ≤ 1: tighter, the section
// planes cross inside the tube). Where slice centroids zigzag more than that (a tusk fused along
// the trunk pulls them aside: elephant's and refined_elephant's axes turned 22–57° per section
// spacing of 0.45 radii there), the axis is smoothed down to it (limit_axis_curvature).
constexpr double kMaxCurvatureRadii = 1;
// The radii fitted to a part decide which vertices the part keeps (near the sweep, a bridge's
// foot off its surface): while the part they select is not the one they were fitted to, they are
// fitted again to the new part, from the slices' radii, up to this many times. (A tusk's foot,
// still in the part the first radii were fitted to, pulls them out along it and keeps itself in.)
// Fitting is deterministic: a part that stays as it was is not fitted twice.
constexpr int kMaxRefits = 2;

// The first ring past the tip's cap: where the rings stop growing fast (growth below the ring
// options' settled_growth), searching up to `last`. Before it, rings spread over the end itself
// (from a pole or, on a blunt bent end, from a vertex of its rim) and their centroids are not on
// the axis.
int first_tube_ring(const RingTrace& rings, int last, const RingOptions& o) {
  for (int i = 0; i < last; ++i) {
    if (rings.rings[static_cast<std::size_t>(i)].growth < o.settled_growth) return i;
  }
  return 0;
}

// How far a cap reaches past an end of the axis along the axis' direction there: the farthest
// projection of the surface nearer to the tip than `level` (the tip's cap: `tip_side`) or farther
// (a far end without a body).
double cap_reach(const Mesh& mesh, const std::vector<double>& d, double level, bool tip_side, const Vec3& end,
                 const Vec3& outwards) {
  double reach = 0;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (tip_side ? d[v] <= level : d[v] >= level) reach = std::max(reach, (mesh.positions[v] - end).dot(outwards));
  }
  return reach;
}

// The axis the other way round: the extensions of its tip end then serve its start.
void reverse_axis(AxisTrace& axis) {
  std::reverse(axis.points.begin(), axis.points.end());
  std::reverse(axis.tangents.begin(), axis.tangents.end());
  for (Vec3& t : axis.tangents) t = -t;
  std::reverse(axis.radii.begin(), axis.radii.end());
}

}  // namespace

FitRun::FitRun(const FitInputs& in, const FitOptions& options) : in_(in), o_(options) {
  r_.sweep.name = o_.name;
  // Seeds must be on or near the mesh: their distance from its surface (a point on a large
  // face may be far from every vertex).
  r_.seed_limit = o_.seed_distance * in_.diagonal;
}

// Refusals carry the fit as far as it got, for the report.
void FitRun::refuse(ErrorCategory category, const std::string& message) const {
  throw FitFailure(category, message, r_);
}

std::uint32_t FitRun::seed_vertex(const Vec3& p, const char* what, double& off_surface) const {
  const Mesh& mesh = in_.mesh;
  off_surface = in_.surface.distance(p);
  if (!std::isfinite(off_surface)) {
    // Past ~1e154 the squared distance overflows. The distance to the mesh's bounding box is
    // then the surface's to every digit printed (the box is nothing beside it).
    Vec3 lo = mesh.positions[0], hi = lo;
    for (const Vec3& q : mesh.positions) {
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    off_surface = (p - p.cwiseMax(lo).cwiseMin(hi)).stableNorm();
  }
  if (off_surface > r_.seed_limit) {
    refuse(ErrorCategory::bad_input, std::string(what) + " " + format_point(p) +
                                         " is far from the mesh: " + format_number(off_surface) +
                                         " from its surface, more than " + format_number(o_.seed_distance) +
                                         " of its bounding box diagonal (" + format_number(r_.seed_limit) + ")");
  }
  return nearest_vertex(mesh, p);
}

Seeds FitRun::resolve_seeds() {
  const Mesh& mesh = in_.mesh;
  Seeds seeds;
  seeds.root = o_.root;
  seeds.tip_point = o_.tip;
  if (!o_.axis.empty()) {
    if (!seeds.root) seeds.root = o_.axis.front();
    seeds.tip_point = o_.axis.back();
  }
  if (seeds.root) r_.root = *seeds.root;  // (until section 0 is cut: a refusal reports the root given)
  std::uint32_t tip = 0;
  if (o_.tip_vertex >= 0) {
    if (static_cast<std::uint64_t>(o_.tip_vertex) >= mesh.vertex_count()) {
      refuse(ErrorCategory::usage, "tip_vertex " + std::to_string(o_.tip_vertex) +
                                       " is not a vertex of the mesh (it has " + std::to_string(mesh.vertex_count()) +
                                       ")");
    }
    tip = static_cast<std::uint32_t>(o_.tip_vertex);
  } else {
    tip = seed_vertex(seeds.tip_point, "tip", r_.tip_off_surface);
  }
  seeds.tip = in_.traced.weld[tip];
  r_.tip_vertex = seeds.tip;
  return seeds;
}

// The tip: climb to the part's end, the local maximum of the distance from the body (the root,
// or, without one, the point of the surface farthest from the tip, which lies on another
// extremity).
TipSearch FitRun::find_tip(const Seeds& seeds) {
  const Mesh& mesh = in_.mesh;
  const Topology& topo = in_.traced;
  const std::uint32_t tip0 = seeds.tip;
  TipSearch t;
  if (seeds.root) {
    t.root_vertex = topo.weld[seed_vertex(*seeds.root, "root", r_.root_off_surface)];
    t.field = surface_distances(mesh, topo, std::span(&t.root_vertex, 1));
  } else {
    const std::vector<double> from_tip = surface_distances(mesh, topo, std::span(&tip0, 1));
    std::uint32_t far = tip0;
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
      if (std::isfinite(from_tip[v]) && from_tip[v] > from_tip[far]) far = v;
    }
    t.field = surface_distances(mesh, topo, std::span(&far, 1));
  }
  if (!std::isfinite(t.field[tip0])) {
    refuse(ErrorCategory::bad_input, "the tip (vertex " + std::to_string(tip0) +
                                         ") is not reachable from the root: they lie on separate "
                                         "pieces of the mesh");
  }
  // A tip given mid-tube (the tube goes on past it: a hose, a knot) has no end to climb to: the
  // part is the stretch from the root to the tip, cut at its last section too.
  if (seeds.root && o_.axis.empty()) {
    t.from_tip = surface_distances(mesh, topo, std::span(&tip0, 1));
    t.mid_tube = rings_run_both_ways(mesh, topo, t.from_tip, kBothWaysLevel * t.from_tip[t.root_vertex]);
  }
  // A tip given as a vertex is the end itself (what --list and --all name: the extremity whose
  // rings found the part); climbing from it may reach another end (the camel's muzzle climbed
  // to an ear and fitted a stub 0.009 long).
  r_.tip_vertex = o_.axis.empty() && !t.mid_tube && o_.tip_vertex < 0 ? climb(topo, t.field, tip0) : tip0;
  if (t.mid_tube) {
    r_.tip_cut = true;
    r_.tip_cut_reason =
        "the rings of surface distance from the tip run both ways along the tube (it "
        "goes on past the tip at least as far as the root lies before it): the part "
        "is cut at its last section too";
  }
  // How far the part's end lies from the tip asked for: worth a warning past a radius (finish).
  t.tip_moved = (mesh.positions[r_.tip_vertex] - (o_.tip_vertex >= 0 ? mesh.positions[tip0] : seeds.tip_point)).norm();
  return t;
}

// Rings from the tip, and the root among them.
RootChoice FitRun::find_root(const Seeds& seeds, TipSearch& tip) {
  const Mesh& mesh = in_.mesh;
  const Topology& topo = in_.traced;
  RootChoice c;
  c.d = r_.tip_vertex == seeds.tip && !tip.from_tip.empty()
            ? std::move(tip.from_tip)
            : surface_distances(mesh, topo, std::span(&r_.tip_vertex, 1));
  c.rings = trace_rings(mesh, topo, c.d, r_.tip_vertex, std::numeric_limits<double>::infinity(), true, o_.rings);
  if (c.rings.rings.size() < 2) {
    refuse(ErrorCategory::bad_input, "no rings of surface distance around the tip (vertex " +
                                         std::to_string(r_.tip_vertex) +
                                         "): the surface there is too small or not connected");
  }
  const auto ring = [&](int i) -> const Ring& { return c.rings.rings[static_cast<std::size_t>(i)]; };
  c.root_ring = c.rings.junction;
  if (seeds.root) {
    const Vec3& root = *seeds.root;
    int last = c.rings.junction;
    const int n = static_cast<int>(c.rings.rings.size());
    while (last + 1 < n && ring(last + 1).distance <= c.d[tip.root_vertex]) ++last;
    c.root_ring = 0;
    for (int i = 1; i <= last; ++i) {
      if ((ring(i).centroid - root).norm() < (ring(c.root_ring).centroid - root).norm()) c.root_ring = i;
    }
    r_.root_reason = "section 0 is cut through the ring nearest to the given root, at distance " +
                     format_number(ring(c.root_ring).distance) + " from the tip";
    // A root a little past the junction only adds a short flare; warn when it has widened.
    if (c.root_ring > c.rings.junction &&
        ring(c.root_ring).radius > (1 + kWidenedRootShare) * ring(c.rings.junction).radius) {
      r_.warnings.push_back("the root lies past where the part meets the body (" + c.rings.junction_reason +
                            "); section 0 is cut where the part has widened");
    }
  } else {
    r_.root_found = true;
    r_.root_reason = c.rings.junction_reason;
  }
  // No body: the rings ran to the far end of the surface, a cap like the tip's (they shrink
  // over it). The axis runs through the rings before it, then straight on to its end.
  c.far_end = !seeds.root && c.rings.junction + 1 == static_cast<int>(c.rings.rings.size());
  if (c.far_end) {
    while (c.root_ring > 1 && ring(c.root_ring).growth < -o_.rings.settled_growth) --c.root_ring;
  }
  r_.surface_length = ring(c.root_ring).distance;
  c.root_distance = ring(c.root_ring).distance;
  c.root_radius = ring(c.root_ring).radius;
  return c;
}

// The axis: ring centroids from the root to the tip, refined by plane slices; mid-tube, slice
// centroids along the surface path from the root to the tip (the rings run both ways).
void FitRun::trace_axis(const Seeds& seeds, const TipSearch& tip, RootChoice& root) {
  const Mesh& mesh = in_.mesh;
  const MeshSlicer& slicer = in_.slicer;
  const auto ring = [&](int i) -> const Ring& { return root.rings.rings[static_cast<std::size_t>(i)]; };
  if (tip.mid_tube) {
    std::vector<Vec3> points;
    std::vector<double> radii;
    path_axis_points(mesh, in_.traced, slicer, tip.field, r_.tip_vertex, points, radii);
    if (points.size() >= 2) r_.axis = refine_axis(slicer, points, radii);
    if (!r_.axis.points.empty()) {
      trim_axis_start(r_.axis, *seeds.root, 2 * radii.front());
      r_.axis.end_reason = "the tip was given mid-tube: the axis ends there";
      root.root_radius = radii.front();
    }
    r_.surface_length = root.root_distance = root.d[tip.root_vertex];
    r_.root_reason =
        "section 0 is cut where the given root projects onto the axis (the tip was "
        "given mid-tube)";
  } else if (o_.axis.empty()) {
    std::vector<Vec3> points;
    std::vector<double> radii;
    const int first = root.root_ring;
    // The axis runs through the rings of the tube; past the tip's cap it goes straight on to
    // the cap's farthest point.
    const int cap = first_tube_ring(root.rings, first, o_.rings);
    for (int i = first; i >= cap; --i) {
      points.push_back(ring(i).centroid);
      radii.push_back(ring(i).radius);
    }
    if (points.size() < 2) {  // the tip's cap reaches the root: the rings alone
      points = {ring(first).centroid, ring(0).centroid};
      radii = {ring(first).radius, ring(0).radius};
    }
    r_.axis = refine_axis(slicer, points, radii);
    if (!r_.axis.points.empty()) {
      extend_axis(slicer, in_.surface, r_.axis,
                  cap_reach(mesh, root.d, ring(cap).distance, true, r_.axis.points.back(), r_.axis.tangents.back()));
    }
    if (root.far_end && !r_.axis.points.empty()) {
      const std::string tip_end = r_.axis.end_reason;  // (the root side's is not the one asked)
      reverse_axis(r_.axis);
      extend_axis(slicer, in_.surface, r_.axis,
                  cap_reach(mesh, root.d, ring(root.root_ring).distance, false, r_.axis.points.back(),
                            r_.axis.tangents.back()));
      reverse_axis(r_.axis);
      r_.axis.end_reason = tip_end;
    } else {
      // Section 0 where the root (or, found, the root ring's centre) projects onto the axis,
      // which may lie a little before the first point kept.
      trim_axis_start(r_.axis, seeds.root ? *seeds.root : ring(root.root_ring).centroid,
                      2 * ring(root.root_ring).radius);
    }
  } else {
    r_.axis = axis_from_polyline(slicer, o_.axis);
  }
  if (r_.axis.points.size() < 2) {
    refuse(ErrorCategory::bad_input,
           "the part from vertex " + std::to_string(r_.tip_vertex) + " has no length to fit (" + r_.root_reason + ")");
  }
  if (o_.axis.empty()) limit_axis_curvature(r_.axis, kMaxCurvatureRadii);
  r_.traced_length = arc_lengths(r_.axis.points).back();
  if (!o_.axis.empty()) r_.surface_length = r_.traced_length;
}

// The last key section: the point nearest the tip whose slice is a real loop at least kCapRadii
// of its radius from the tip; likewise the first at a far end without a body.
AxisTrace FitRun::key_section_span(const RootChoice& root) {
  const std::vector<double> s = arc_lengths(r_.axis.points);
  std::size_t end = r_.axis.points.size() - 1;
  while (end > 1 && !(r_.axis.radii[end] > 0 && s.back() - s[end] >= kCapRadii * r_.axis.radii[end])) {
    --end;
  }
  std::size_t begin = 0;
  while (root.far_end && begin + 1 < end &&
         !(r_.axis.radii[begin] > 0 && s[begin] >= kCapRadii * r_.axis.radii[begin])) {
    ++begin;
  }
  AxisTrace span;
  const auto first = static_cast<std::ptrdiff_t>(begin), last = static_cast<std::ptrdiff_t>(end + 1);
  span.points.assign(r_.axis.points.begin() + first, r_.axis.points.begin() + last);
  span.tangents.assign(r_.axis.tangents.begin() + first, r_.axis.tangents.begin() + last);
  span.radii.assign(r_.axis.radii.begin() + first, r_.axis.radii.begin() + last);
  // A missing slice (0) takes its neighbours' size (sections_along); with none at all, the tip
  // ring's size serves the fallback circles.
  if (std::none_of(span.radii.begin(), span.radii.end(), [](double x) { return x > 0; }))
    std::fill(span.radii.begin(), span.radii.end(), root.rings.rings[0].radius);
  if (!(arc_lengths(span.points).back() > 0)) {
    refuse(ErrorCategory::bad_input,
           "the part from vertex " + std::to_string(r_.tip_vertex) + " is too short to cut two key sections");
  }
  return span;
}

void FitRun::build_sections(int k, const AxisTrace& span, SectionFit& sections) {
  const Mesh& mesh = in_.mesh;
  FitResult& r = r_;
  r.star_violations.clear();
  r.sweep.rest = sections_along(in_.slicer, span, k, o_.radial, &r.star_violations, &r.warnings);
  r.length = r.sweep.rest.length();
  const PartSeeds seeds{Vec3::Zero(), mesh.positions[r.tip_vertex], r.tip_cut};
  r.part_vertices = select_sweep_part(mesh, in_.own, r.sweep.rest, seeds);
  const std::vector<double> slice_radii = r.sweep.rest.radii;
  // The radii that best match the part's vertices (the slices run through facets' chords).
  std::vector<std::uint32_t> fitted_to = r.part_vertices;
  fit_radii(r.sweep.rest, mesh, fitted_to);
  // The part again, as sweep-bind will select it: its bound near the sweep reads the radii.
  r.part_vertices = select_sweep_part(mesh, in_.own, r.sweep.rest, seeds);
  for (int refit = 0; refit < kMaxRefits && r.part_vertices != fitted_to; ++refit) {
    fitted_to = r.part_vertices;
    r.sweep.rest.radii = slice_radii;
    fit_radii(r.sweep.rest, mesh, fitted_to);
    r.part_vertices = select_sweep_part(mesh, in_.own, r.sweep.rest, seeds);
  }
  // The limits below are relative to the radii the rig keeps, not to the slices'.
  const std::vector<double>& radii = r.sweep.rest.radii;
  r.mean_radius = 0;
  for (const double x : radii) r.mean_radius += x;
  r.mean_radius /= static_cast<double>(radii.size());
  sections.along.clear();
  if (o_.measure_error || o_.tolerance > 0) {
    r.error = measure_fit_error(r.sweep.rest, mesh, r.part_vertices,
                                std::span(in_.traced.triangles).subspan(in_.own.triangles.size()), in_.own.weld,
                                &sections.along);
  }
}

// Sections (a fixed K, or the fewest that meet the tolerance), part, error.
SectionFit FitRun::fit_sections(const AxisTrace& span) {
  SectionFit sections;
  sections.warnings_before = r_.warnings;
  if (o_.tolerance > 0) {
    bool met = false;
    for (int k : kSectionLadder) {
      k = std::min(k, o_.max_sections);
      build_sections(k, span, sections);
      if (r_.error.rms <= o_.tolerance * r_.mean_radius) {
        met = true;
        break;
      }
      if (k == o_.max_sections) break;
    }
    if (!met) {
      r_.warnings.push_back("tolerance " + format_number(o_.tolerance) + " not met with " +
                            std::to_string(r_.sweep.rest.section_count()) + " sections: the fit RMS is " +
                            format_percent(r_.error.rms / r_.mean_radius) + " of the mean radius");
    }
  } else {
    build_sections(o_.sections, span, sections);
  }
  return sections;
}

bool FitRun::cut_end(const TubeEnd& tube_end, const char* kind, const RootChoice& root, AxisTrace& span,
                     SectionFit& sections) {
  const Mesh& mesh = in_.mesh;
  FitResult& r = r_;
  const SweepShape& shape = r.sweep.rest;
  const int k = shape.section_count();
  const int end_first = tube_end.first_section;
  const double end_rms = tube_end.end_rms, before_rms = tube_end.before_rms, share = tube_end.share;
  const std::size_t end_count = tube_end.end_count;
  const Vec3 end_point = shape.frames[static_cast<std::size_t>(end_first)].center;
  const double old_mean_radius = r.mean_radius;
  const FitResult uncut = r;
  const AxisTrace uncut_span = span;
  // The axis cut where the run begins: the tube's end. (Continued by slices into the end,
  // extend_axis, they are pulled towards the foot's toe, and its sections with them: camel's
  // hind leg 4.1 % RMS against 0.96 % cut here.)
  AxisTrace ended = r.axis;
  std::size_t at = 0;
  for (std::size_t i = 1; i < ended.points.size(); ++i) {
    if ((ended.points[i] - end_point).norm() < (ended.points[at] - end_point).norm()) at = i;
  }
  at = std::max<std::size_t>(at, 1);
  ended.points.resize(at + 1);
  ended.tangents.resize(at + 1);
  ended.radii.resize(at + 1);
  const std::vector<double> se = arc_lengths(ended.points);
  span = ended;
  r.warnings = sections.warnings_before;  // (the sections' own are given again)
  build_sections(k, span, sections);
  const double ended_length = se.back();
  const double ended_gap = (mesh.positions[r.tip_vertex] - ended.points.back()).norm();
  // The surface distance from the tip to the tube's end: of the part's vertices within half a
  // spacing of the last section, the mean. The axis is measured against the rest.
  double end_distance = 0;
  {
    const SweepLocator locator(r.sweep.rest);
    const double from = r.sweep.rest.length() * (1 - 0.5 / (k - 1));
    std::size_t n_end = 0;
    for (const std::uint32_t v : r.part_vertices) {
      const SweepCoords c = locator.locate(mesh.positions[v]);
      if (c.z != 0 || c.t < from || !std::isfinite(root.d[v])) continue;
      end_distance += root.d[v];
      ++n_end;
    }
    if (n_end > 0) end_distance /= static_cast<double>(n_end);
  }
  const double tube_surface = r.surface_length - end_distance;
  const std::size_t old_count = uncut.part_vertices.size();
  std::size_t gained = 0;
  for (const std::uint32_t v : r.part_vertices)
    gained += !std::binary_search(uncut.part_vertices.begin(), uncut.part_vertices.end(), v);
  const bool fits = r.error.measured_count > 0 && r.error.p90 <= o_.max_error * r.mean_radius &&
                    r.error.rms < uncut.error.rms / old_mean_radius * r.mean_radius &&
                    r.error.surface_p90 <= o_.max_surface_error * r.mean_radius &&
                    r.beyond_root_share() <= o_.max_beyond_root_share &&
                    static_cast<double>(gained) <= o_.max_leak_share * static_cast<double>(old_count) &&
                    !(ended_length < o_.min_length_ratio * tube_surface && ended_gap > o_.max_tip_gap * r.mean_radius);
  if (fits) {
    r.axis = std::move(ended);
    r.traced_length = ended_length;
    r.surface_length = tube_surface;
    const std::size_t carried = r.error.beyond_ends_count - r.error.beyond_root_count;
    r.end_cut = true;
    r.end_cut_reason = "the part's end is not a tube (" + std::string(kind) +
                       "): the sweep fitted through it "
                       "was " +
                       format_percent(end_rms / old_mean_radius) + " of the mean radius off its " +
                       std::to_string(end_count) + " vertices (RMS) over the last " + format_percent(share) +
                       " of its length, against " + format_percent(before_rms / old_mean_radius) +
                       " before; the axis and the sweep end at " + format_point(end_point, 4) + ", and the " +
                       std::to_string(carried) +
                       " vertices past the sweep's last section are carried rigidly by it (the axis is "
                       "measured against the surface distance from the root ring to there, " +
                       format_number(tube_surface) + "; on to the tip it is " + format_number(end_distance) + " more)";
    r.axis.end_reason = "the part's end is not a tube past " + format_point(end_point, 4) + " (the sweep was " +
                        format_percent(end_rms / old_mean_radius) + " of the mean radius off it, RMS)";
    return true;
  }
  r = uncut;
  span = uncut_span;
  return false;
}

bool FitRun::too_far() const {
  return r_.error.measured_count > 0 &&
         (r_.error.p90 > o_.max_error * r_.mean_radius || r_.error.surface_p90 > o_.max_surface_error * r_.mean_radius);
}

void FitRun::cut_ends(const TipSearch& tip, const RootChoice& root, AxisTrace& span, SectionFit& sections) {
  // An end that is not a tube: the sweep ends where the tube does (fit/tube_end.h). At a fixed
  // section count only: a foot spoils every rung of the tolerance search, which would climb to
  // max_sections before the end is cut (camel's hind leg: K = 256, 1.6 % RMS, the axis still in
  // the foot); and only when the error is measured, which tells where the end is.
  const bool fixed_count = o_.tolerance == 0;
  const bool may_cut = o_.axis.empty() && !tip.mid_tube && !root.far_end && fixed_count && o_.measure_error;
  if (may_cut && r_.error.measured_count > 0) {
    if (const std::optional<TubeEnd> tube_end =
            find_tube_end(r_.sweep.rest, sections.along, o_.max_error * r_.mean_radius, r_.mean_radius)) {
      cut_end(*tube_end, "a foot, a hoof, a tuft", root, span, sections);
    }
  }
  // An end the sweep cannot follow and the cut above does not take (a head turned across the
  // neck, a hand, clicked at its top or a fingertip: a long end, or sections far apart): when the
  // fit breaks the error limits, the sweep is cut where the spans first go off the tube from the
  // root on, or up to kMaxWideEndSteps sections before, the first cut that meets every limit kept.
  if (may_cut && !r_.end_cut && too_far()) {
    for (const TubeEnd& wide : wide_end_cuts(r_.sweep.rest, sections.along, o_.max_error * r_.mean_radius)) {
      if (cut_end(wide, "a head, a hand: an end the sweep cannot follow", root, span, sections)) break;
    }
  }
}

// The sweep, and what the user must know, and what makes the fit wrong.
FitResult FitRun::finish(const TipSearch& tip, const RootChoice& root) {
  const Mesh& mesh = in_.mesh;
  FitResult& r = r_;
  if (const std::string why = check_shape(r.sweep.rest); !why.empty()) {
    fail(ErrorCategory::internal, "the fitted sweep is invalid: " + why);
  }
  r.root = r.sweep.rest.frames[0].center;
  SweepShape shape = std::move(r.sweep.rest);
  r.sweep = make_sweep(o_.name, std::move(shape));
  r.sweep.part = PartSeeds{r.root, mesh.positions[r.tip_vertex], r.tip_cut};

  if (in_.slicer.repaired_face_count() > 0) {
    r.warnings.push_back(std::to_string(in_.slicer.repaired_face_count()) +
                         " triangles were not manifold; the slicer duplicated vertices to take them");
  }
  if (!r.star_violations.empty()) {
    int rays = 0;
    for (const StarViolation& v : r.star_violations) rays += v.multi_crossing_rays + v.missed_rays;
    r.warnings.push_back(std::to_string(r.star_violations.size()) +
                         " sections are not star-shaped about their centre (" + std::to_string(rays) +
                         " rays; the outermost crossing was used)");
  }
  const double leak_level = root.root_distance + kLeakRadii * root.root_radius;
  for (const std::uint32_t v : r.part_vertices) r.leaked_count += root.d[v] > leak_level;
  const double part_count = static_cast<double>(std::max<std::size_t>(r.part_vertices.size(), 1));
  // Short against the surface and far from the tip: stopped early. (A foot or a head at the end
  // lengthens the surface path without leaving the axis short of the tip.)
  r.tip_gap = (mesh.positions[r.tip_vertex] - r.axis.points.back()).norm();
  if (r.traced_length < o_.min_length_ratio * r.surface_length && r.tip_gap > o_.max_tip_gap * r.mean_radius) {
    r.problems.push_back(
        "the axis (" + format_number(r.traced_length) + " long) covers only " +
        format_percent(r.traced_length / r.surface_length) + " of the surface distance from the tip to the root (" +
        format_number(r.surface_length) + ") and ends " + format_number(r.tip_gap / r.mean_radius) +
        " mean radii from the tip: the trace stopped short of the tip (" +
        (r.axis.end_reason.empty() ? std::string("the axis given ends there") : r.axis.end_reason) + ")");
  }
  if (static_cast<double>(r.leaked_count) > o_.max_leak_share * part_count) {
    r.problems.push_back("the part leaks past its root into the body: " + std::to_string(r.leaked_count) + " of its " +
                         std::to_string(r.part_vertices.size()) +
                         " vertices lie farther from the tip than the root section; give --root where the part "
                         "is still a tube");
  }
  if (o_.measure_error || o_.tolerance > 0) {
    if (r.error.measured_count == 0) {
      r.problems.push_back("none of the part's " + std::to_string(r.part_vertices.size()) +
                           " vertices lies between the end sections: there is no fit to measure");
    } else if (r.beyond_root_share() > o_.max_beyond_root_share) {
      r.problems.push_back(std::to_string(r.error.beyond_root_count) + " of the part's " +
                           std::to_string(r.part_vertices.size()) +
                           " vertices lie before the root section: the root section does not "
                           "close the part off; move --root along the part");
    }
    if (r.error.measured_count > 0 && r.error.p90 > o_.max_error * r.mean_radius) {
      r.problems.push_back("a tenth of the part's vertices are farther than " +
                           format_percent(r.error.p90 / r.mean_radius) +
                           " of the mean radius from the fit, above the limit of " + format_percent(o_.max_error) +
                           ": the part is not a tube where it is cut, or the axis strayed; try "
                           "--root nearer the tip, or more sections");
    }
    if (r.error.surface_samples > 0 && r.error.surface_p90 > o_.max_surface_error * r.mean_radius) {
      r.problems.push_back(
          "a tenth of the fitted surface is farther than " + format_percent(r.error.surface_p90 / r.mean_radius) +
          " of the mean radius from the part's faces, above the limit of " + format_percent(o_.max_surface_error) +
          ": the sweep leaves the mesh between the part's vertices (the part "
          "is not one tube, or the axis strayed); try --tip and --root on the "
          "part, or more sections");
    }
  }
  if (r.length < kStubRadii * r.mean_radius) {
    r.warnings.push_back("the part is only " + format_number(r.length / r.mean_radius) +
                         " mean radii long: a stub more than a tube (" + r.root_reason +
                         "); give --root farther from the tip if the part goes on");
  }
  if (tip.tip_moved > r.mean_radius) {
    r.warnings.push_back("tip moved to the part's end, vertex " + std::to_string(r.tip_vertex) + " at " +
                         format_point(mesh.positions[r.tip_vertex]) + ", " +
                         format_number(tip.tip_moved / r.mean_radius) + " mean radii from the tip given");
  }
  return std::move(r_);
}

}  // namespace sweep::fit::detail
