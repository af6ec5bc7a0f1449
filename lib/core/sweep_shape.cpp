#include "sweep/core/sweep_shape.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace sweep {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// The periodic Catmull-Rom cell of section i that angle coordinate a falls in.
CatmullRomCell cell_of(const SweepShape& s, int i, const AngleCoord& a) {
  return CatmullRomCell(s.section_radii(i), a.j);
}

}  // namespace

Slerp::Slerp(const Quat& a, const Quat& b) {
  // Eigen's Quaternion::slerp, its pair-only part: the weight of b is negated there when the dot
  // product is negative; here b is (the same bits: negation is exact).
  const double d = a.dot(b);
  const double abs_d = std::abs(d);
  linear_ = abs_d >= 1.0 - Eigen::NumTraits<double>::epsilon();
  if (!linear_) {
    theta_ = std::acos(abs_d);
    sin_theta_ = std::sin(theta_);
  }
  a_ = a.coeffs();
  b_ = (d < 0 ? -1.0 : 1.0) * b.coeffs();
}

Quat Slerp::at(double u) const {
  Quat q;
  if (linear_) {
    q.coeffs() = (1.0 - u) * a_ + u * b_;
  } else {
    q.coeffs() = (std::sin((1.0 - u) * theta_) / sin_theta_) * a_ + (std::sin(u * theta_) / sin_theta_) * b_;
  }
  return q;
}

void Slerp::at_steps(std::span<Quat> out) const {
  const int steps = static_cast<int>(out.size()) - 1;
  if (linear_) {
    for (int q = 0; q <= steps; ++q) {
      const double u = static_cast<double>(q) / steps;
      out[q].coeffs() = (1 - u) * a_ + u * b_;
    }
    return;
  }
  // sin(q·δ), δ = θ/S, by the recurrence, held in the w slots of `out` until the pair of points
  // that weights by them (q and S − q) is written.
  const auto sine = [&](int q) -> double& { return out[q].w(); };
  const double delta = theta_ / steps;
  const double c2 = 2 * std::cos(delta);
  sine(0) = 0;
  sine(1) = std::sin(delta);
  for (int q = 1; q < steps; ++q) sine(q + 1) = c2 * sine(q) - sine(q - 1);
  sine(steps) = sin_theta_;  // exact at the end
  const double inv_sin = 1.0 / sin_theta_;
  for (int q = 0; 2 * q <= steps; ++q) {
    const double near = sine(q), far = sine(steps - q);  // sin(qδ), sin((S − q)δ)
    out[q].coeffs() = (far * inv_sin) * a_ + (near * inv_sin) * b_;
    out[steps - q].coeffs() = (near * inv_sin) * a_ + (far * inv_sin) * b_;
  }
}

double SweepShape::sample_angle(int j) const {
  return kTwoPi * j / radial_count;
}

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
  const HermiteBasis w(sc.u);
  return w.h00 * a.center + w.h10 * h * a.axis() + w.h01 * b.center + w.h11 * h * b.axis();
}

Quat rotation_at(const SweepShape& shape, double t) {
  const SpanCoord sc = locate_span(shape, t);
  if (sc.u == 0.0) return shape.frames[sc.span].rotation;
  if (sc.u == 1.0) return shape.frames[sc.span + 1].rotation;
  const Slerp arc(shape.frames[sc.span].rotation, shape.frames[sc.span + 1].rotation);
  return arc.at(sc.u).normalized();
}

Frame frame_at(const SweepShape& shape, double t) {
  return {rotation_at(shape, t), center_at(shape, t)};
}

double radius_at(const SweepShape& shape, double theta, double t) {
  const SpanCoord sc = locate_span(shape, t);
  const AngleCoord ac = locate_angle(shape.radial_count, theta);
  const int k = shape.section_count();
  const int i0 = sc.span, i1 = sc.span + 1;
  const CatmullRomCell c0 = cell_of(shape, i0, ac), c1 = cell_of(shape, i1, ac);
  const double r0 = c0.at(ac.w), r1 = c1.at(ac.w);
  if (sc.u == 0.0) return r0;  // exact at the key sections (the floor cannot bite on a sample)
  if (sc.u == 1.0) return r1;
  // Finite-difference slopes dr/dt at both ends of the span (one-sided at the end sections),
  // turned into per-span Hermite tangents by the span length h.
  const double h = shape.t[i1] - shape.t[i0];
  auto slope = [&](int i) {
    const int lo = std::max(i - 1, 0), hi = std::min(i + 1, k - 1);
    const double r_hi = cell_of(shape, hi, ac).at(ac.w), r_lo = cell_of(shape, lo, ac).at(ac.w);
    return (r_hi - r_lo) / (shape.t[hi] - shape.t[lo]);
  };
  const HermiteBasis w(sc.u);
  const double r = w.h00 * r0 + w.h10 * h * slope(i0) + w.h01 * r1 + w.h11 * h * slope(i1);
  const double floor = kMinRadiusFraction * std::min(c0.min_sample(), c1.min_sample());
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
  const HermiteBasis w(sc.u);
  for (int j = 0; j < n; ++j) {
    // At a sample angle the periodic Catmull-Rom in θ is the sample itself; what is left is the
    // Hermite in t with finite-difference slopes, exactly as radius_at does it.
    const double r0 = shape.radius_sample(i0, j), r1 = shape.radius_sample(i1, j);
    const double m0 = g0 * (shape.radius_sample(hi0, j) - shape.radius_sample(lo0, j));
    const double m1 = g1 * (shape.radius_sample(hi1, j) - shape.radius_sample(lo1, j));
    out[j] = w.h00 * r0 + w.h10 * m0 + w.h01 * r1 + w.h11 * m1;
  }
}

std::vector<double> station_parameters(const SweepShape& shape, int stations_per_span) {
  std::vector<double> t;
  station_parameters(shape, stations_per_span, t);
  return t;
}

void station_parameters(const SweepShape& shape, int stations_per_span, std::vector<double>& t) {
  const int k = shape.section_count();
  t.clear();
  t.reserve(static_cast<std::size_t>(std::max(k - 1, 0)) * stations_per_span + 1);
  for (int s = 0; s + 1 < k; ++s) {
    for (int q = 0; q < stations_per_span; ++q)
      t.push_back(shape.t[s] + (shape.t[s + 1] - shape.t[s]) * q / stations_per_span);
  }
  t.push_back(shape.length());
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
