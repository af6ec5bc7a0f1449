#pragma once
// The sweep surface of DESIGN.md §2.1, S(θ,t) = C(t) + R(t)·(r(θ,t) cos θ, r(θ,t) sin θ, 0),
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
#include <span>
#include <vector>

#include "core/frame.h"

namespace sweep {

// Lowest radius the interpolant may return, as a fraction of the smallest sample it interpolates.
inline constexpr double kMinRadiusFraction = 0.05;

struct SweepShape {
  std::vector<double> t;        // K section parameters (arc length), t[0] = 0, strictly increasing
  std::vector<Frame> frames;    // K section frames in world space
  int radial_count = 0;         // n radius samples per section, at θ_j = 2πj/n
  std::vector<double> radii;    // K*n samples; section i's sample j at radii[i*n + j]

  int section_count() const { return static_cast<int>(t.size()); }
  double length() const { return t.back(); }
  double radius_sample(int i, int j) const { return radii[static_cast<std::size_t>(i) * radial_count + j]; }
  std::span<const double> section_radii(int i) const {
    return {radii.data() + static_cast<std::size_t>(i) * radial_count, static_cast<std::size_t>(radial_count)};
  }
  double sample_angle(int j) const;
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

Vec3 center_at(const SweepShape& shape, double t);       // C(t)
Quat rotation_at(const SweepShape& shape, double t);     // R(t)
Frame frame_at(const SweepShape& shape, double t);       // [R(t) | C(t)]
double radius_at(const SweepShape& shape, double theta, double t);  // r(θ,t)
Vec3 surface_point(const SweepShape& shape, double theta, double t);  // S(θ,t)

// r(θ_j, t) for every sample angle θ_j at once (out.size() == n), as radius_at gives them but
// without the floor: the fast deformation path tabulates these at its stations.
void radii_at_samples(const SweepShape& shape, double t, std::span<double> out);

// Checks the invariants evaluation relies on; returns an empty string when they hold, otherwise
// what is wrong (used by loaders to turn bad data into messages rather than asserts).
std::string check_shape(const SweepShape& shape);

}  // namespace sweep
