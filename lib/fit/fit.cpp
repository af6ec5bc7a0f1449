#include "fit/fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/limits.h"
#include "core/locate.h"
#include "fit/loop.h"
#include "fit/part.h"
#include "fit/slicer.h"
#include "io/mesh_io.h"

namespace sweep::fit {
namespace {

// Section counts tried by the tolerance search, about √2 apart.
constexpr int kSectionLadder[] = {2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64, 91, 128, 181, 256};
// The part reached from the tip must come this close to the root section's centre, in units of
// the root loop's extent (its farthest point from the centre); otherwise it is not the part
// that the traced axis leaves from.
constexpr double kRootReachExtents = 1.5;

std::string format(const Vec3& v) {
  std::ostringstream s;
  s << v.x() << "," << v.y() << "," << v.z();
  return s.str();
}

bool finite(const Vec3& v) {
  return v.allFinite();
}

// Position, tangent and RMF frame on the axis polyline at arc length t.
struct AxisSample {
  Vec3 point;
  Vec3 tangent;
  double radius;
};

AxisSample sample_axis(const AxisTrace& axis, const std::vector<double>& s, double t) {
  const std::size_t m = axis.points.size();
  std::size_t k = static_cast<std::size_t>(std::upper_bound(s.begin(), s.end(), t) - s.begin());
  k = std::clamp<std::size_t>(k, 1, m - 1) - 1;  // segment k → k+1
  const double span = s[k + 1] - s[k];
  const double u = span > 0 ? std::clamp((t - s[k]) / span, 0.0, 1.0) : 0.0;
  return {(1 - u) * axis.points[k] + u * axis.points[k + 1],
          ((1 - u) * axis.tangents[k] + u * axis.tangents[k + 1]).normalized(),
          (1 - u) * axis.radii[k] + u * axis.radii[k + 1]};
}

}  // namespace

SweepShape sections_along(const MeshSlicer& slicer, const AxisTrace& axis, int sections, int radial,
                          std::vector<StarViolation>* violations,
                          std::vector<std::string>* warnings) {
  const std::vector<double> s = arc_lengths(axis.points);
  const double length = s.back();
  const std::vector<Quat> rmf = rotation_minimizing_frames(axis.points, axis.tangents);

  SweepShape shape;
  shape.radial_count = radial;
  shape.t.resize(static_cast<std::size_t>(sections));
  shape.frames.resize(static_cast<std::size_t>(sections));
  shape.radii.resize(static_cast<std::size_t>(sections) * radial);
  for (int i = 0; i < sections; ++i) {
    const double t = i == sections - 1 ? length : length * i / (sections - 1);
    const AxisSample a = sample_axis(axis, s, t);
    // Carry the frame of the axis point at or before t to t by one double-reflection step.
    const std::size_t k = static_cast<std::size_t>(
        std::max<std::ptrdiff_t>(0, std::upper_bound(s.begin(), s.end(), t) - s.begin() - 1));
    const Vec3 x_k = rmf[k] * Vec3::UnitX();
    const Quat q = rotation_minimizing_frames({axis.points[k], a.point},
                                              {axis.tangents[k], a.tangent}, x_k)[1];
    Frame frame{q, a.point};
    shape.t[static_cast<std::size_t>(i)] = t;
    shape.frames[static_cast<std::size_t>(i)] = frame;

    const double reach = std::max(a.radius, 1e-9 * std::max(length, 1.0));
    const std::optional<Loop> loop =
        loop_around(slicer.slice(a.point, a.tangent), a.point, a.tangent, reach);
    double* out = shape.radii.data() + static_cast<std::size_t>(i) * radial;
    if (!loop) {
      // Only possible where the section plane, turned to the interpolated tangent, slips off a
      // tiny end cap: keep a circle of the traced radius.
      std::fill(out, out + radial, reach);
      if (warnings) {
        warnings->push_back("section " + std::to_string(i) + ": no slice loop around its centre " +
                            format(a.point) + "; used a circle of the traced radius");
      }
      continue;
    }
    const RaySamples rays = sample_radii(frame, loop->points, radial);
    std::copy(rays.radii.begin(), rays.radii.end(), out);
    if ((rays.multi_crossing_rays > 0 || rays.missed_rays > 0) && violations) {
      violations->push_back({i, rays.multi_crossing_rays, rays.missed_rays});
    }
    if (loop->was_open && warnings) {
      warnings->push_back(
          "section " + std::to_string(i) +
          ": the slice is an open polyline (a hole in the mesh), closed by its gap");
    }
  }
  return shape;
}

FitError measure_fit_error(const SweepShape& shape, const Mesh& mesh,
                           const std::vector<std::uint32_t>& vertices) {
  FitError e;
  const SweepLocator locator(shape);
  double sum2 = 0;
  for (const std::uint32_t v : vertices) {
    const SweepCoords c = locator.locate(mesh.positions[v]);
    if (c.z != 0) {
      ++e.beyond_ends_count;
      continue;
    }
    const double d = std::abs(c.s - 1) * radius_at(shape, c.theta, c.t);
    sum2 += d * d;
    e.max = std::max(e.max, d);
    ++e.measured_count;
  }
  e.rms = e.measured_count > 0 ? std::sqrt(sum2 / static_cast<double>(e.measured_count)) : 0;
  return e;
}

struct SweepFitter::Impl {
  explicit Impl(const Mesh& mesh) : slicer(mesh), adjacency(vertex_adjacency(mesh)) {}
  MeshSlicer slicer;
  VertexAdjacency adjacency;
  double diagonal = 0;
};

SweepFitter::SweepFitter(const Mesh& mesh) : mesh_(mesh) {
  io::validate_mesh(mesh, "mesh");
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

FitResult SweepFitter::fit(const FitOptions& o) const {
  const auto start = std::chrono::steady_clock::now();
  if (o.tolerance == 0 && o.sections < 2) {
    fail(ErrorCategory::usage, "--sections must be at least 2, got " + std::to_string(o.sections));
  }
  if (o.radial < 3) {
    fail(ErrorCategory::usage, "--radial must be at least 3, got " + std::to_string(o.radial));
  }
  // The rig reader's limits (core/limits.h): never write a rig that sweep-bind refuses.
  if (o.sections > limits::kMaxSections || o.max_sections > limits::kMaxSections ||
      o.radial > limits::kMaxRadial) {
    fail(ErrorCategory::usage, "--sections must be at most " + std::to_string(limits::kMaxSections) +
                                   " and --radial at most " + std::to_string(limits::kMaxRadial));
  }
  if (!(o.tolerance >= 0) || !std::isfinite(o.tolerance)) {
    fail(ErrorCategory::usage, "--tolerance must be a finite number ≥ 0");
  }
  if (o.tolerance > 0 && o.max_sections < 2) {
    fail(ErrorCategory::usage, "the maximum number of sections must be at least 2");
  }
  if (!finite(o.root) || !finite(o.tip))
    fail(ErrorCategory::usage, "--root and --tip must be finite");
  for (const Vec3& p : o.axis) {
    if (!finite(p)) fail(ErrorCategory::bad_input, "the axis polyline has a non-finite point");
  }

  // Root and tip must be on or near the mesh.
  const double seed_limit = o.seed_distance * impl_->diagonal;
  auto check_seed = [&](const Vec3& p, const char* what) {
    const double d = (mesh_.positions[nearest_vertex(mesh_, p)] - p).norm();
    if (d > seed_limit) {
      std::ostringstream s;
      s << what << " " << format(p) << " is far from the mesh: its nearest vertex is " << d
        << " away (more than " << o.seed_distance << " of the bounding box diagonal, " << seed_limit
        << ")";
      fail(ErrorCategory::bad_input, s.str());
    }
  };
  check_seed(o.root, "root");
  check_seed(o.tip, "tip");

  FitResult r;
  TraceOptions trace_options = o.trace;
  trace_options.root_max_distance = seed_limit;
  r.axis = o.axis.empty() ? trace_axis(impl_->slicer, o.root, o.tip, trace_options)
                          : axis_from_polyline(impl_->slicer, o.axis);
  if (!r.axis.reached_tip) {
    fail(ErrorCategory::bad_input,
         "tip " + format(o.tip) + " is not reachable from root " + format(o.root) +
             ": the axis trace lost the part (" + r.axis.stop_reason + ") " +
             std::to_string((o.tip - r.axis.points.back()).norm()) + " away from the tip");
  }
  if (r.axis.points.size() < 2) {
    fail(ErrorCategory::bad_input, "the part between root " + format(o.root) + " and tip " +
                                       format(o.tip) + " is too short to trace (" +
                                       r.axis.stop_reason + ")");
  }

  // The part: flood from the tip, bounded by the root plane.
  const Frame root_plane{Quat::FromTwoVectors(Vec3::UnitZ(), r.axis.tangents[0]), r.axis.points[0]};
  r.part_vertices = select_part(mesh_, impl_->adjacency, root_plane, o.tip);
  if (r.part_vertices.empty()) fail(ErrorCategory::bad_input, "the part has no vertices");
  double nearest_root = std::numeric_limits<double>::infinity();
  for (const std::uint32_t v : r.part_vertices) {
    nearest_root = std::min(nearest_root, (mesh_.positions[v] - r.axis.points[0]).norm());
  }
  const double root_reach = kRootReachExtents * r.axis.root_loop_extent;
  if (nearest_root > root_reach) {
    std::ostringstream s;
    s << "tip " << format(o.tip) << " is not reachable from root " << format(o.root)
      << ": the surface reached from the tip (" << r.part_vertices.size()
      << " vertices) comes no closer than " << nearest_root << " to the root section";
    fail(ErrorCategory::bad_input, s.str());
  }

  // Sections: a fixed K, or the fewest that meet the tolerance.
  auto build = [&](int k) {
    r.star_violations.clear();
    r.warnings.clear();
    r.sweep.rest =
        sections_along(impl_->slicer, r.axis, k, o.radial, &r.star_violations, &r.warnings);
    const std::vector<double>& radii = r.sweep.rest.radii;
    r.mean_radius = 0;
    for (const double x : radii) r.mean_radius += x;
    r.mean_radius /= static_cast<double>(radii.size());
    r.length = r.sweep.rest.length();
    if (o.measure_error || o.tolerance > 0) {
      r.error = measure_fit_error(r.sweep.rest, mesh_, r.part_vertices);
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
      std::ostringstream s;
      s << "tolerance " << o.tolerance << " not met with " << r.sweep.rest.section_count()
        << " sections: fit_rms is " << r.error.rms / r.mean_radius << " of the mean radius";
      r.warnings.push_back(s.str());
    }
  } else {
    build(o.sections);
  }

  if (const std::string why = check_shape(r.sweep.rest); !why.empty()) {
    fail(ErrorCategory::internal, "the fitted sweep is invalid: " + why);
  }
  SweepShape shape = std::move(r.sweep.rest);
  r.sweep = make_sweep(o.name, std::move(shape));
  r.sweep.part = PartSeeds{o.root, o.tip};
  if (impl_->slicer.repaired_face_count() > 0) {
    r.warnings.push_back(
        std::to_string(impl_->slicer.repaired_face_count()) +
        " triangles were not manifold; the slicer duplicated vertices to take them");
  }
  if (r.error.measured_count < r.part_vertices.size() / 2) {
    // Most of the part lies beyond the end sections: the root plane cut more than the part (a
    // root at a junction whose plane also slices the body), or the tip stops short of the end.
    r.warnings.push_back("only " + std::to_string(r.error.measured_count) + " of the part's " +
                         std::to_string(r.part_vertices.size()) +
                         " vertices lie between the end sections: move the root further out "
                         "along the part, or the tip to its end");
  }
  if (!r.star_violations.empty()) {
    int rays = 0;
    for (const StarViolation& v : r.star_violations) rays += v.multi_crossing_rays + v.missed_rays;
    r.warnings.push_back(std::to_string(r.star_violations.size()) +
                         " sections are not star-shaped about their centre (" +
                         std::to_string(rays) + " rays; the outermost crossing was used)");
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

FitResult fit_sweep(const Mesh& mesh, const FitOptions& options) {
  return SweepFitter(mesh).fit(options);
}

}  // namespace sweep::fit
