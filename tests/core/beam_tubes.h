#pragma once
// Generated straight tubes in material mode and what beam theory says about them: the
// cases of tests/core/beam_test.cpp (at K = 32) and of BENCHMARKS.md's beam table (K = 8 … 64).
// A tube is 3.1 m long (31 mesh units at 0.1 m per unit) whatever its section count, 5 cm in radius,
// of a stiff rubber (E = 10 MPa, ν = 0.45, ρ = 1100 kg/m³).
#include <cmath>
#include <numbers>
#include <vector>

#include "sample_sweeps.h"
#include "sweep/core/elastic_sweep.h"
#include "sweep/core/section_properties.h"
#include "test_constants.h"

namespace sweep::test::beam {

using ::sweep::test::kPi;
constexpr int kSections = 32, kRadii = 32;
constexpr double kRadius = 0.5;      // mesh units
constexpr double kScale = 0.1;       // metres per unit
constexpr double kLengthUnits = 31;  // mesh units
constexpr double kYoung = 1e7, kDensity = 1100;

inline Material rubber(double damping_ratio) {
  Material m;
  m.youngs_modulus = kYoung;
  m.poisson_ratio = 0.45;
  m.density = kDensity;
  m.metres_per_unit = kScale;
  m.damping_ratio = damping_ratio;
  return m;
}

// A straight tube along z of `sections` sections, evenly spaced over kLengthUnits, whose sections
// are the ellipse with semi-axes a (x) and b (y), in mesh units; a == b is the circular tube.
inline SweepDef tube(double a, double b, double damping_ratio, int sections = kSections) {
  SweepShape shape = straight_shape(sections, kRadii, kRadius);
  const double spacing = kLengthUnits / (sections - 1);
  for (int i = 0; i < sections; ++i) {
    shape.t[i] = spacing * i;
    shape.frames[i].center = Vec3(0, 0, spacing * i);
    for (int j = 0; j < kRadii; ++j) {
      const double th = 2 * kPi * j / kRadii;
      shape.radii[static_cast<std::size_t>(i) * kRadii + j] = a * b / std::hypot(b * std::cos(th), a * std::sin(th));
    }
  }
  SweepDef def = sweep_def(shape);
  def.material = rubber(damping_ratio);
  def.section_materials.assign(sections, *def.material);
  return def;
}

// The tube of another stiffness: every section's material and the sweep's.
inline void set_youngs_modulus(SweepDef& def, double youngs_modulus) {
  for (Material& m : def.section_materials) m.youngs_modulus = youngs_modulus;
  def.material->youngs_modulus = youngs_modulus;
}

inline SectionProperties props_of(const SweepDef& def) {
  std::vector<double> r(kRadii);
  for (int j = 0; j < kRadii; ++j) r[j] = kScale * def.rest.radius_sample(1, j);
  return section_properties(r);
}

inline double length_m(const SweepDef& def) {
  return kScale * def.rest.length();
}

// Frequencies (rad/s) of the modes that turn about `axis` (0, 1: bend; 2: twist). A round tube
// bends alike about x and y, so its bending frequencies come in pairs whose eigenvectors may be any
// mix of the two: modes of one frequency are taken as a group, and the group gives `axis` as many
// modes as its share on that axis adds up to.
inline std::vector<double> frequencies_about(const ChainModel& m, int axis) {
  std::vector<double> out;
  const Eigen::Index count = m.modes.cols();
  for (Eigen::Index first = 0; first < count;) {
    const double w = std::sqrt(std::max(m.omega2[first], 0.0));
    double share = 0;
    Eigen::Index c = first;
    for (; c < count && std::abs(std::sqrt(std::max(m.omega2[c], 0.0)) - w) <= 1e-6 * w; ++c) {
      double on = 0, all = 0;
      for (Eigen::Index r = 0; r < m.modes.rows(); ++r) {
        all += m.modes(r, c) * m.modes(r, c);
        if (r % 3 == axis) on += m.modes(r, c) * m.modes(r, c);
      }
      share += on / all;
    }
    for (long n = std::lround(share); n > 0; --n) out.push_back(w);
    first = c;
  }
  return out;
}

// Euler–Bernoulli's clamped–free bending frequencies (rad/s), modes 1–3.
inline double euler_bernoulli(int mode, const SectionProperties& p, double length) {
  const double beta_l[3] = {1.8751, 4.6941, 7.8548};
  return beta_l[mode] * beta_l[mode] * std::sqrt(kYoung * p.i_xx / (kDensity * p.area * std::pow(length, 4)));
}

// The first twist frequency of a clamped–free shaft (rad/s): π/2 · √(GJ / ρJ_p) / L.
inline double first_twist(const SweepDef& def, const SectionProperties& p) {
  return kPi / 2 * std::sqrt(def.material->shear() * p.torsion / (kDensity * p.polar)) / length_m(def);
}

// Settles the tube under a tip force (N, world) or its own weight under `gravity` (m/s², down -y);
// returns the tip's deflection along the force (or down), in metres. Critically damped modes:
// settled to e^-40 of the start.
inline double settled_tip_deflection(const SweepDef& def, const Vec3& force, double gravity) {
  ElasticSweep sweep(def);
  if (gravity != 0) sweep.set_gravity(Vec3(0, -gravity, 0), false);
  if (force != Vec3::Zero()) {
    ForceSpec f;
    f.t = def.rest.length();
    f.theta = std::atan2(force.y(), force.x());  // the arm along the force: no twist
    f.vector = force;
    f.components = kRotational;
    f.target = RotationTarget::chain;
    f.moment = MomentModel::physical;
    sweep.add_force(f);
  }
  const double w1 = std::sqrt(sweep.chain()->omega2[0]);
  for (int s = 0; s < 400; ++s) sweep.step(0.1 / w1);
  const Vec3 d = sweep.deformed().frames.back().center - def.rest.frames.back().center;
  return kScale * d.dot(force != Vec3::Zero() ? force.normalized() : Vec3(0, -1, 0));
}

}  // namespace sweep::test::beam
