#pragma once
// The sweep surface of the paper's §II, S(θ,t) = C(t) + R(t)·(r(θ,t) cos θ, r(θ,t) sin θ, 0),
// through K key sections. The same evaluation serves the rest pose and every deformed pose: it
// only sees section parameters, frames and radii, never which solver produced them.
//
// Interpolation choices (each reproduces the key sections exactly):
//  - C(t): cubic Hermite per span, tangents along each section's axis with length h = t_{i+1}-t_i
//    (for an arc-length parameter the tangent of a smooth curve is a unit vector times h per span);
//  - R(t): quaternion slerp per span (shortest arc), so frames stay orthonormal;
//  - r(θ,t): periodic uniform Catmull-Rom in θ through the n samples, then cubic Hermite in t with
//    finite-difference slopes (one-sided at the end sections). The result is floored at
//    kMinRadiusFraction of the smallest sample involved, so an overshooting cubic can never make
//    a radius negative; samples themselves are never changed by the floor.
// The interpolants themselves (HermiteBasis, CatmullRomCell, Slerp) are declared below: the fast
// deformation path (bind/fast_deform.h) tabulates its stations with them.
#include <algorithm>
#include <array>
#include <span>
#include <vector>

#include "sweep/core/frame.h"

namespace sweep {

// Lowest radius the interpolant may return, as a fraction of the smallest sample it interpolates.
inline constexpr double kMinRadiusFraction = 0.05;

struct SweepShape {
  std::vector<double> t;      // K section parameters (arc length), t[0] = 0, strictly increasing
  std::vector<Frame> frames;  // K section frames in world space
  int radial_count = 0;       // n radius samples per section, at θ_j = 2πj/n
  std::vector<double> radii;  // K*n samples; section i's sample j at radii[i*n + j]

  int section_count() const { return static_cast<int>(t.size()); }
  double length() const { return t.back(); }
  double radius_sample(int i, int j) const { return radii[static_cast<std::size_t>(i) * radial_count + j]; }
  std::span<const double> section_radii(int i) const {
    return {radii.data() + static_cast<std::size_t>(i) * radial_count, static_cast<std::size_t>(radial_count)};
  }
  double sample_angle(int j) const;
};

// Cubic Hermite basis on u ∈ [0,1]: p(u) = h00·p0 + h10·m0 + h01·p1 + h11·m1.
struct HermiteBasis {
  double h00, h10, h01, h11;
  explicit HermiteBasis(double u) {
    const double u2 = u * u, u3 = u2 * u;
    h00 = 2 * u3 - 3 * u2 + 1;
    h10 = u3 - 2 * u2 + u;
    h01 = -2 * u3 + 3 * u2;
    h11 = u3 - u2;
  }
};

// One cell of the periodic uniform Catmull-Rom through a section's n samples: cell j lies between
// samples j and j+1 (mod n) and is shaped by p0..p3 = r_{j-1}, r_j, r_{j+1}, r_{j+2}.
struct CatmullRomCell {
  double p0, p1, p2, p3;
  CatmullRomCell(std::span<const double> samples, int j) {
    const int n = static_cast<int>(samples.size());
    p0 = samples[(j + n - 1) % n];
    p1 = samples[j];
    p2 = samples[(j + 1) % n];
    p3 = samples[(j + 2) % n];
  }
  // The curve at w ∈ [0,1) in the cell, in Hermite form (radius_at).
  double at(double w) const {
    const HermiteBasis b(w);
    return b.h00 * p1 + b.h10 * 0.5 * (p2 - p0) + b.h01 * p2 + b.h11 * 0.5 * (p3 - p1);
  }
  // The same cubic as coefficients c0 + w·c1 + w²·c2 + w³·c3 (the fast path evaluates it by
  // Horner). The same polynomial as at(), rounded differently: each form is kept for the bits of
  // the outputs made with it.
  std::array<double, 4> cubic() const {
    return {p1, 0.5 * (p2 - p0), p0 - 2.5 * p1 + 2 * p2 - 0.5 * p3, 0.5 * (p3 - p0) + 1.5 * (p1 - p2)};
  }
  double min_sample() const { return std::min(std::min(std::min(p1, p0), p2), p3); }
};

// Spherical linear interpolation between two rotations along the shorter arc, exactly as Eigen's
// Quaternion::slerp computes it (same threshold for the nearly-equal case, same operations), with
// the work that depends only on the pair done once.
class Slerp {
 public:
  Slerp(const Quat& a, const Quat& b);
  // Bit for bit a.slerp(u, b) (not normalized).
  Quat at(double u) const;
  // The arc at u = q/S, q = 0..S (out.size() == S + 1, S ≥ 1; not normalized), with the sines
  // sin(q·θ/S) from the angle-addition recurrence sin((q+1)δ) = 2 cos δ·sin(qδ) − sin((q−1)δ):
  // four transcendentals for the whole arc, not two a point. The last bits differ from at(q/S).
  void at_steps(std::span<Quat> out) const;

 private:
  Eigen::Vector4d a_, b_;  // b_ negated when the pair's dot product is negative (shorter arc)
  bool linear_ = false;    // nearly equal: weights 1 − u and u
  double theta_ = 0, sin_theta_ = 0;
};

// Where a parameter falls: span s (between sections s and s+1) and the local coordinate u ∈ [0,1].
// t outside [0, L] is clamped.
struct SpanCoord {
  int span = 0;
  double u = 0;
};
SpanCoord locate_span(const SweepShape& shape, double t);

// Where an angle falls among the radial samples: samples j and j+1 (mod n), local w ∈ [0,1).
struct AngleCoord {
  int j = 0;
  double w = 0;
};
AngleCoord locate_angle(int radial_count, double theta);

Vec3 center_at(const SweepShape& shape, double t);                    // C(t)
Quat rotation_at(const SweepShape& shape, double t);                  // R(t)
Frame frame_at(const SweepShape& shape, double t);                    // [R(t) | C(t)]
double radius_at(const SweepShape& shape, double theta, double t);    // r(θ,t)
Vec3 surface_point(const SweepShape& shape, double theta, double t);  // S(θ,t)

// The parameters of `stations_per_span` evenly spaced stations a span, t_s + (t_{s+1} − t_s)·q/S,
// and the tip's: (K − 1)·S + 1 of them (the locator's and the fast deformation path's stations).
std::vector<double> station_parameters(const SweepShape& shape, int stations_per_span);
void station_parameters(const SweepShape& shape, int stations_per_span, std::vector<double>& out);  // into `out`

// r(θ_j, t) for every sample angle θ_j at once (out.size() == n), as radius_at gives them but
// without the floor: the fast deformation path tabulates these at its stations.
void radii_at_samples(const SweepShape& shape, double t, std::span<double> out);

// Checks the invariants evaluation relies on; returns an empty string when they hold, otherwise
// what is wrong (used by loaders to turn bad data into messages rather than asserts).
std::string check_shape(const SweepShape& shape);

}  // namespace sweep
