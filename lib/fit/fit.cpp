#include "sweep/fit/fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <sstream>

#include "sweep/core/error.h"
#include "sweep/core/frame.h"
#include "sweep/core/limits.h"
#include "sweep/core/locate.h"
#include "sweep/core/text.h"
#include "sweep/fit/hole_patches.h"
#include "sweep/fit/loop.h"
#include "sweep/fit/mid_tube.h"
#include "sweep/fit/slicer.h"
#include "sweep/fit/surface_distance.h"
#include "sweep/fit/tube_end.h"

namespace sweep::fit {
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
// The error's tessellation of the sweep surface: stations per span and angles per radius sample.
constexpr int kErrorStationsPerSpan = 4;
constexpr int kErrorAnglesPerSample = 2;
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

}  // namespace

FitError measure_fit_error(const SweepShape& shape, const Mesh& mesh,
                           const std::vector<std::uint32_t>& vertices,
                           std::span<const std::uint32_t> patches,
                           std::span<const std::uint32_t> weld,
                           std::vector<std::pair<double, double>>* along) {
  FitError e;
  // The sweep's tube, tessellated: stations along t, 2n angles around.
  const int k = shape.section_count();
  const int stations = (k - 1) * kErrorStationsPerSpan + 1;
  const int angles = kErrorAnglesPerSample * shape.radial_count;
  std::vector<Vec3> points;
  points.reserve(static_cast<std::size_t>(stations) * angles);
  for (int i = 0; i < stations; ++i) {
    const double t = shape.length() * i / (stations - 1);
    for (int j = 0; j < angles; ++j) {
      points.push_back(surface_point(shape, 2 * std::numbers::pi * j / angles, t));
    }
  }
  std::vector<std::uint32_t> grid;
  for (int i = 0; i + 1 < stations; ++i) {
    for (int j = 0; j < angles; ++j) {
      const auto id = [&](int a, int b) {
        return static_cast<std::uint32_t>(a * angles + b % angles);
      };
      grid.insert(grid.end(), {id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1),
                               id(i + 1, j)});
    }
  }
  const TriangleDistance to_sweep(points, grid);

  const SweepLocator locator(shape);
  std::vector<char> in_part(mesh.vertex_count(), 0);
  double sum2 = 0, radial2 = 0;
  std::vector<double> distances;
  distances.reserve(vertices.size());
  for (const std::uint32_t v : vertices) {
    in_part[v] = 1;
    const SweepCoords c = locator.locate(mesh.positions[v]);
    if (c.z != 0) {
      ++e.beyond_ends_count;
      e.beyond_root_count += c.z < 0;  // before section 0 (its axis points to the tip)
      continue;
    }
    if (c.s > kPartReachRadii) {
      ++e.protrusion_count;
      continue;
    }
    const double radial = std::abs(c.s - 1) * radius_at(shape, c.theta, c.t);
    const double d = std::min(radial, to_sweep.distance(mesh.positions[v]));
    sum2 += d * d;
    distances.push_back(d);
    radial2 += radial * radial;
    if (along) along->emplace_back(c.t, d);
    e.max = std::max(e.max, d);
    ++e.measured_count;
  }
  if (e.measured_count > 0) {
    e.rms = std::sqrt(sum2 / static_cast<double>(e.measured_count));
    e.radial_rms = std::sqrt(radial2 / static_cast<double>(e.measured_count));
    e.p90 = percentile_90(distances);
  }
  // The other way: the sweep's samples to the part's faces, those with a vertex in the part (the
  // faces across the root section are the part's surface there: without them a sample at the
  // root of a coarse part is a whole ring of faces from the nearest one).
  std::vector<std::uint32_t> part_faces;
  const std::vector<std::uint32_t> all = mesh.triangles();
  for (std::size_t f = 0; f + 2 < all.size(); f += 3) {
    if (in_part[all[f]] || in_part[all[f + 1]] || in_part[all[f + 2]]) {
      part_faces.insert(part_faces.end(), {all[f], all[f + 1], all[f + 2]});
    }
  }
  if (!patches.empty() && weld.size() == mesh.vertex_count()) {
    // (Over representatives: a part vertex welded to another stands for it.)
    std::vector<char> rep_in_part(mesh.vertex_count(), 0);
    for (const std::uint32_t v : vertices) rep_in_part[weld[v]] = 1;
    for (std::size_t f = 0; f + 2 < patches.size(); f += 3) {
      if (rep_in_part[patches[f]] || rep_in_part[patches[f + 1]] || rep_in_part[patches[f + 2]])
        part_faces.insert(part_faces.end(), {patches[f], patches[f + 1], patches[f + 2]});
    }
  }
  const TriangleDistance to_part(mesh.positions, part_faces);
  if (!to_part.empty()) {
    double s2 = 0;
    std::vector<double> surface_distances;
    surface_distances.reserve(points.size());
    for (const Vec3& p : points) {
      const double d = to_part.distance(p);
      s2 += d * d;
      e.surface_max = std::max(e.surface_max, d);
      surface_distances.push_back(d);
    }
    e.surface_samples = points.size();
    e.surface_rms = std::sqrt(s2 / static_cast<double>(points.size()));
    e.surface_p90 = percentile_90(surface_distances);
  }
  return e;
}

namespace {

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
double cap_reach(const Mesh& mesh, const std::vector<double>& d, double level, bool tip_side,
                 const Vec3& end, const Vec3& outwards) {
  double reach = 0;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (tip_side ? d[v] <= level : d[v] >= level)
      reach = std::max(reach, (mesh.positions[v] - end).dot(outwards));
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

struct SweepFitter::Impl {
  explicit Impl(const Mesh& mesh)
      : topology(build_topology(mesh)),
        patched(fit::patched_topology(mesh, topology)),
        slicer(mesh.positions, traced().triangles),
        surface(mesh.positions, traced().triangles) {}
  // What the distances, rings and slices run over: patched where the mesh has holes.
  const Topology& traced() const { return patched ? *patched : topology; }
  Topology topology;  // the mesh's own: the part is walked over it (select_sweep_part)
  std::optional<Topology> patched;  // before the slicer and the surface, which are over its triangles
  MeshSlicer slicer;
  TriangleDistance surface;  // the whole mesh: seeds off the surface, the axis' end inside it
  double diagonal = 0;
};

SweepFitter::SweepFitter(const Mesh& mesh) : mesh_(mesh) {
  const std::string why = check_mesh(mesh);
  if (!why.empty()) fail(ErrorCategory::bad_input, why);
  impl_ = std::make_unique<Impl>(mesh);
  Vec3 lo = mesh.positions[0], hi = mesh.positions[0];
  for (const Vec3& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  impl_->diagonal = (hi - lo).norm();
}

SweepFitter::~SweepFitter() = default;
SweepFitter::SweepFitter(SweepFitter&&) noexcept = default;

const MeshSlicer& SweepFitter::slicer() const {
  return impl_->slicer;
}
const Topology& SweepFitter::topology() const {
  return impl_->topology;
}
const Topology& SweepFitter::patched_topology() const {
  return impl_->traced();
}
double SweepFitter::diagonal() const {
  return impl_->diagonal;
}

namespace {

void validate(const FitOptions& o) {
  const auto bad = [](const std::string& what) { fail(ErrorCategory::usage, what); };
  if (o.tolerance == 0 && o.sections < 2) {
    bad("sections must be at least 2, got " + std::to_string(o.sections));
  }
  if (o.radial < 3) bad("radial must be at least 3, got " + std::to_string(o.radial));
  // The rig reader's limits (core/limits.h): never write a rig that sweep-bind refuses.
  if (o.sections > limits::kMaxSections || o.max_sections > limits::kMaxSections ||
      o.radial > limits::kMaxRadial) {
    bad("sections must be at most " + std::to_string(limits::kMaxSections) +
        " and radial at most " + std::to_string(limits::kMaxRadial));
  }
  if (!(o.tolerance >= 0) || !std::isfinite(o.tolerance))
    bad("tolerance must be a finite number >= 0");
  if (o.tolerance > 0 && o.max_sections < 2) bad("max_sections must be at least 2");
  if (!is_finite(o.tip) || (o.root && !is_finite(*o.root))) bad("root and tip must be finite");
  if (o.name.empty()) bad("name must not be empty");
  for (const Vec3& p : o.axis) {
    if (!is_finite(p)) fail(ErrorCategory::bad_input, "the axis polyline has a non-finite point");
  }
}

}  // namespace

FitResult SweepFitter::fit(const FitOptions& o) const {
  const auto start = std::chrono::steady_clock::now();
  validate(o);
  const Mesh& mesh = mesh_;
  const Topology& topo = impl_->traced();  // the walks that trace; the part uses the mesh's own

  FitResult r;
  r.sweep.name = o.name;
  // Refusals carry the fit as far as it got (FitFailure), for the report.
  const auto refuse = [&r](ErrorCategory category, const std::string& message) {
    throw FitFailure(category, message, r);
  };
  // Seeds must be on or near the mesh: their distance from its surface (a point on a large
  // face may be far from every vertex).
  r.seed_limit = o.seed_distance * impl_->diagonal;
  auto seed_vertex = [&](const Vec3& p, const char* what, double& off_surface) {
    off_surface = impl_->surface.distance(p);
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
    if (off_surface > r.seed_limit) {
      refuse(ErrorCategory::bad_input,
             std::string(what) + " " + format_point(p) + " is far from the mesh: " +
                 format_number(off_surface) + " from its surface, more than " +
                 format_number(o.seed_distance) + " of its bounding box diagonal (" +
                 format_number(r.seed_limit) + ")");
    }
    return nearest_vertex(mesh, p);
  };
  std::optional<Vec3> root = o.root;
  Vec3 tip_point = o.tip;
  if (!o.axis.empty()) {
    if (!root) root = o.axis.front();
    tip_point = o.axis.back();
  }
  if (root) r.root = *root;  // (until section 0 is cut: a refusal reports the root given)
  std::uint32_t tip0 = 0;
  if (o.tip_vertex >= 0) {
    if (static_cast<std::uint64_t>(o.tip_vertex) >= mesh.vertex_count()) {
      refuse(ErrorCategory::usage, "tip_vertex " + std::to_string(o.tip_vertex) +
                                       " is not a vertex of the mesh (it has " +
                                       std::to_string(mesh.vertex_count()) + ")");
    }
    tip0 = static_cast<std::uint32_t>(o.tip_vertex);
  } else {
    tip0 = seed_vertex(tip_point, "tip", r.tip_off_surface);
  }
  tip0 = topo.weld[tip0];
  r.tip_vertex = tip0;

  // 1. The tip: climb to the part's end, the local maximum of the distance from the body (the
  //    root, or, without one, the point of the surface farthest from the tip, which lies on
  //    another extremity).
  std::uint32_t root_vertex = 0;
  std::vector<double> field;
  if (root) {
    root_vertex = topo.weld[seed_vertex(*root, "root", r.root_off_surface)];
    field = surface_distances(mesh, topo, std::span(&root_vertex, 1));
  } else {
    const std::vector<double> from_tip = surface_distances(mesh, topo, std::span(&tip0, 1));
    std::uint32_t far = tip0;
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
      if (std::isfinite(from_tip[v]) && from_tip[v] > from_tip[far]) far = v;
    }
    field = surface_distances(mesh, topo, std::span(&far, 1));
  }
  if (!std::isfinite(field[tip0])) {
    refuse(ErrorCategory::bad_input, "the tip (vertex " + std::to_string(tip0) +
                                         ") is not reachable from the root: they lie on separate "
                                         "pieces of the mesh");
  }
  // A tip given mid-tube (the tube goes on past it: a hose, a knot) has no end to climb to: the
  // part is the stretch from the root to the tip, cut at its last section too.
  std::vector<double> from_tip0;
  bool mid_tube = false;
  if (root && o.axis.empty()) {
    from_tip0 = surface_distances(mesh, topo, std::span(&tip0, 1));
    mid_tube = rings_run_both_ways(mesh, topo, from_tip0, kBothWaysLevel * from_tip0[root_vertex]);
  }
  // A tip given as a vertex is the end itself (what --list and --all name: the extremity whose
  // rings found the part); climbing from it may reach another end (the camel's muzzle climbed
  // to an ear and fitted a stub 0.009 long).
  r.tip_vertex = o.axis.empty() && !mid_tube && o.tip_vertex < 0 ? climb(topo, field, tip0) : tip0;
  if (mid_tube) {
    r.tip_cut = true;
    r.tip_cut_reason = "the rings of surface distance from the tip run both ways along the tube (it "
                       "goes on past the tip at least as far as the root lies before it): the part "
                       "is cut at its last section too";
  }
  // How far the part's end lies from the tip asked for: worth a warning past a radius (below).
  const double tip_moved =
      (mesh.positions[r.tip_vertex] - (o.tip_vertex >= 0 ? mesh.positions[tip0] : tip_point)).norm();

  // 2. Rings from the tip, and the root among them.
  const std::vector<double> d = r.tip_vertex == tip0 && !from_tip0.empty()
                                    ? std::move(from_tip0)
                                    : surface_distances(mesh, topo, std::span(&r.tip_vertex, 1));
  const RingTrace rings = trace_rings(mesh, topo, d, r.tip_vertex,
                                      std::numeric_limits<double>::infinity(), true, o.rings);
  if (rings.rings.size() < 2) {
    refuse(ErrorCategory::bad_input, "no rings of surface distance around the tip (vertex " +
                                         std::to_string(r.tip_vertex) +
                                         "): the surface there is too small or not connected");
  }
  const auto ring = [&](int i) -> const Ring& { return rings.rings[static_cast<std::size_t>(i)]; };
  int root_ring = rings.junction;
  if (root) {
    int last = rings.junction;
    const int n = static_cast<int>(rings.rings.size());
    while (last + 1 < n && ring(last + 1).distance <= d[root_vertex]) ++last;
    root_ring = 0;
    for (int i = 1; i <= last; ++i) {
      if ((ring(i).centroid - *root).norm() < (ring(root_ring).centroid - *root).norm())
        root_ring = i;
    }
    r.root_reason = "section 0 is cut through the ring nearest to the given root, at distance " +
                    format_number(ring(root_ring).distance) + " from the tip";
    // A root a little past the junction only adds a short flare; warn when it has widened.
    if (root_ring > rings.junction &&
        ring(root_ring).radius > (1 + kWidenedRootShare) * ring(rings.junction).radius) {
      r.warnings.push_back("the root lies past where the part meets the body (" +
                           rings.junction_reason +
                           "); section 0 is cut where the part has widened");
    }
  } else {
    r.root_found = true;
    r.root_reason = rings.junction_reason;
  }
  // No body: the rings ran to the far end of the surface, a cap like the tip's (they shrink
  // over it). The axis runs through the rings before it, then straight on to its end.
  const bool far_end = !root && rings.junction + 1 == static_cast<int>(rings.rings.size());
  if (far_end) {
    while (root_ring > 1 && ring(root_ring).growth < -o.rings.settled_growth) --root_ring;
  }
  r.surface_length = ring(root_ring).distance;
  // Where the part leaks past its root (below): farther from the tip than the root's ring.
  double root_distance = ring(root_ring).distance, root_radius = ring(root_ring).radius;

  // 3. The axis: ring centroids from the root to the tip, refined by plane slices; mid-tube,
  //    slice centroids along the surface path from the root to the tip (the rings run both ways).
  if (mid_tube) {
    std::vector<Vec3> points;
    std::vector<double> radii;
    path_axis_points(mesh, topo, impl_->slicer, field, r.tip_vertex, points, radii);
    if (points.size() >= 2) r.axis = refine_axis(impl_->slicer, points, radii);
    if (!r.axis.points.empty()) {
      trim_axis_start(r.axis, *root, 2 * radii.front());
      r.axis.end_reason = "the tip was given mid-tube: the axis ends there";
      root_radius = radii.front();
    }
    r.surface_length = root_distance = d[root_vertex];
    r.root_reason = "section 0 is cut where the given root projects onto the axis (the tip was "
                    "given mid-tube)";
  } else if (o.axis.empty()) {
    std::vector<Vec3> points;
    std::vector<double> radii;
    const int first = root_ring;
    // The axis runs through the rings of the tube; past the tip's cap it goes straight on to
    // the cap's farthest point.
    const int cap = first_tube_ring(rings, first, o.rings);
    for (int i = first; i >= cap; --i) {
      points.push_back(ring(i).centroid);
      radii.push_back(ring(i).radius);
    }
    if (points.size() < 2) {  // the tip's cap reaches the root: the rings alone
      points = {ring(first).centroid, ring(0).centroid};
      radii = {ring(first).radius, ring(0).radius};
    }
    r.axis = refine_axis(impl_->slicer, points, radii);
    if (!r.axis.points.empty()) {
      extend_axis(impl_->slicer, impl_->surface, r.axis,
                  cap_reach(mesh, d, ring(cap).distance, true, r.axis.points.back(),
                            r.axis.tangents.back()));
    }
    if (far_end && !r.axis.points.empty()) {
      const std::string tip_end = r.axis.end_reason;  // (the root side's is not the one asked)
      reverse_axis(r.axis);
      extend_axis(impl_->slicer, impl_->surface, r.axis,
                  cap_reach(mesh, d, ring(root_ring).distance, false, r.axis.points.back(),
                            r.axis.tangents.back()));
      reverse_axis(r.axis);
      r.axis.end_reason = tip_end;
    } else {
      // Section 0 where the root (or, found, the root ring's centre) projects onto the axis,
      // which may lie a little before the first point kept.
      trim_axis_start(r.axis, root ? *root : ring(root_ring).centroid,
                      2 * ring(root_ring).radius);
    }
  } else {
    r.axis = axis_from_polyline(impl_->slicer, o.axis);
  }
  if (r.axis.points.size() < 2) {
    refuse(ErrorCategory::bad_input, "the part from vertex " + std::to_string(r.tip_vertex) +
                                         " has no length to fit (" + r.root_reason + ")");
  }
  if (o.axis.empty()) limit_axis_curvature(r.axis, kMaxCurvatureRadii);
  const std::vector<double> s = arc_lengths(r.axis.points);
  r.traced_length = s.back();
  if (!o.axis.empty()) r.surface_length = r.traced_length;
  // The last key section: the point nearest the tip whose slice is a real loop at least
  // kCapRadii of its radius from the tip; likewise the first at a far end without a body.
  std::size_t end = r.axis.points.size() - 1;
  while (end > 1 &&
         !(r.axis.radii[end] > 0 && s.back() - s[end] >= kCapRadii * r.axis.radii[end])) {
    --end;
  }
  std::size_t begin = 0;
  while (far_end && begin + 1 < end &&
         !(r.axis.radii[begin] > 0 && s[begin] >= kCapRadii * r.axis.radii[begin])) {
    ++begin;
  }
  AxisTrace cut;
  const auto first = static_cast<std::ptrdiff_t>(begin), last = static_cast<std::ptrdiff_t>(end + 1);
  cut.points.assign(r.axis.points.begin() + first, r.axis.points.begin() + last);
  cut.tangents.assign(r.axis.tangents.begin() + first, r.axis.tangents.begin() + last);
  cut.radii.assign(r.axis.radii.begin() + first, r.axis.radii.begin() + last);
  // A missing slice (0) takes its neighbours' size (sections_along); with none at all, the tip
  // ring's size serves the fallback circles.
  if (std::none_of(cut.radii.begin(), cut.radii.end(), [](double x) { return x > 0; }))
    std::fill(cut.radii.begin(), cut.radii.end(), ring(0).radius);
  if (!(arc_lengths(cut.points).back() > 0)) {
    refuse(ErrorCategory::bad_input, "the part from vertex " + std::to_string(r.tip_vertex) +
                                         " is too short to cut two key sections");
  }

  // 4. Sections (a fixed K, or the fewest that meet the tolerance), part, error.
  std::vector<std::pair<double, double>> along;  // (t, distance) of each measured part vertex
  const std::vector<std::string> warnings_before_sections = r.warnings;
  auto build = [&](int k) {
    r.star_violations.clear();
    r.sweep.rest = sections_along(impl_->slicer, cut, k, o.radial, &r.star_violations, &r.warnings);
    r.length = r.sweep.rest.length();
    const PartSeeds seeds{Vec3::Zero(), mesh.positions[r.tip_vertex], r.tip_cut};
    r.part_vertices = select_sweep_part(mesh, impl_->topology, r.sweep.rest, seeds);
    const std::vector<double> slice_radii = r.sweep.rest.radii;
    // The radii that best match the part's vertices (the slices run through facets' chords).
    std::vector<std::uint32_t> fitted_to = r.part_vertices;
    fit_radii(r.sweep.rest, mesh, fitted_to);
    // The part again, as sweep-bind will select it: its bound near the sweep reads the radii.
    r.part_vertices = select_sweep_part(mesh, impl_->topology, r.sweep.rest, seeds);
    for (int refit = 0; refit < kMaxRefits && r.part_vertices != fitted_to; ++refit) {
      fitted_to = r.part_vertices;
      r.sweep.rest.radii = slice_radii;
      fit_radii(r.sweep.rest, mesh, fitted_to);
      r.part_vertices = select_sweep_part(mesh, impl_->topology, r.sweep.rest, seeds);
    }
    // The limits below are relative to the radii the rig keeps, not to the slices'.
    const std::vector<double>& radii = r.sweep.rest.radii;
    r.mean_radius = 0;
    for (const double x : radii) r.mean_radius += x;
    r.mean_radius /= static_cast<double>(radii.size());
    along.clear();
    if (o.measure_error || o.tolerance > 0) {
      r.error = measure_fit_error(
          r.sweep.rest, mesh, r.part_vertices,
          std::span(impl_->traced().triangles).subspan(impl_->topology.triangles.size()),
          impl_->topology.weld, &along);
    }
  };
  if (o.tolerance > 0) {
    bool met = false;
    for (int k : kSectionLadder) {
      k = std::min(k, o.max_sections);
      build(k);
      if (r.error.rms <= o.tolerance * r.mean_radius) {
        met = true;
        break;
      }
      if (k == o.max_sections) break;
    }
    if (!met) {
      r.warnings.push_back("tolerance " + format_number(o.tolerance) + " not met with " +
                           std::to_string(r.sweep.rest.section_count()) +
                           " sections: the fit RMS is " + format_percent(r.error.rms / r.mean_radius) +
                           " of the mean radius");
    }
  } else {
    build(o.sections);
  }
  // 4b. An end that is not a tube: the sweep ends where the tube does (fit/tube_end.h). At a
  // fixed section count only: a foot spoils every rung of the tolerance search, which would climb
  // to max_sections before the end is cut (camel's hind leg: K = 256, 1.6 % RMS, the axis still
  // in the foot); and only when the error is measured, which tells where the end is.
  const bool fixed_count = o.tolerance == 0;
  // Cuts the sweep where `tube_end` begins and fits it again; kept (true) only if the cut fit meets
  // the limits below, else the fit is put back as it was.
  const auto cut_end = [&](const TubeEnd* tube_end, const char* kind) {
    const SweepShape& shape = r.sweep.rest;
    const int k = shape.section_count();
    {
      const int end_first = tube_end->first_section;
      const double end_rms = tube_end->end_rms, before_rms = tube_end->before_rms, share = tube_end->share;
      const std::size_t end_count = tube_end->end_count;
      const Vec3 end_point = shape.frames[static_cast<std::size_t>(end_first)].center;
      const double old_mean_radius = r.mean_radius;
      const FitResult uncut = r;
      const AxisTrace uncut_axis = cut;
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
      cut = ended;
      r.warnings = warnings_before_sections;  // (the sections' own are given again)
      build(k);
      const double ended_length = se.back();
      const double ended_gap = (mesh.positions[r.tip_vertex] - ended.points.back()).norm();
      // The surface distance from the tip to the tube's end: of the part's vertices within half
      // a spacing of the last section, the mean. The axis is measured against the rest.
      double end_distance = 0;
      {
        const SweepLocator locator(r.sweep.rest);
        const double from = r.sweep.rest.length() * (1 - 0.5 / (k - 1));
        std::size_t n_end = 0;
        for (const std::uint32_t v : r.part_vertices) {
          const SweepCoords c = locator.locate(mesh.positions[v]);
          if (c.z != 0 || c.t < from || !std::isfinite(d[v])) continue;
          end_distance += d[v];
          ++n_end;
        }
        if (n_end > 0) end_distance /= static_cast<double>(n_end);
      }
      const double tube_surface = r.surface_length - end_distance;
      const std::size_t old_count = uncut.part_vertices.size();
      std::size_t gained = 0;
      for (const std::uint32_t v : r.part_vertices)
        gained += !std::binary_search(uncut.part_vertices.begin(), uncut.part_vertices.end(), v);
      const bool fits =
          r.error.measured_count > 0 && r.error.p90 <= o.max_error * r.mean_radius &&
          r.error.rms < uncut.error.rms / old_mean_radius * r.mean_radius &&
          r.error.surface_p90 <= o.max_surface_error * r.mean_radius &&
          r.beyond_root_share() <= o.max_beyond_root_share &&
          static_cast<double>(gained) <= o.max_leak_share * static_cast<double>(old_count) &&
          !(ended_length < o.min_length_ratio * tube_surface &&
            ended_gap > o.max_tip_gap * r.mean_radius);
      if (fits) {
        r.axis = std::move(ended);
        r.traced_length = ended_length;
        r.surface_length = tube_surface;
        const std::size_t carried = r.error.beyond_ends_count - r.error.beyond_root_count;
        r.end_cut = true;
        r.end_cut_reason =
            "the part's end is not a tube (" + std::string(kind) + "): the sweep fitted through it "
            "was " + format_percent(end_rms / old_mean_radius) + " of the mean radius off its " +
            std::to_string(end_count) + " vertices (RMS) over the last " + format_percent(share) +
            " of its length, against " + format_percent(before_rms / old_mean_radius) +
            " before; the axis and the sweep end at " + format_point(end_point, 4) +
            ", and the " + std::to_string(carried) +
            " vertices past the sweep's last section are carried rigidly by it (the axis is "
            "measured against the surface distance from the root ring to there, " +
            format_number(tube_surface) + "; on to the tip it is " +
            format_number(end_distance) + " more)";
        r.axis.end_reason = "the part's end is not a tube past " + format_point(end_point, 4) +
                            " (the sweep was " + format_percent(end_rms / old_mean_radius) +
                            " of the mean radius off it, RMS)";
        return true;
      }
      r = uncut;
      cut = uncut_axis;
      return false;
    }
  };
  const bool may_cut = o.axis.empty() && !mid_tube && !far_end && fixed_count && o.measure_error;
  if (may_cut && r.error.measured_count > 0) {
    if (const std::optional<TubeEnd> tube_end =
            find_tube_end(r.sweep.rest, along, o.max_error * r.mean_radius, r.mean_radius)) {
      cut_end(&*tube_end, "a foot, a hoof, a tuft");
    }
  }
  // 4c. An end the sweep cannot follow and 4b does not cut (a head turned across the neck, a hand,
  // clicked at its top or a fingertip: a long end, or sections far apart): when the fit breaks
  // the error limits, the sweep is cut where the spans first go off the tube from the root on,
  // or up to kMaxWideEndSteps sections before, the first cut that meets every limit kept.
  const auto too_far = [&] {
    return r.error.measured_count > 0 && (r.error.p90 > o.max_error * r.mean_radius ||
                                          r.error.surface_p90 > o.max_surface_error * r.mean_radius);
  };
  if (may_cut && !r.end_cut && too_far()) {
    for (const TubeEnd& wide : wide_end_cuts(r.sweep.rest, along, o.max_error * r.mean_radius)) {
      if (cut_end(&wide, "a head, a hand: an end the sweep cannot follow")) break;
    }
  }
  if (const std::string why = check_shape(r.sweep.rest); !why.empty()) {
    fail(ErrorCategory::internal, "the fitted sweep is invalid: " + why);
  }
  r.root = r.sweep.rest.frames[0].center;
  SweepShape shape = std::move(r.sweep.rest);
  r.sweep = make_sweep(o.name, std::move(shape));
  r.sweep.part = PartSeeds{r.root, mesh.positions[r.tip_vertex], r.tip_cut};

  // 5. What the user must know, and what makes the fit wrong.
  if (impl_->slicer.repaired_face_count() > 0) {
    r.warnings.push_back(
        std::to_string(impl_->slicer.repaired_face_count()) +
        " triangles were not manifold; the slicer duplicated vertices to take them");
  }
  if (!r.star_violations.empty()) {
    int rays = 0;
    for (const StarViolation& v : r.star_violations) rays += v.multi_crossing_rays + v.missed_rays;
    r.warnings.push_back(std::to_string(r.star_violations.size()) +
                         " sections are not star-shaped about their centre (" +
                         std::to_string(rays) + " rays; the outermost crossing was used)");
  }
  const double leak_level = root_distance + kLeakRadii * root_radius;
  for (const std::uint32_t v : r.part_vertices) r.leaked_count += d[v] > leak_level;
  const double part_count = static_cast<double>(std::max<std::size_t>(r.part_vertices.size(), 1));
  // Short against the surface and far from the tip: stopped early. (A foot or a head at the end
  // lengthens the surface path without leaving the axis short of the tip.)
  r.tip_gap = (mesh.positions[r.tip_vertex] - r.axis.points.back()).norm();
  if (r.traced_length < o.min_length_ratio * r.surface_length &&
      r.tip_gap > o.max_tip_gap * r.mean_radius) {
    r.problems.push_back("the axis (" + format_number(r.traced_length) + " long) covers only " +
                         format_percent(r.traced_length / r.surface_length) +
                         " of the surface distance from the tip to the root (" +
                         format_number(r.surface_length) + ") and ends " +
                         format_number(r.tip_gap / r.mean_radius) +
                         " mean radii from the tip: the trace stopped short of the tip (" +
                         (r.axis.end_reason.empty() ? std::string("the axis given ends there")
                                                    : r.axis.end_reason) +
                         ")");
  }
  if (static_cast<double>(r.leaked_count) > o.max_leak_share * part_count) {
    r.problems.push_back(
        "the part leaks past its root into the body: " + std::to_string(r.leaked_count) +
        " of its " + std::to_string(r.part_vertices.size()) +
        " vertices lie farther from the tip than the root section; give --root where the part "
        "is still a tube");
  }
  if (o.measure_error || o.tolerance > 0) {
    if (r.error.measured_count == 0) {
      r.problems.push_back("none of the part's " + std::to_string(r.part_vertices.size()) +
                           " vertices lies between the end sections: there is no fit to measure");
    } else if (r.beyond_root_share() > o.max_beyond_root_share) {
      r.problems.push_back(std::to_string(r.error.beyond_root_count) + " of the part's " +
                           std::to_string(r.part_vertices.size()) +
                           " vertices lie before the root section: the root section does not "
                           "close the part off; move --root along the part");
    }
    if (r.error.measured_count > 0 && r.error.p90 > o.max_error * r.mean_radius) {
      r.problems.push_back("a tenth of the part's vertices are farther than " +
                           format_percent(r.error.p90 / r.mean_radius) +
                           " of the mean radius from the fit, above the limit of " +
                           format_percent(o.max_error) +
                           ": the part is not a tube where it is cut, or the axis strayed; try "
                           "--root nearer the tip, or more sections");
    }
    if (r.error.surface_samples > 0 &&
        r.error.surface_p90 > o.max_surface_error * r.mean_radius) {
      r.problems.push_back("a tenth of the fitted surface is farther than " +
                           format_percent(r.error.surface_p90 / r.mean_radius) +
                           " of the mean radius from the part's faces, above the limit of " +
                           format_percent(o.max_surface_error) +
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
  if (tip_moved > r.mean_radius) {
    r.warnings.push_back("tip moved to the part's end, vertex " + std::to_string(r.tip_vertex) +
                         " at " + format_point(mesh.positions[r.tip_vertex]) + ", " +
                         format_number(tip_moved / r.mean_radius) +
                         " mean radii from the tip given");
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

FitResult fit_sweep(const Mesh& mesh, const FitOptions& options) {
  return SweepFitter(mesh).fit(options);
}

}  // namespace sweep::fit
