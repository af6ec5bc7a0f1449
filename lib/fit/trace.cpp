#include "sweep/fit/trace.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

#include "sweep/core/error.h"
#include "sweep/core/frame.h"
#include "sweep/core/text.h"
#include "sweep/fit/loop.h"

namespace sweep::fit {
namespace {

// Smoothing window of the ring centroids, in local radii: removes the jitter of level sets over
// a faceted surface while keeping bends of a radius or more.
constexpr double kSmoothRadii = 0.5;
// Axis samples every this many median radii (bounded): enough to follow an elbow.
constexpr double kStationRadii = 0.25;
constexpr int kMinStations = 16;
constexpr int kMaxStations = 1000;
// A slice loop larger than this many local radii also cuts something else: keep the ring centre.
constexpr double kMaxSliceRadii = 1.5;
// ... and one whose centre lies farther than this many radii from the ring's has caught another
// surface beside the part (a tusk by a trunk): keep the ring centre.
constexpr double kMaxSliceShiftRadii = 0.5;
// Marching into the tip's cap goes on while each slice keeps this share of the last one's radius.
constexpr double kMinCapSliceShare = 0.8;
// ... and while the axis turns by less than this per step (a quarter radius): a bend of a radius.
constexpr double kMaxCapTurnDegrees = 15;
// An end point where the refined axis turns by more than this is off centre (see
// drop_kinked_ends); at most this many are dropped at each end.
constexpr double kMaxEndTurnDegrees = 15;
constexpr double kMinKinkDegrees = 3;
constexpr double kKinkRatio = 3;
constexpr int kMaxKinkedEndPoints = 4;
// limit_axis_curvature: at most this many rounds of smoothing.
constexpr int kMaxCurvatureRounds = 50;

}  // namespace

std::vector<double> arc_lengths(const std::vector<Vec3>& points) {
  std::vector<double> s(points.size(), 0.0);
  for (std::size_t i = 1; i < points.size(); ++i) s[i] = s[i - 1] + (points[i] - points[i - 1]).norm();
  return s;
}

namespace {

// Smoothing over arc length by a local quadratic (Gaussian weights, window sigma[i] at point i,
// but never narrower than a point and a half of the mean spacing): the value at s_i of the
// weighted least-squares parabola through the neighbours. Unlike a plain weighted mean it does not
// pull a bend inwards (a mean shrinks an arc of curvature κ by about κσ²/2); it is exact on any
// quadratic curve, so the end points too are fitted, from one side, without being drawn inwards:
// an end slice that caught some of the body or the cap is brought back in line with the rest.
std::vector<Vec3> smooth(const std::vector<Vec3>& points, const std::vector<double>& sigma) {
  const std::vector<double> s = arc_lengths(points);
  std::vector<Vec3> out = points;
  const std::size_t m = points.size();
  if (m < 4 || !(s.back() > 0)) return out;
  const double min_window = 1.5 * s.back() / static_cast<double>(m - 1);
  for (std::size_t i = 0; i < m; ++i) {
    if (!(sigma[i] > 0)) continue;
    const double w = std::max(sigma[i], min_window);
    // Normal equations of p(u) = a + b u + c u² in u = (s_j − s_i)/w.
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d rhs = Eigen::Matrix3d::Zero();  // rows: 1, u, u²; columns: x, y, z
    std::size_t count = 0;
    const auto add = [&](std::size_t j) {
      const double u = (s[j] - s[i]) / w;
      const double g = std::exp(-0.5 * u * u);
      const Eigen::Vector3d basis(1, u, u * u);
      normal += g * basis * basis.transpose();
      rhs += g * basis * points[j].transpose();
      ++count;
    };
    for (std::size_t j = i; j-- > 0 && s[i] - s[j] <= 2 * w;) add(j);
    for (std::size_t j = i; j < m && s[j] - s[i] <= 2 * w; ++j) add(j);
    if (count < 4) continue;  // too few neighbours for a parabola: keep the point
    const Eigen::LDLT<Eigen::Matrix3d> solve(normal);
    const Vec3 fitted = solve.solve(rhs).row(0).transpose();
    if (solve.info() == Eigen::Success && is_finite(fitted)) out[i] = fitted;
  }
  return out;
}

std::vector<Vec3> central_tangents(const std::vector<Vec3>& points) {
  const std::size_t m = points.size();
  std::vector<Vec3> t(m);
  for (std::size_t i = 0; i < m; ++i) {
    t[i] = (points[std::min(i + 1, m - 1)] - points[i == 0 ? 0 : i - 1]).normalized();
  }
  return t;
}

// Linear interpolation of per-point values at arc length x.
double value_at(const std::vector<double>& s, const std::vector<double>& v, double x) {
  const auto k = std::upper_bound(s.begin(), s.end(), x) - s.begin();
  if (k <= 0) return v.front();
  if (static_cast<std::size_t>(k) >= s.size()) return v.back();
  const double span = s[k] - s[k - 1];
  const double u = span > 0 ? (x - s[k - 1]) / span : 0;
  return (1 - u) * v[k - 1] + u * v[k];
}

Vec3 point_at(const std::vector<double>& s, const std::vector<Vec3>& p, double x) {
  const auto k = std::upper_bound(s.begin(), s.end(), x) - s.begin();
  if (k <= 0) return p.front();
  if (static_cast<std::size_t>(k) >= s.size()) return p.back();
  const double span = s[k] - s[k - 1];
  const double u = span > 0 ? (x - s[k - 1]) / span : 0;
  return (1 - u) * p[k - 1] + u * p[k];
}

}  // namespace

namespace {

// Drops end points where the axis kinks: turns in its last step by more than kMaxEndTurnDegrees,
// or by more than kKinkRatio times the turns further in and at least kMinKinkDegrees (a
// bend changes gently; an end that jumps aside does not bend). A ring at a junction or over a
// flat end is tilted and off centre, and so is its slice; the inner points are not. What is
// dropped is restored by the straight extensions of the ends.
void drop_kinked_ends(AxisTrace& trace) {
  const auto turn = [&](std::size_t a, std::size_t b, std::size_t c) {
    const Vec3 u = trace.points[b] - trace.points[a], v = trace.points[c] - trace.points[b];
    if (!(u.norm() > 0) || !(v.norm() > 0)) return 0.0;
    return std::acos(std::clamp(u.normalized().dot(v.normalized()), -1.0, 1.0)) * 180 / std::numbers::pi;
  };
  const auto kinked = [&](double last, double before) {
    return last > kMaxEndTurnDegrees || (last > kMinKinkDegrees && last > kKinkRatio * before);
  };
  const auto erase = [&](std::size_t i) {
    trace.points.erase(trace.points.begin() + static_cast<std::ptrdiff_t>(i));
    trace.tangents.erase(trace.tangents.begin() + static_cast<std::ptrdiff_t>(i));
    trace.radii.erase(trace.radii.begin() + static_cast<std::ptrdiff_t>(i));
  };
  // The turns further in: the median of the next three, the bend the end should continue.
  const auto inner = [&](double a, double b, double c) {
    return std::max(std::min(a, b), std::min(std::max(a, b), c));
  };
  bool dropped = false;
  for (int k = 0; k < kMaxKinkedEndPoints && trace.points.size() > 6 &&
                  kinked(turn(0, 1, 2), inner(turn(1, 2, 3), turn(2, 3, 4), turn(3, 4, 5)));
       ++k) {
    erase(0);
    dropped = true;
  }
  for (int k = 0; k < kMaxKinkedEndPoints && trace.points.size() > 6; ++k) {
    const std::size_t m = trace.points.size();
    const double before = inner(turn(m - 4, m - 3, m - 2), turn(m - 5, m - 4, m - 3), turn(m - 6, m - 5, m - 4));
    if (!kinked(turn(m - 3, m - 2, m - 1), before)) break;
    erase(m - 1);
    dropped = true;
  }
  if (dropped) trace.tangents = central_tangents(trace.points);
}

}  // namespace

AxisTrace refine_axis(const MeshSlicer& slicer, const std::vector<Vec3>& points, const std::vector<double>& radii) {
  AxisTrace trace;
  if (points.size() < 2) return trace;
  std::vector<double> half(radii.size());
  for (std::size_t i = 0; i < radii.size(); ++i) half[i] = kSmoothRadii * radii[i];
  const std::vector<Vec3> smoothed = smooth(points, half);
  const std::vector<double> s = arc_lengths(smoothed);
  const double length = s.back();
  if (!(length > 0)) return trace;
  std::vector<double> sorted = radii;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const double median = sorted[sorted.size() / 2];
  // Clamped as a double: a needle-thin ring over a long axis would overflow an int.
  const int stations =
      static_cast<int>(std::clamp(std::ceil(length / std::max(kStationRadii * median, 1e-12)),
                                  static_cast<double>(kMinStations), static_cast<double>(kMaxStations)));
  for (int i = 0; i <= stations; ++i) {
    const double x = length * i / stations;
    trace.points.push_back(point_at(s, smoothed, x));
    trace.radii.push_back(value_at(s, radii, x));
  }
  trace.tangents = central_tangents(trace.points);
  // Slice centroids: the centre of the section a key section would be cut around.
  // Two passes: slice at each point normal to the current tangent and move the point to its
  // loop's centroid, then smooth lightly; the second pass slices along the tangents of the first.
  // An end point takes its neighbour's tangent (its own is a one-sided chord through a point
  // not yet centred).
  std::vector<double> sliced;
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t m = trace.points.size();
    sliced.assign(m, 0.0);
    for (std::size_t i = 0; i < m; ++i) {
      const Vec3 p = trace.points[i];
      const Vec3 t = trace.tangents[std::clamp<std::size_t>(i, 1, std::max<std::size_t>(m, 2) - 2)];
      const double r = std::max(trace.radii[i], 1e-12);
      const std::optional<Loop> loop = loop_around(slicer.slice(p, t), p, t, r);
      if (!loop || !(loop->radius <= kMaxSliceRadii * r) || (loop->centroid - p).norm() > kMaxSliceShiftRadii * r) {
        continue;
      }
      sliced[i] = loop->radius;
      trace.points[i] = loop->centroid;
    }
    // An end whose slice failed is not on the axis (a ring over a cap or past a hole): drop it.
    std::size_t first = 0, last = m - 1;
    while (last - first > 1 && !(sliced[first] > 0)) ++first;
    while (last - first > 1 && !(sliced[last] > 0)) --last;
    const auto keep = [&](auto& v) {
      v.erase(v.begin() + static_cast<std::ptrdiff_t>(last + 1), v.end());
      v.erase(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(first));
    };
    keep(trace.points);
    keep(trace.radii);
    keep(sliced);
    std::vector<double> quarter(trace.points.size());
    for (std::size_t i = 0; i < quarter.size(); ++i) {
      quarter[i] = 0.5 * kSmoothRadii * std::max(sliced[i], trace.radii[i]);
      if (sliced[i] > 0) trace.radii[i] = sliced[i];
    }
    trace.points = smooth(trace.points, quarter);
    trace.tangents = central_tangents(trace.points);
  }
  trace.radii = sliced;
  drop_kinked_ends(trace);
  return trace;
}

void extend_axis(const MeshSlicer& slicer, const TriangleDistance& surface, AxisTrace& axis, double length) {
  const std::size_t m = axis.points.size();
  if (m < 2 || !(length > 0)) return;
  const Vec3 start = axis.points.back();
  const Vec3 forward = axis.tangents.back();
  const double spacing = std::max((axis.points[m - 1] - axis.points[m - 2]).norm(), 1e-12);
  const double reach = std::max(axis.radii.back(), 1e-12);
  double radius = axis.radii.back();
  const double min_turn_cos = std::cos(kMaxCapTurnDegrees * std::numbers::pi / 180);
  Vec3 p = start, t = forward;
  std::string why = "the slices reached the cap";
  for (int k = 0; k < kMaxStations; ++k) {
    const double left = length - (p - start).dot(forward);
    if (left <= spacing) break;
    const Vec3 ahead = p + spacing * t;
    // Only while the slice is still a section of the tube (not much smaller than the last, not
    // pulled aside): a slice that also cuts the end face or a bulb is off centre.
    const std::optional<Loop> loop = loop_around(slicer.slice(ahead, t), ahead, t, reach);
    const std::string at = " at " + format_point(ahead, 4);
    if (!loop) {
      why = "no slice loop around the axis" + at;
      break;
    }
    if (!(loop->radius <= kMaxSliceRadii * reach)) {
      why = "the slice" + at + " is " + format_number(loop->radius / reach) + " radii wide: it cuts more than the part";
      break;
    }
    if ((loop->centroid - ahead).norm() > reach) {
      why =
          "the slice" + at + " is pulled aside by " + format_number((loop->centroid - ahead).norm() / reach) + " radii";
      break;
    }
    if (loop->radius < kMinCapSliceShare * radius) {
      why = "the slice" + at + " shrank to " + format_percent(loop->radius / radius) + " of the last (the end's cap)";
      break;
    }
    const Vec3 chord = loop->centroid - p;
    if (!(chord.norm() > 0) || chord.normalized().dot(t) < min_turn_cos) {
      why = "the axis" + at + " would turn by more than " + format_number(kMaxCapTurnDegrees) + " degrees in a step";
      break;
    }
    t = chord.normalized();
    p = loop->centroid;
    radius = loop->radius;
    axis.points.push_back(p);
    axis.tangents.push_back(t);
    axis.radii.push_back(radius);
  }
  // Straight on to the cap's reach, but not out of the mesh.
  const double left = length - (p - start).dot(forward);
  const double to_surface = surface.ray_distance(p, t);
  const double go = std::min(left / std::max(t.dot(forward), 0.5), to_surface);
  if (go > 0 && std::isfinite(go)) {
    axis.points.push_back(p + go * t);
    axis.tangents.push_back(t);
    axis.radii.push_back(0);
    why += go == to_surface ? "; then straight on " + format_number(go) + " to the surface"
                            : "; then straight on " + format_number(go) + " to the cap's reach";
  }
  axis.end_reason = why;
}

void trim_axis_start(AxisTrace& axis, const Vec3& point, double max_extension) {
  const std::size_t m = axis.points.size();
  if (m < 2) return;
  // Before the start: extend straight along the first tangent. (Not re-centred by a slice: at a
  // junction the part flares into the body, and a slice there is pulled aside by any tilt.)
  const Vec3 t0 = axis.tangents[0];
  const double before = (axis.points[0] - point).dot(t0);
  if (before > 0 && (point - axis.points[0]).dot(axis.points[1] - axis.points[0]) <= 0) {
    axis.points.insert(axis.points.begin(), axis.points[0] - std::min(before, max_extension) * t0);
    axis.tangents.insert(axis.tangents.begin(), t0);
    axis.radii.insert(axis.radii.begin(), axis.radii[0]);
    return;
  }
  std::size_t best_k = 0;
  double best_u = 0, best_d = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + 1 < m; ++k) {
    const Vec3 ab = axis.points[k + 1] - axis.points[k];
    const double len2 = ab.squaredNorm();
    const double u = len2 > 0 ? std::clamp((point - axis.points[k]).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const double d = (axis.points[k] + u * ab - point).norm();
    if (d < best_d) {
      best_d = d;
      best_k = k;
      best_u = u;
    }
  }
  if (best_k + 1 == m - 1 && best_u >= 1) return;  // would leave nothing but the tip
  const auto lerp = [&](const auto& v) { return (1 - best_u) * v[best_k] + best_u * v[best_k + 1]; };
  const Vec3 p = lerp(axis.points);
  const Vec3 t = Vec3(lerp(axis.tangents)).normalized();
  const double a = axis.radii[best_k], b = axis.radii[best_k + 1];
  const double r = a > 0 && b > 0 ? (1 - best_u) * a + best_u * b : std::max(a, b);
  const std::size_t drop = best_u >= 1 ? best_k + 1 : best_k;
  axis.points.erase(axis.points.begin(), axis.points.begin() + static_cast<std::ptrdiff_t>(drop));
  axis.tangents.erase(axis.tangents.begin(), axis.tangents.begin() + static_cast<std::ptrdiff_t>(drop));
  axis.radii.erase(axis.radii.begin(), axis.radii.begin() + static_cast<std::ptrdiff_t>(drop));
  axis.points[0] = p;
  axis.tangents[0] = t;
  axis.radii[0] = r;
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
    trace.tangents[i] = (trace.points[std::min(i + 1, m - 1)] - trace.points[i == 0 ? 0 : i - 1]).normalized();
    const std::optional<Loop> l =
        loop_around(slicer.slice(trace.points[i], trace.tangents[i]), trace.points[i], trace.tangents[i], 0);
    if (l) trace.radii[i] = l->radius;
  }
  return trace;
}

std::vector<Quat> rotation_minimizing_frames(const std::vector<Vec3>& points, const std::vector<Vec3>& tangents,
                                             const Vec3& x0) {
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

int limit_axis_curvature(AxisTrace& axis, double max_curvature_radii) {
  const std::size_t m = axis.points.size();
  if (m < 3 || axis.radii.size() != m) return 0;
  // The local radius: the slice's where measured, the nearest measured one elsewhere.
  std::vector<double> r = axis.radii;
  const double largest = *std::max_element(r.begin(), r.end());
  for (std::size_t i = 0; i < m; ++i) {
    if (r[i] > 0) continue;
    std::size_t lo = i, hi = i;
    while (lo > 0 && !(axis.radii[lo] > 0)) --lo;
    while (hi + 1 < m && !(axis.radii[hi] > 0)) ++hi;
    const bool below = axis.radii[lo] > 0, above = axis.radii[hi] > 0;
    if (below && above)
      r[i] = i - lo <= hi - i ? axis.radii[lo] : axis.radii[hi];
    else
      r[i] = below ? axis.radii[lo] : above ? axis.radii[hi] : largest;
  }
  int moves = 0;
  for (int round = 0; round < kMaxCurvatureRounds; ++round) {
    std::vector<Vec3> next = axis.points;
    bool moved = false;
    for (std::size_t i = 1; i + 1 < m; ++i) {
      const Vec3 u = axis.points[i] - axis.points[i - 1], v = axis.points[i + 1] - axis.points[i];
      const double a = u.norm(), b = v.norm();
      if (!(a > 0) || !(b > 0)) continue;
      const double turn = std::acos(std::clamp(u.dot(v) / (a * b), -1.0, 1.0));
      if (turn / (0.5 * (a + b)) * r[i] <= max_curvature_radii) continue;
      next[i] = 0.5 * axis.points[i] + 0.25 * (axis.points[i - 1] + axis.points[i + 1]);
      moved = true;
      ++moves;
    }
    axis.points = std::move(next);
    if (!moved) break;
  }
  if (moves > 0) axis.tangents = central_tangents(axis.points);
  return moves;
}

}  // namespace sweep::fit
