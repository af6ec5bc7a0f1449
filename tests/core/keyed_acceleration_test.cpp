// The keyed bend's accelerations (ElasticSweep::set_keyed_acceleration) load a part as the body's
// own acceleration does: the same acceleration given either way moves every spring alike, in the
// paper's springs and in material mode; a bend keyed on the tip alone moves the paper's tip spring
// alone, as the driven oscillator's closed form says.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "beam_tubes.h"
#include "sample_sweeps.h"
#include "sweep/core/elastic_sweep.h"

namespace sweep::test {
namespace {

// Largest difference of the section offsets and rotation vectors of two sweeps, and the largest of
// the first's.
void compare(const ElasticSweep& a, const ElasticSweep& b, double& difference, double& size) {
  difference = size = 0;
  for (int i = 1; i < a.rest().section_count(); ++i) {
    difference = std::max({difference, (a.section_offset(i) - b.section_offset(i)).norm(),
                           (a.rotation_vector(i) - b.rotation_vector(i)).norm()});
    size = std::max({size, a.section_offset(i).norm(), a.rotation_vector(i).norm()});
  }
}

void expect_as_the_body(const SweepDef& def) {
  ElasticSweep by_body(def), by_keys(def);
  ElasticSweep::BodyMotion motion;
  motion.acceleration = Vec3(3, 0, -1);
  by_body.set_body_motion(motion);
  const std::vector<Vec3> keyed(static_cast<std::size_t>(def.rest.section_count()), motion.acceleration);
  by_keys.set_keyed_acceleration(keyed);
  for (int n = 0; n < 40; ++n) {
    by_body.step(1.0 / 240);
    by_keys.step(1.0 / 240);
  }
  double difference = 0, size = 0;
  compare(by_body, by_keys, difference, size);
  EXPECT_GT(size, 1e-4);  // it moved
  EXPECT_LT(difference, 1e-12 * size);
}

TEST(KeyedAcceleration, LoadsThePaperSpringsAsTheBodysAccelerationDoes) {
  expect_as_the_body(sweep_def(straight_shape(6, 8)));
}

TEST(KeyedAcceleration, LoadsAMaterialChainAsTheBodysAccelerationDoes) {
  expect_as_the_body(beam::tube(beam::kRadius, beam::kRadius, 0.05, 8));
}

// The paper's springs: the tip's keyed acceleration a sin ωt loads the tip's positional spring
// alone, x'' + 2ζω0 x' + ω0² x = −a sin ωt from rest, whose solution is computed here in closed form
// (steady response plus the free decay that starts it at rest).
TEST(KeyedAcceleration, ATipKeyedToSwayDrivesItsSpringAsTheClosedFormSays) {
  const SweepDef def = sweep_def(straight_shape(4, 8));
  const int tip = def.rest.section_count() - 1;
  const SpringSettings k = def.springs[tip].positional;
  const double w0 = 2 * std::numbers::pi * k.frequency_hz, zeta = k.damping_ratio, w = 5.0, a = 2.0;
  ASSERT_LT(zeta, 1.0);
  ElasticSweep sweep(def);
  std::vector<Vec3> keyed(static_cast<std::size_t>(tip + 1), Vec3::Zero());
  const double h = 1.0 / 480;
  // Steady: x_s = Im(X e^{iωt}), X = −a / (ω0² − ω² + 2iζω0ω); free: e^{−ζω0 t}(c1 cos ωd t + c2 sin ωd t).
  const double den = std::pow(w0 * w0 - w * w, 2) + std::pow(2 * zeta * w0 * w, 2);
  const double re = -a * (w0 * w0 - w * w) / den, im = a * 2 * zeta * w0 * w / den;  // X = re + i·im
  // x_s = re sin ωt + im cos ωt; x(0) = 0 and x'(0) = 0 fix c1, c2.
  const double wd = w0 * std::sqrt(1 - zeta * zeta), c1 = -im, c2 = (zeta * w0 * c1 - re * w) / wd;
  double worst = 0, largest = 0;
  for (int n = 0; n < 480; ++n) {
    const double mid = (n + 0.5) * h;  // the simulator's rule: the load held at the step's middle
    keyed[tip] = Vec3(a * std::sin(w * mid), 0, 0);
    sweep.set_keyed_acceleration(keyed);
    sweep.step(h);
    const double t = (n + 1) * h;
    const double x = re * std::sin(w * t) + im * std::cos(w * t) +
                     std::exp(-zeta * w0 * t) * (c1 * std::cos(wd * t) + c2 * std::sin(wd * t));
    worst = std::max(worst, std::abs(sweep.section_offset(tip).x() - x));
    largest = std::max(largest, std::abs(x));
    for (int i = 1; i < tip; ++i) EXPECT_EQ(sweep.section_offset(i), Vec3::Zero());
  }
  EXPECT_GT(largest, 0.01);
  // Midpoint loads over 1/480 s: second order, (ωh)² ≈ 1e-4 of the motion.
  EXPECT_LT(worst, 1e-3 * largest);
}

}  // namespace
}  // namespace sweep::test
