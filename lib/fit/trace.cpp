#include "fit/trace.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

#include "core/error.h"
#include "fit/loop.h"

namespace sweep::fit {
namespace {

constexpr double kDegree = std::numbers::pi / 180;
// Root direction: at most this many chord updates, stopping early when the direction moves by
// less than 0.05 degrees.
constexpr int kRootIterations = 8;
// ... started from the direction to the tip and from kRootStarts directions tilted by
// kRootStartTilt around it; another start wins only with a loop this much smaller (relative).
constexpr int kRootStarts = 6;
constexpr double kRootStartTilt = 40 * kDegree;
constexpr double kRootAreaMargin = 0.02;
const double kRootSettledCos = std::cos(0.05 * kDegree);
// Trace corrector: a step whose chord turns from its plane's normal by more than 2 degrees is
// sliced again with the plane turned to the chord, at most this often.
constexpr int kCorrections = 4;
const double kCorrectCos = std::cos(2 * kDegree);

std::string format(const Vec3& v) {
  std::ostringstream s;
  s << v.x() << "," << v.y() << "," << v.z();
  return s.str();
}

}  // namespace

std::vector<double> arc_lengths(const std::vector<Vec3>& points) {
  std::vector<double> s(points.size(), 0.0);
  for (std::size_t i = 1; i < points.size(); ++i)
    s[i] = s[i - 1] + (points[i] - points[i - 1]).norm();
  return s;
}

AxisTrace trace_axis(const MeshSlicer& slicer, const Vec3& root, const Vec3& tip,
                     const TraceOptions& options) {
  const double chord = (tip - root).norm();
  if (!(chord > 0)) fail(ErrorCategory::bad_input, "root and tip are the same point");
  const Vec3 toward_tip = (tip - root) / chord;

  // 1. The root plane: the chord from the root loop's centroid to the centroid of the loop one
  //    radius ahead gives the direction; iterate until it settles. Oblique cuts of a tube have
  //    their centroids on its axis, so this converges in a few slices even when the straight
  //    line to the tip is far from the part's direction (a curled tail).
  auto root_loop = [&](const Vec3& d) {
    std::optional<Loop> l = loop_around(slicer.slice(root, d), root, d, options.root_max_distance);
    if (!l) {
      fail(ErrorCategory::bad_input,
           "root " + format(root) +
               " is not inside the mesh: no slice loop around it (put the root on the part's "
               "axis, where it leaves the body)");
    }
    return *l;
  };
  const double h_min = options.min_step_fraction * chord;
  const double h_max = options.max_step_fraction * chord;
  // The chord iteration from one starting direction; the root loop it settles on.
  // The chord iteration from one starting direction: the direction it settles on, its root
  // loop, and the area of the loop one radius ahead (away from a junction or an end cap, where
  // a cut can be small without being perpendicular).
  struct Settled {
    Vec3 dir;
    Loop loop;
    double ahead_area = std::numeric_limits<double>::infinity();
  };
  auto settle = [&](Vec3 dir) {
    Settled s{dir, root_loop(dir)};
    for (int it = 0; it < kRootIterations; ++it) {
      const double h = std::clamp(s.loop.radius, h_min, h_max);
      const Vec3 q = s.loop.centroid + h * s.dir;
      const std::optional<Loop> ahead =
          loop_around(slicer.slice(q, s.dir), q, s.dir, s.loop.radius);
      if (!ahead) break;
      s.ahead_area = ahead->area;
      const Vec3 next = (ahead->centroid - s.loop.centroid).normalized();
      if (next.dot(toward_tip) <= 0) break;
      const bool settled = next.dot(s.dir) > kRootSettledCos;
      s.dir = next;
      s.loop = root_loop(s.dir);
      if (settled) break;
    }
    return s;
  };
  // Started towards the tip and from directions around it; where they settle differently (a
  // root near a junction), the one whose loop ahead is least is along the part.
  Settled best = settle(toward_tip);
  const PlaneBasis around = plane_basis(root, toward_tip);
  for (int a = 0; a < kRootStarts; ++a) {
    const double phi = 2 * std::numbers::pi * a / kRootStarts;
    const Vec3 start =
        std::cos(kRootStartTilt) * toward_tip +
        std::sin(kRootStartTilt) * (std::cos(phi) * around.u + std::sin(phi) * around.v);
    Settled s = settle(start);
    if (s.ahead_area < best.ahead_area * (1 - kRootAreaMargin)) best = std::move(s);
  }
  const Vec3 dir0 = best.dir;

  AxisTrace trace;
  const Vec3 root_dir = dir0;
  Vec3 dir = dir0;
  Vec3 c = best.loop.centroid;
  double r = best.loop.radius;
  for (const Vec3& p : best.loop.points)
    trace.root_loop_extent = std::max(trace.root_loop_extent, (p - c).norm());
  trace.points.push_back(c);
  trace.radii.push_back(r);

  // 2. March towards the tip.
  const double max_turn_cos = std::cos(options.max_turn_degrees * kDegree);
  for (int step = 0;; ++step) {
    if (step == options.max_steps) {
      trace.stop_reason =
          "the trace took more than " + std::to_string(options.max_steps) + " steps";
      break;
    }
    const double h = std::clamp(options.step_fraction * r, h_min, h_max);
    const Vec3 q = c + h * dir;
    const double tip_reach = options.tip_reach_radii * r + h;
    // Done when the next plane passes the tip while the tip is near this section (a plane can
    // pass the tip's level long before a bending part gets there).
    if ((tip - q).dot(dir) <= 0 && (tip - c).norm() <= options.tip_pass_radii * r + h) {
      trace.reached_tip = true;
      trace.stop_reason = "the next plane passes the tip";
      break;
    }
    std::optional<Loop> l = loop_around(slicer.slice(q, dir), q, dir, r);
    if (!l) {
      trace.reached_tip = (tip - c).norm() <= tip_reach;
      trace.stop_reason = "no slice loop around the axis at " + format(q);
      break;
    }
    Vec3 next_dir = (l->centroid - c).normalized();
    // Corrector: in a bend the plane ahead is oblique to the axis and its centroid pulls the
    // chord round; turn the plane to the chord and slice again until the chord settles.
    Vec3 normal = dir;
    for (int it = 0; it < kCorrections && next_dir.dot(normal) < kCorrectCos; ++it) {
      const Vec3 q2 = c + h * next_dir;
      std::optional<Loop> l2 = loop_around(slicer.slice(q2, next_dir), q2, next_dir, r);
      if (!l2) break;
      normal = next_dir;
      l = std::move(l2);
      next_dir = (l->centroid - c).normalized();
    }
    if (next_dir.dot(dir) < max_turn_cos) {
      trace.reached_tip = (tip - c).norm() <= tip_reach;
      trace.stop_reason = "the axis turned by more than " +
                          std::to_string(options.max_turn_degrees) + " degrees in one step at " +
                          format(q);
      break;
    }
    c = l->centroid;
    r = l->radius;
    dir = next_dir;
    trace.points.push_back(c);
    trace.radii.push_back(r);
  }

  // 3. Tangents: the root plane's normal, central chords inside, the last chord at the end.
  const std::size_t m = trace.points.size();
  trace.tangents.resize(m);
  trace.tangents[0] = root_dir;
  for (std::size_t i = 1; i < m; ++i) {
    trace.tangents[i] = (trace.points[std::min(i + 1, m - 1)] - trace.points[i - 1]).normalized();
  }
  return trace;
}

AxisTrace axis_from_polyline(const MeshSlicer& slicer, const std::vector<Vec3>& points) {
  AxisTrace trace;
  for (const Vec3& p : points) {  // drop repeated points: they have no direction
    if (trace.points.empty() || (p - trace.points.back()).norm() > 0) trace.points.push_back(p);
  }
  const std::size_t m = trace.points.size();
  if (m < 2) fail(ErrorCategory::bad_input, "the axis polyline needs at least 2 distinct points");
  trace.tangents.resize(m);
  trace.radii.assign(m, 0.0);
  for (std::size_t i = 0; i < m; ++i) {
    trace.tangents[i] =
        (trace.points[std::min(i + 1, m - 1)] - trace.points[i == 0 ? 0 : i - 1]).normalized();
    const std::optional<Loop> l = loop_around(slicer.slice(trace.points[i], trace.tangents[i]),
                                              trace.points[i], trace.tangents[i], 0);
    if (!l) continue;
    trace.radii[i] = l->radius;
    if (i == 0) {
      for (const Vec3& p : l->points) {
        trace.root_loop_extent = std::max(trace.root_loop_extent, (p - trace.points[0]).norm());
      }
    }
  }
  trace.reached_tip = true;
  trace.stop_reason = "the axis polyline was given";
  return trace;
}

std::vector<Quat> rotation_minimizing_frames(const std::vector<Vec3>& points,
                                             const std::vector<Vec3>& tangents, const Vec3& x0) {
  std::vector<Quat> out(points.size());
  if (points.empty()) return out;
  Vec3 t = tangents[0].normalized();
  Vec3 x = x0 - t * t.dot(x0);
  if (!(x.squaredNorm() > 1e-24)) x = plane_basis(Vec3::Zero(), t).u;
  x.normalize();
  auto to_quat = [](const Vec3& ex, const Vec3& ez) {
    Mat3 m;
    m.col(0) = ex;
    m.col(1) = ez.cross(ex);
    m.col(2) = ez;
    return Quat(m).normalized();
  };
  out[0] = to_quat(x, t);
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const Vec3 t1 = tangents[i + 1].normalized();
    const Vec3 v1 = points[i + 1] - points[i];
    const double c1 = v1.squaredNorm();
    Vec3 xl = x, tl = t;
    if (c1 > 0) {  // reflect in the bisecting plane of the two points
      xl = x - (2 / c1) * v1.dot(x) * v1;
      tl = t - (2 / c1) * v1.dot(t) * v1;
    }
    const Vec3 v2 = t1 - tl;  // reflect tl onto the new tangent
    const double c2 = v2.squaredNorm();
    Vec3 x1 = c2 > 0 ? Vec3(xl - (2 / c2) * v2.dot(xl) * v2) : xl;
    x1 = (x1 - t1 * t1.dot(x1)).normalized();  // remove rounding drift
    out[i + 1] = to_quat(x1, t1);
    x = x1;
    t = t1;
  }
  return out;
}

}  // namespace sweep::fit
