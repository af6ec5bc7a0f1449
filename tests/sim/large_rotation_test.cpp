// Large rotations of a material part, through the simulator's own path (ElasticSweep in material
// mode, the geometrically exact chain): a 2 m tube of K = 32 sections, 5 cm in radius, ρ = 1100
// kg/m³ (its own weight β = q L³ / EI = 1.38e8 Pa / E: 138 at E = 1e6). Measured against what
// physics allows, never against the integrator's own bookkeeping: kinetic energies from the
// section centres' motion (central differences of the poses), gravity's work from their heights.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/beam_tubes.h"
#include "sweep/core/elastic_sweep.h"

namespace sweep::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.81;
constexpr double kLengthUnits = 20;  // 2 m at the tubes' 0.1 m per unit

// The 2 m tube along z, straight or bent at rest into a quarter circle in the x–z plane.
SweepDef two_metre_tube(double youngs, double zeta, bool bent = false) {
  SweepDef def = test::beam::tube(test::beam::kRadius, test::beam::kRadius, zeta);
  test::beam::set_youngs_modulus(def, youngs);
  const int k = def.rest.section_count();
  const double radius = kLengthUnits / (kPi / 2);
  for (int i = 0; i < k; ++i) {
    const double s = kLengthUnits * i / (k - 1);
    def.rest.t[i] = s;
    if (bent) {
      const double a = s / radius;
      def.rest.frames[i].center = Vec3(radius * (1 - std::cos(a)), 0, radius * std::sin(a));
      def.rest.frames[i].rotation = Quat(Eigen::AngleAxisd(a, Vec3::UnitY()));
    } else {
      def.rest.frames[i].center = Vec3(0, 0, s);
    }
  }
  def.name = "tube";
  return def;
}

double length_m(const ElasticSweep& s) { return s.chain()->metres_per_unit * s.rest().length(); }

double total_mass(const ElasticSweep& s) {
  double m = 0;
  for (double x : s.chain()->node_mass) m += x;
  return m;
}

// Released level under gravity (not pre-loaded): the kinetic energy of the sections is at most
// what gravity's work gave them, and by symmetry the tube never leaves its vertical plane. Both
// measured on the joints' pose (exact_chain_state: the sections where the joints put them; the
// stiff stretch and shear springs ride on it as independent springs and are not part of this).
// The rest-pose modal step (set_exact_chain(false)), its joints measured the same way, breaks
// both: run alongside, it shows the test can fail.
TEST(LargeRotation, ASoftTubeReleasedLevelNeverOutrunsGravitysWorkAndStaysInItsPlane) {
  for (const bool exact : {true, false}) {
    ElasticSweep tube(two_metre_tube(1e6, 0.05));  // β = 138, the default damping
    tube.set_exact_chain(exact);
    tube.set_gravity(Vec3(0, -kG, 0), false);
    const double h = 1.0 / 480, l = length_m(tube), mgl = total_mass(tube) * kG * l;
    const std::vector<double>& mass = tube.chain()->node_mass;
    const std::vector<Vec3> start = tube.exact_chain_state()->centres();
    std::vector<Vec3> before = start, now = start;
    double worst = -1, off_plane = 0, lowest = 0;
    for (int s = 0; s < 480; ++s) {
      tube.step(h);
      const std::vector<Vec3> after = tube.exact_chain_state()->centres();
      if (s > 0) {
        double work = 0, kinetic = 0;
        for (std::size_t i = 1; i < now.size(); ++i) {
          work += mass[i] * kG * (start[i].y() - now[i].y());
          kinetic += 0.5 * mass[i] * ((after[i] - before[i]) / (2 * h)).squaredNorm();
        }
        worst = std::max(worst, (kinetic - work) / mgl);
      }
      for (const Vec3& c : after) off_plane = std::max(off_plane, std::abs(c.x()) / l);
      lowest = std::min(lowest, after.back().y() / l);
      before = now;
      now = after;
    }
    std::printf("released soft tube (%s): tip down to %.3f L, largest (KE - W)/(m g L) %.3g, off its plane %.3g L\n",
                exact ? "exact chain" : "rest-pose modes", lowest, worst, off_plane);
    if (exact) {
      EXPECT_LE(worst, 1e-4);  // the differences' own error is O(h²): far below
      EXPECT_LE(off_plane, 1e-9);
      EXPECT_LT(lowest, -0.5);  // it did fall
    } else {
      EXPECT_GT(worst, 0.1);  // the rest-pose modes gain energy
    }
  }
}

}  // namespace
}  // namespace sweep::sim
