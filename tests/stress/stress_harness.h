#pragma once
// The stress harness, shared by the test suite (tests/stress, short runs) and the
// benchmark (tools/bench/sweep-bench-stress, long runs): random forces (seeded) on one sweep with
// extreme but valid springs, force scales and time steps, checking invariants after every step:
//  - every spring coordinate finite, every deformed frame, centre and radius finite;
//  - radii positive (a radial handle cannot invert its section);
//  - frames orthonormal: max |RᵀR − I| < kOrthonormalTolerance;
//  - after the forces stop, with damping > 0: the energy never grows (exact integrator), and when
//    the springs' own decay predicts it, the sweep returns to rest.
// Nothing here prints; the result says what held, and the first thing that did not.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <random>
#include <string>

#include "sweep/core/elastic_sweep.h"

namespace sweep::stress {

inline constexpr double kOrthonormalTolerance = 1e-6;
// Energy may grow by this much, relative, in a force-free step (rounding of the closed form).
inline constexpr double kEnergyGrowthTolerance = 1e-9;
// Below this energy (J) the motion has decayed so far (displacements ~1e-125 and less) that ½kx²
// and ½mv² approach the subnormal numbers, where few significant bits are left and relative growth
// is rounding, not motion (the 100,000-step benchmark run at dt = 1/60 s met it after 200 s of free
// decay: a "6.7% growth" of an energy of ~1e-318 J).
inline constexpr double kEnergyFloor = 1e-250;

struct StressParams {
  double mass = 1;          // kg (kg·m² rotational): every spring kind of every section
  double frequency_hz = 1;  // natural frequency, Hz
  double damping_ratio = 0.3;
  double c_rot = 1;      // the sweep's rotational force scale C_rot
  double c_rad = 1;      // the sweep's radial force scale C_rad
  double dt = 1.0 / 60;  // s
  double force = 10;     // N: largest force magnitude drawn
  Integrator integrator = Integrator::exact;
  // Material mode: when set, the sweep's springs and masses follow from it (the spring
  // members above but dt, force and the force scales are then unused; damping_ratio is the
  // material's).
  std::optional<Material> material;
};

struct StressResult {
  long long steps = 0;                  // steps run (fewer than asked when an invariant failed)
  std::string failure;                  // empty when every invariant held at every step
  double max_orthonormality_error = 0;  // largest max|RᵀR − I| seen
  double min_radius_ratio = 1e300;      // smallest deformed radius / its rest radius
  double max_energy_growth = 0;         // largest relative energy growth of a force-free step
  double peak_displacement = 0;         // largest spring displacement seen
  double final_displacement = 0;        // spring displacement after the last step
  bool rest_expected = false;           // the decay predicts a return to rest within the run
  bool returned_to_rest = false;
  bool ok() const { return failure.empty(); }
};

inline SweepDef with_params(SweepDef def, const StressParams& p) {
  const SpringSettings s{p.mass, p.frequency_hz, p.damping_ratio};
  def.default_springs = {s, s, s, s};
  for (SectionSprings& sec : def.springs) sec = {s, s, s, s};
  def.rotational_scale = p.c_rot;
  def.radial_scale = p.c_rad;
  def.material = p.material;
  def.section_materials.assign(p.material ? def.rest.section_count() : 0, p.material.value_or(Material{}));
  return def;
}

// Largest |(RᵀR − I)_ab| of one frame.
inline double orthonormality_error(const Frame& f) {
  const Mat3 r = f.matrix();
  return (r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff();
}

// Checks the invariants of the current state; returns what is wrong, or "".
inline std::string check_state(const ElasticSweep& body, StressResult& res) {
  if (!body.is_finite()) return "a spring coordinate is not finite";
  const SweepShape& d = body.deformed();
  for (int i = 0; i < d.section_count(); ++i) {
    const Frame& f = d.frames[i];
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(f.center[c])) return "section " + std::to_string(i) + ": centre not finite";
    }
    for (int c = 0; c < 4; ++c) {
      if (!std::isfinite(f.rotation.coeffs()[c])) return "section " + std::to_string(i) + ": rotation not finite";
    }
    const double e = orthonormality_error(f);
    res.max_orthonormality_error = std::max(res.max_orthonormality_error, e);
    if (!(e < kOrthonormalTolerance)) return "section " + std::to_string(i) + ": frame not orthonormal";
  }
  for (std::size_t m = 0; m < d.radii.size(); ++m) {
    if (!std::isfinite(d.radii[m]) || !(d.radii[m] > 0))
      return "radius " + std::to_string(m) + " not finite and positive";
    res.min_radius_ratio = std::min(res.min_radius_ratio, d.radii[m] / body.rest().radii[m]);
  }
  return {};
}

// Decay rate of a damped oscillator, 1/s: ζω for ζ ≤ 1, ω(ζ − √(ζ² − 1)) above.
inline double decay_rate(double w, double z) {
  return z <= 1 ? z * w : w * (z - std::sqrt(z * z - 1));
}

// Slowest decay rate of the sweep's springs (of its modes, in material mode: the lowest frequency
// decays slowest at one damping ratio, under- or over-damped alike).
inline double slowest_decay_rate(const StressParams& p, const ElasticSweep& body) {
  if (!p.material) return decay_rate(2 * std::numbers::pi * p.frequency_hz, p.damping_ratio);
  const ChainModel& c = *body.chain();
  double w2 = c.omega2.minCoeff();
  const std::size_t root_entries[2] = {3, static_cast<std::size_t>(body.rest().radial_count)};
  int which = 0;
  for (const auto* bank : {&c.positional, &c.radial}) {
    // (section 0 is fixed: its entries never move)
    for (std::size_t m = root_entries[which]; m < bank->size(); ++m)
      w2 = std::min(w2, (*bank)[m].stiffness / (*bank)[m].mass);
    ++which;
  }
  return decay_rate(std::sqrt(std::max(w2, 0.0)), p.material->damping_ratio);
}

// Runs `steps` steps: the first `forced_steps` under random forces (a new random set every
// `change_every` steps, with an occasional impulse), the rest force-free.
inline StressResult run_stress(const SweepDef& base, const StressParams& p, std::uint64_t seed, long long steps,
                               long long forced_steps, long long change_every = 50) {
  StressResult res;
  ElasticSweep body(with_params(base, p));
  body.set_integrator(p.integrator);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0, 1);
  const double length = body.rest().length();
  const int k = body.rest().section_count();
  auto random_force = [&]() {
    ForceSpec f;
    f.t = length * uni(rng);
    f.theta = 2 * std::numbers::pi * uni(rng);
    const Vec3 dir = Vec3(uni(rng) - 0.5, uni(rng) - 0.5, uni(rng) - 0.5);
    const double mag = p.force * std::pow(10.0, -2 * uni(rng));
    f.vector = dir.norm() > 1e-9 ? Vec3(mag * dir.normalized()) : Vec3(mag, 0, 0);
    f.components = static_cast<std::uint8_t>(1 + rng() % 7);
    const int target = static_cast<int>(rng() % 3);
    f.target = target == 0 ? RotationTarget::nearest : target == 1 ? RotationTarget::chain : RotationTarget::section;
    f.target_section = 1 + static_cast<int>(rng() % (k - 1));
    f.moment = rng() % 2 ? MomentModel::scaled : MomentModel::physical;
    return f;
  };
  double energy = body.energy();
  for (long long s = 0; s < steps; ++s) {
    const bool forced = s < forced_steps;
    if (forced && s % change_every == 0) {
      body.clear_forces();
      const int count = 1 + static_cast<int>(rng() % 3);
      for (int c = 0; c < count; ++c) body.add_force(random_force());
      if (rng() % 4 == 0) body.apply_impulse(random_force());
    }
    if (s == forced_steps) body.clear_forces();
    body.step(p.dt);
    res.steps = s + 1;
    if (std::string why = check_state(body, res); !why.empty()) {
      res.failure = "step " + std::to_string(s + 1) + ": " + why;
      return res;
    }
    res.peak_displacement = std::max(res.peak_displacement, body.max_displacement());
    const double e = body.energy();
    if (!std::isfinite(e)) {
      res.failure = "step " + std::to_string(s + 1) + ": energy not finite";
      return res;
    }
    const double damping = p.material ? p.material->damping_ratio : p.damping_ratio;
    if (!forced && damping > 0 && p.integrator == Integrator::exact) {
      const double growth = energy > kEnergyFloor ? (e - energy) / energy : (e > kEnergyFloor ? 1.0 : 0.0);
      res.max_energy_growth = std::max(res.max_energy_growth, growth);
      if (growth > kEnergyGrowthTolerance) {
        res.failure = "step " + std::to_string(s + 1) + ": energy grew without force, by " + std::to_string(growth);
        return res;
      }
    }
    energy = e;
  }
  res.final_displacement = body.max_displacement();
  // Return to rest: expected when the slowest spring mode has decayed by e^-30 over the free part.
  const double free_time = static_cast<double>(steps - forced_steps) * p.dt;
  res.rest_expected = p.integrator == Integrator::exact && slowest_decay_rate(p, body) * free_time > 30;
  res.returned_to_rest = res.final_displacement <= 1e-9 * std::max(res.peak_displacement, 1e-300) + 1e-300;
  if (res.rest_expected && !res.returned_to_rest) {
    res.failure = "did not return to rest: displacement " + std::to_string(res.final_displacement) + " after peak " +
                  std::to_string(res.peak_displacement);
  }
  return res;
}

}  // namespace sweep::stress
