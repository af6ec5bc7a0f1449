#include "core/sweep_shape.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace sweep {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Cubic Hermite basis on u ∈ [0,1].
struct Hermite {
  double h00, h10, h01, h11;
  explicit Hermite(double u) {
    const double u2 = u * u, u3 = u2 * u;
    h00 = 2 * u3 - 3 * u2 + 1;
    h10 = u3 - 2 * u2 + u;
    h01 = -2 * u3 + 3 * u2;
    h11 = u3 - u2;
  }
};

int wrap(int j, int n) { return ((j % n) + n) % n; }

// Periodic uniform Catmull-Rom through section i's samples, at angle coordinate a.
double radius_in_section(const SweepShape& s, int i, const AngleCoord& a) {
  const int n = s.radial_count;
  const double p0 = s.radius_sample(i, wrap(a.j - 1, n)), p1 = s.radius_sample(i, a.j);
  const double p2 = s.radius_sample(i, wrap(a.j + 1, n)), p3 = s.radius_sample(i, wrap(a.j + 2, n));
  const Hermite b(a.w);
  return b.h00 * p1 + b.h10 * 0.5 * (p2 - p0) + b.h01 * p2 + b.h11 * 0.5 * (p3 - p1);
}

double min_sample(const SweepShape& s, int i, const AngleCoord& a) {
  const int n = s.radial_count;
  double m = s.radius_sample(i, a.j);
  for (int d : {-1, 1, 2}) m = std::min(m, s.radius_sample(i, wrap(a.j + d, n)));
  return m;
}

}  // namespace

double SweepShape::sample_angle(int j) const { return kTwoPi * j / radial_count; }

SpanCoord locate_span(const SweepShape& shape, double t) {
  const int k = shape.section_count();
  if (!(t > shape.t.front())) return {0, 0.0};  // also catches NaN
  if (t >= shape.t.back()) return {k - 2, 1.0};
  // First section whose parameter exceeds t; the span starts one before it.
  const auto it = std::upper_bound(shape.t.begin(), shape.t.end(), t);
  const int s = static_cast<int>(it - shape.t.begin()) - 1;
  return {s, (t - shape.t[s]) / (shape.t[s + 1] - shape.t[s])};
}

AngleCoord locate_angle(int radial_count, double theta) {
  double a = std::fmod(theta, kTwoPi);
  if (a < 0) a += kTwoPi;
  const double x = a * radial_count / kTwoPi;
  int j = static_cast<int>(std::floor(x));
  double w = x - j;
  if (j >= radial_count) {  // fmod rounding can land exactly on 2π
    j = 0;
    w = 0;
  }
  return {j, w};
}

Vec3 center_at(const SweepShape& shape, double t) {
  const SpanCoord sc = locate_span(shape, t);
  const Frame& a = shape.frames[sc.span];
  const Frame& b = shape.frames[sc.span + 1];
  const double h = shape.t[sc.span + 1] - shape.t[sc.span];
  const Hermite w(sc.u);
  return w.h00 * a.center + w.h10 * h * a.axis() + w.h01 * b.center + w.h11 * h * b.axis();
}

Quat rotation_at(const SweepShape& shape, double t) {
  const SpanCoord sc = locate_span(shape, t);
  if (sc.u == 0.0) return shape.frames[sc.span].rotation;
  if (sc.u == 1.0) return shape.frames[sc.span + 1].rotation;
  return shape.frames[sc.span].rotation.slerp(sc.u, shape.frames[sc.span + 1].rotation).normalized();
}

Frame frame_at(const SweepShape& shape, double t) { return {rotation_at(shape, t), center_at(shape, t)}; }

double radius_at(const SweepShape& shape, double theta, double t) {
  const SpanCoord sc = locate_span(shape, t);
  const AngleCoord ac = locate_angle(shape.radial_count, theta);
  const int k = shape.section_count();
  const int i0 = sc.span, i1 = sc.span + 1;
  const double r0 = radius_in_section(shape, i0, ac), r1 = radius_in_section(shape, i1, ac);
  if (sc.u == 0.0) return r0;  // exact at the key sections (the floor cannot bite on a sample)
  if (sc.u == 1.0) return r1;
  // Finite-difference slopes dr/dt at both ends of the span (one-sided at the end sections),
  // turned into per-span Hermite tangents by the span length h.
  const double h = shape.t[i1] - shape.t[i0];
  auto slope = [&](int i) {
    const int lo = std::max(i - 1, 0), hi = std::min(i + 1, k - 1);
    return (radius_in_section(shape, hi, ac) - radius_in_section(shape, lo, ac)) / (shape.t[hi] - shape.t[lo]);
  };
  const Hermite w(sc.u);
  const double r = w.h00 * r0 + w.h10 * h * slope(i0) + w.h01 * r1 + w.h11 * h * slope(i1);
  const double floor = kMinRadiusFraction * std::min(min_sample(shape, i0, ac), min_sample(shape, i1, ac));
  return std::max(r, floor);
}

void radii_at_samples(const SweepShape& shape, double t, std::span<double> out) {
  const SpanCoord sc = locate_span(shape, t);
  const int k = shape.section_count(), n = shape.radial_count;
  const int i0 = sc.span, i1 = sc.span + 1;
  const int lo0 = std::max(i0 - 1, 0), hi0 = std::min(i0 + 1, k - 1);
  const int lo1 = std::max(i1 - 1, 0), hi1 = std::min(i1 + 1, k - 1);
  const double h = shape.t[i1] - shape.t[i0];
  const double g0 = h / (shape.t[hi0] - shape.t[lo0]), g1 = h / (shape.t[hi1] - shape.t[lo1]);
  const Hermite w(sc.u);
  for (int j = 0; j < n; ++j) {
    // At a sample angle the periodic Catmull-Rom in θ is the sample itself; what is left is the
    // Hermite in t with finite-difference slopes, exactly as radius_at does it.
    const double r0 = shape.radius_sample(i0, j), r1 = shape.radius_sample(i1, j);
    const double m0 = g0 * (shape.radius_sample(hi0, j) - shape.radius_sample(lo0, j));
    const double m1 = g1 * (shape.radius_sample(hi1, j) - shape.radius_sample(lo1, j));
    out[j] = w.h00 * r0 + w.h10 * m0 + w.h01 * r1 + w.h11 * m1;
  }
}

Vec3 surface_point(const SweepShape& shape, double theta, double t) {
  const Frame f = frame_at(shape, t);
  const double r = radius_at(shape, theta, t);
  return f.to_world(Vec3(r * std::cos(theta), r * std::sin(theta), 0.0));
}

std::string check_shape(const SweepShape& shape) {
  std::ostringstream why;
  const int k = shape.section_count();
  if (k < 2) {
    why << "a sweep needs at least 2 key sections, got " << k;
  } else if (shape.frames.size() != shape.t.size()) {
    why << "expected " << k << " frames, got " << shape.frames.size();
  } else if (shape.radial_count < 3) {
    why << "a section needs at least 3 radius samples, got " << shape.radial_count;
  } else if (shape.radii.size() != static_cast<std::size_t>(k) * shape.radial_count) {
    why << "expected " << k * shape.radial_count << " radii, got " << shape.radii.size();
  } else if (shape.t[0] != 0.0) {
    why << "the first section's t must be 0, got " << shape.t[0];
  } else {
    for (int i = 1; i < k; ++i) {
      if (!(shape.t[i] > shape.t[i - 1]) || !std::isfinite(shape.t[i])) {
        why << "section " << i << ": t must be finite and greater than section " << i - 1 << "'s";
        return why.str();
      }
    }
    for (std::size_t m = 0; m < shape.radii.size(); ++m) {
      if (!(shape.radii[m] > 0) || !std::isfinite(shape.radii[m])) {
        why << "section " << m / shape.radial_count << ", radius " << m % shape.radial_count
            << ": must be a finite positive number";
        return why.str();
      }
    }
  }
  return why.str();
}

}  // namespace sweep
