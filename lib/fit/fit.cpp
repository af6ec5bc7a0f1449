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
#include "sweep/fit/fit_stages.h"
#include "sweep/fit/hole_patches.h"
#include "sweep/fit/loop.h"
#include "sweep/fit/mid_tube.h"
#include "sweep/fit/slicer.h"
#include "sweep/fit/surface_distance.h"
#include "sweep/fit/tube_end.h"

namespace sweep::fit {
namespace {

// The error's tessellation of the sweep surface: stations per span and angles per radius sample.
constexpr int kErrorStationsPerSpan = 4;
constexpr int kErrorAnglesPerSample = 2;

}  // namespace

FitError measure_fit_error(const SweepShape& shape, const Mesh& mesh, const std::vector<std::uint32_t>& vertices,
                           std::span<const std::uint32_t> patches, std::span<const std::uint32_t> weld,
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
      const auto id = [&](int a, int b) { return static_cast<std::uint32_t>(a * angles + b % angles); };
      grid.insert(grid.end(), {id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i + 1, j)});
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

struct SweepFitter::Impl {
  explicit Impl(const Mesh& mesh)
      : topology(build_topology(mesh)),
        patched(fit::patched_topology(mesh, topology)),
        slicer(mesh.positions, traced().triangles),
        surface(mesh.positions, traced().triangles) {}
  // What the distances, rings and slices run over: patched where the mesh has holes.
  const Topology& traced() const { return patched ? *patched : topology; }
  Topology topology;                // the mesh's own: the part is walked over it (select_sweep_part)
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
  if (o.sections > limits::kMaxSections || o.max_sections > limits::kMaxSections || o.radial > limits::kMaxRadial) {
    bad("sections must be at most " + std::to_string(limits::kMaxSections) + " and radial at most " +
        std::to_string(limits::kMaxRadial));
  }
  if (!(o.tolerance >= 0) || !std::isfinite(o.tolerance)) bad("tolerance must be a finite number >= 0");
  if (o.tolerance > 0 && o.max_sections < 2) bad("max_sections must be at least 2");
  if (!is_finite(o.tip) || (o.root && !is_finite(*o.root))) bad("root and tip must be finite");
  if (o.name.empty()) bad("name must not be empty");
  for (const Vec3& p : o.axis) {
    if (!is_finite(p)) fail(ErrorCategory::bad_input, "the axis polyline has a non-finite point");
  }
}

}  // namespace

// The stages, in order (fit_stages.h says what each finds).
FitResult SweepFitter::fit(const FitOptions& o) const {
  const auto start = std::chrono::steady_clock::now();
  validate(o);
  const detail::FitInputs inputs{mesh_,         impl_->topology, impl_->traced(),
                                 impl_->slicer, impl_->surface,  impl_->diagonal};
  detail::FitRun run(inputs, o);
  const detail::Seeds seeds = run.resolve_seeds();
  detail::TipSearch tip = run.find_tip(seeds);
  detail::RootChoice root = run.find_root(seeds, tip);
  run.trace_axis(seeds, tip, root);
  AxisTrace span = run.key_section_span(root);
  detail::SectionFit sections = run.fit_sections(span);
  run.cut_ends(tip, root, span, sections);
  FitResult r = run.finish(tip, root);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

FitResult fit_sweep(const Mesh& mesh, const FitOptions& options) {
  return SweepFitter(mesh).fit(options);
}

}  // namespace sweep::fit
