#include "fit/loop.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace sweep::fit {
namespace {

// A ray's radius is floored at this fraction of the loop's largest extent from the centre, so a
// centre lying on the loop still gives a positive radius.
constexpr double kMinRadiusOfExtent = 1e-6;

bool contains(const std::vector<Vec2>& poly, const Vec2& p) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) inside = !inside;
    }
  }
  return inside;
}

double boundary_distance(const std::vector<Vec2>& poly, const Vec2& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2 ab = poly[i] - poly[j];
    const double len2 = ab.squaredNorm();
    const double u = len2 > 0 ? std::clamp((p - poly[j]).dot(ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, (poly[j] + u * ab - p).norm());
  }
  return best;
}

}  // namespace

PlaneBasis plane_basis(const Vec3& origin, const Vec3& normal) {
  PlaneBasis b;
  b.origin = origin;
  b.n = normal.normalized();
  // The world axis least aligned with n gives a well-conditioned u (deterministic).
  Eigen::Index k = 0;
  b.n.cwiseAbs().minCoeff(&k);
  b.u = (Vec3::Unit(k) - b.n * b.n[k]).normalized();
  b.v = b.n.cross(b.u);
  return b;
}

void measure_loop(const PlaneBasis& basis, Loop& loop) {
  double a2 = 0;  // twice the signed area
  Vec2 moment = Vec2::Zero();
  Vec2 mean = Vec2::Zero();
  const std::size_t m = loop.points.size();
  std::vector<Vec2> q(m);
  for (std::size_t i = 0; i < m; ++i) {
    q[i] = basis.to_plane(loop.points[i]);
    mean += q[i];
  }
  if (m > 0) mean /= static_cast<double>(m);
  for (std::size_t i = 0, j = m - 1; i < m; j = i++) {
    // Relative to the mean, so that loops far from the plane origin lose no precision.
    const Vec2 a = q[j] - mean, b = q[i] - mean;
    const double cross = a.x() * b.y() - a.y() * b.x();
    a2 += cross;
    moment += (a + b) * cross;
  }
  loop.area = std::abs(a2) / 2;
  loop.radius = std::sqrt(loop.area / std::numbers::pi);
  const double tiny = 1e-12 * (q.empty() ? 0.0 : (q[0] - mean).squaredNorm() + 1e-300);
  const Vec2 c = std::abs(a2) > tiny ? Vec2(mean + moment / (3 * a2)) : mean;
  // Put the centroid back in the loop's own plane (the slice plane, which may be offset from
  // the basis origin along n).
  double offset = 0;
  for (const Vec3& p : loop.points) offset += (p - basis.origin).dot(basis.n);
  if (m > 0) offset /= static_cast<double>(m);
  loop.centroid = basis.to_world(c) + offset * basis.n;
}

std::optional<Loop> loop_around(const std::vector<SlicePolyline>& slice, const Vec3& point,
                                const Vec3& normal, double max_distance) {
  const PlaneBasis basis = plane_basis(point, normal);
  const Vec2 p = Vec2::Zero();
  std::optional<std::size_t> best_inside, best_near;
  double best_area = std::numeric_limits<double>::infinity();
  double best_distance = max_distance;
  for (std::size_t i = 0; i < slice.size(); ++i) {
    const SlicePolyline& line = slice[i];
    if (line.points.size() < 3) continue;
    std::vector<Vec2> poly;
    poly.reserve(line.points.size());
    for (const Vec3& x : line.points) poly.push_back(basis.to_plane(x));
    if (contains(poly, p)) {
      double a2 = 0;
      for (std::size_t k = 0, j = poly.size() - 1; k < poly.size(); j = k++) {
        a2 += poly[j].x() * poly[k].y() - poly[j].y() * poly[k].x();
      }
      if (std::abs(a2) < best_area) {
        best_area = std::abs(a2);
        best_inside = i;
      }
    } else if (!best_inside) {
      const double d = boundary_distance(poly, p);
      if (d <= best_distance) {
        best_distance = d;
        best_near = i;
      }
    }
  }
  const std::optional<std::size_t> pick = best_inside ? best_inside : best_near;
  if (!pick) return std::nullopt;
  Loop loop;
  loop.points = slice[*pick].points;
  loop.was_open = !slice[*pick].closed;
  loop.around = best_inside.has_value();
  measure_loop(basis, loop);
  return loop;
}

RaySamples sample_radii(const Frame& frame, const std::vector<Vec3>& loop, int n) {
  RaySamples out;
  out.radii.assign(static_cast<std::size_t>(n), 0.0);
  const Mat3 r = frame.matrix();
  const Vec3 ex = r.col(0), ey = r.col(1);
  std::vector<Vec2> q;
  q.reserve(loop.size());
  double extent = 0;
  for (const Vec3& x : loop) {
    const Vec3 d = x - frame.center;
    q.emplace_back(d.dot(ex), d.dot(ey));
    extent = std::max(extent, q.back().norm());
  }
  const double floor = kMinRadiusOfExtent * extent;
  double hit_sum = 0;
  int hits = 0;
  std::vector<bool> missed(static_cast<std::size_t>(n), false);
  for (int j = 0; j < n; ++j) {
    const double theta = 2 * std::numbers::pi * j / n;
    const Vec2 dir(std::cos(theta), std::sin(theta));
    int crossings = 0;
    double outer = -1;
    // A segment crosses the ray's line where its ends lie on opposite sides of it. The side of
    // each vertex is computed once (on the line counts as below), so a ray through a vertex
    // crosses exactly one of the two segments that meet there, whatever the rounding.
    const auto side = [&](const Vec2& x) { return dir.x() * x.y() - dir.y() * x.x() > 0; };
    for (std::size_t i = 0, k = q.size() - 1; !q.empty() && i < q.size(); k = i++) {
      const Vec2 a = q[k], b = q[i];
      if (side(a) == side(b)) continue;
      const double ha = dir.x() * a.y() - dir.y() * a.x(), hb = dir.x() * b.y() - dir.y() * b.x();
      const double u = ha / (ha - hb);  // along the segment, where its height above the line is 0
      const double s = (a + u * (b - a)).dot(dir);  // along the ray
      if (!(s > 0)) continue;
      ++crossings;
      outer = std::max(outer, s);
    }
    if (crossings == 0) {
      missed[static_cast<std::size_t>(j)] = true;
      ++out.missed_rays;
      continue;
    }
    if (crossings > 1) ++out.multi_crossing_rays;
    out.radii[static_cast<std::size_t>(j)] = std::max(outer, floor);
    hit_sum += out.radii[static_cast<std::size_t>(j)];
    ++hits;
  }
  if (out.missed_rays > 0) {
    // The centre lies outside the loop (or on it): fall back to the mean of the rays that hit,
    // or the loop's mean distance when none did.
    double fill = hits > 0 ? hit_sum / hits : 0;
    if (hits == 0) {
      for (const Vec2& x : q) fill += x.norm();
      fill = q.empty() ? 0 : fill / static_cast<double>(q.size());
    }
    for (int j = 0; j < n; ++j) {
      if (missed[static_cast<std::size_t>(j)])
        out.radii[static_cast<std::size_t>(j)] = std::max(fill, floor);
    }
  }
  return out;
}

}  // namespace sweep::fit
