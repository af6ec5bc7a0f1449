// Material mode against beam theory: generated straight tubes, K = 32 sections, a
// chain of hinges with masses and stiffnesses from the material and each section's polygon.
// (BENCHMARKS.md's table gives the same measures at K = 8, 16, 32 and 64.)
#include <gtest/gtest.h>

#include <cstdio>
#include <numbers>

#include "beam_tubes.h"
#include "sweep/core/elastic_sweep.h"
#include "sweep/core/section_properties.h"

namespace sweep {
namespace {

using namespace test::beam;  // the tubes and their measurements, shared with tools/bench/bench_beam.cpp

TEST(SectionProperties, CircleAndEllipseMatchTheirFormulas) {
  const double r = 0.3;
  const SectionProperties c = section_properties(std::vector<double>(2048, r));
  EXPECT_NEAR(c.area / (kPi * r * r), 1.0, 1e-5);
  EXPECT_NEAR(c.i_xx / (kPi * std::pow(r, 4) / 4), 1.0, 1e-5);
  EXPECT_NEAR(c.i_yy / c.i_xx, 1.0, 1e-12);
  EXPECT_NEAR(c.torsion / c.polar, 1.0, 1e-12);
  EXPECT_NEAR(c.i_xy, 0.0, 1e-15);
  const double a = 0.4, b = 0.2;
  std::vector<double> e(2048);
  for (std::size_t j = 0; j < e.size(); ++j) {
    const double th = 2 * kPi * j / e.size();
    e[j] = a * b / std::hypot(b * std::cos(th), a * std::sin(th));
  }
  const SectionProperties p = section_properties(e);
  EXPECT_NEAR(p.i_xx / (kPi * a * b * b * b / 4), 1.0, 1e-5);
  EXPECT_NEAR(p.i_yy / (kPi * a * a * a * b / 4), 1.0, 1e-5);
  // Saint-Venant's A⁴/(4π² I_p) against the ellipse's exact π a³ b³ / (a² + b²): within 2%.
  EXPECT_NEAR(p.torsion / (kPi * std::pow(a * b, 3) / (a * a + b * b)), 1.0, 0.02);
}

TEST(BeamTheory, FirstThreeBendingFrequenciesWithinTwoPercentOfEulerBernoulli) {
  const SweepDef def = tube(kRadius, kRadius, 0.0);
  const ElasticSweep sweep(def);
  const SectionProperties p = props_of(def);
  const double l = length_m(def);
  const std::vector<double> w = frequencies_about(*sweep.chain(), 0);
  ASSERT_GE(w.size(), 3u);
  for (int n = 0; n < 3; ++n) {
    const double expected = euler_bernoulli(n, p, l);
    std::printf("bending mode %d: %.5g rad/s, Euler-Bernoulli %.5g (%+.3f%%)\n", n + 1, w[n], expected,
                100 * (w[n] / expected - 1));
    EXPECT_NEAR(w[n] / expected, 1.0, 0.02) << "mode " << n + 1;
  }
}

TEST(BeamTheory, FirstTwistFrequencyWithinTwoPercent) {
  const SweepDef def = tube(kRadius, kRadius, 0.0);
  const ElasticSweep sweep(def);
  const SectionProperties p = props_of(def);
  const std::vector<double> w = frequencies_about(*sweep.chain(), 2);
  ASSERT_GE(w.size(), 1u);
  const double expected = first_twist(def, p);
  std::printf("twist mode 1: %.5g rad/s, expected %.5g (%+.3f%%)\n", w[0], expected, 100 * (w[0] / expected - 1));
  EXPECT_NEAR(w[0] / expected, 1.0, 0.02);
}

TEST(BeamTheory, StaticTipLoadWithinOnePercentOfFL3Over3EI) {
  const SweepDef def = tube(kRadius, kRadius, 1.0);
  const SectionProperties p = props_of(def);
  const double l = length_m(def), force = 0.01;  // N: a deflection of ~1e-4 of the length
  const double expected = force * l * l * l / (3 * kYoung * p.i_xx);
  const double got = settled_tip_deflection(def, Vec3(0, force, 0), 0);
  std::printf("tip load: %.6g m, FL^3/3EI %.6g m (%+.3f%%)\n", got, expected, 100 * (got / expected - 1));
  EXPECT_LT(expected, 1e-3 * l);
  EXPECT_NEAR(got / expected, 1.0, 0.01);
}

TEST(BeamTheory, OwnWeightWithinOnePercentOfWL4Over8EI) {
  const SweepDef def = tube(kRadius, kRadius, 1.0);
  const SectionProperties p = props_of(def);
  const double l = length_m(def), g = 0.01;  // m/s²: small deflection
  const double w = kDensity * p.area * g;    // N/m
  const double expected = w * std::pow(l, 4) / (8 * kYoung * p.i_xx);
  const double got = settled_tip_deflection(def, Vec3::Zero(), g);
  std::printf("own weight: %.6g m, wL^4/8EI %.6g m (%+.3f%%)\n", got, expected, 100 * (got / expected - 1));
  EXPECT_NEAR(got / expected, 1.0, 0.01);
}

TEST(BeamTheory, EllipticalSectionBendsMoreEasilyAboutItsShortAxisByTheRatioOfItsMoments) {
  const SweepDef def = tube(0.6, 0.3, 1.0);  // wide in x
  const SectionProperties p = props_of(def);
  const double across = settled_tip_deflection(def, Vec3(0.01, 0, 0), 0);  // bends about y: I_yy
  const double down = settled_tip_deflection(def, Vec3(0, 0.01, 0), 0);    // bends about x: I_xx
  std::printf("ellipse: deflection ratio %.5g, I_yy/I_xx %.5g\n", down / across, p.i_yy / p.i_xx);
  EXPECT_NEAR((down / across) / (p.i_yy / p.i_xx), 1.0, 0.01);
  // (The 32-gon's ratio, 3.91, is not the ellipse's (a/b)² = 4: the polygon's own moments are the
  // model's; SectionProperties.CircleAndEllipseMatchTheirFormulas checks them converge to 4.)
  EXPECT_GT(p.i_yy / p.i_xx, 3.8);
}

// Exactly: with the rest-pose modes and with the exact chain (whose pre-load is its own gravity
// torques at rest, so that they cancel to the last bit; the split's differed by 2e-16).
TEST(BeamTheory, PreloadedGravityLeavesTheRestPoseStill) {
  for (const bool exact : {false, true}) {
    const SweepDef def = tube(kRadius, kRadius, 0.05);
    ElasticSweep sweep(def);
    sweep.set_exact_chain(exact);
    sweep.set_gravity(Vec3(0, -9.81, 0));  // pre-loaded: as modelled
    for (int s = 0; s < 100; ++s) sweep.step(1.0 / 480);
    EXPECT_TRUE(sweep.exact_chain() == exact);
    EXPECT_EQ(sweep.max_displacement(), 0.0) << (exact ? "exact chain" : "rest-pose modes");
  }
}

// The same part modelled at ten times the size in mesh units, with its scale set to match, is the
// same object: under the same push it moves the same in metres — bends, shifts and bulges alike.
TEST(MaterialMode, AMeshTenTimesLargerWithItsScaleMovesTheSameInMetres) {
  std::vector<double> motion[2];
  for (int big = 0; big < 2; ++big) {
    const double size = big ? 10.0 : 1.0;
    SweepShape shape = test::straight_shape(12, 16, kRadius * size);
    for (int i = 0; i < 12; ++i) {
      shape.t[i] *= size;
      shape.frames[i].center *= size;
      for (int j = 0; j < 16; ++j) shape.radii[static_cast<std::size_t>(i) * 16 + j] *= 1.0 + 0.2 * std::sin(j);
    }
    SweepDef def = test::sweep_def(shape);
    def.material = rubber(0.05);
    def.material->metres_per_unit = kScale / size;
    def.section_materials.assign(12, *def.material);
    ElasticSweep sweep(def);
    ForceSpec f;
    f.t = 7.3 * size;
    f.theta = 0.6;
    f.vector = Vec3(0.02, -0.05, 0.01);  // N
    f.components = kPositional | kRotational | kRadial;
    f.target = RotationTarget::chain;
    f.moment = MomentModel::physical;
    sweep.add_force(f);
    for (int s = 0; s < 200; ++s) {
      sweep.step(1.0 / 480);
      const double to_metres = def.material->metres_per_unit;
      for (int i = 0; i < 12; ++i) {
        const Frame& d = sweep.deformed().frames[i];
        for (int c = 0; c < 3; ++c) motion[big].push_back(to_metres * (d.center[c] - def.rest.frames[i].center[c]));
        motion[big].push_back(d.rotation.angularDistance(def.rest.frames[i].rotation));
        for (int j = 0; j < 16; ++j) motion[big].push_back(to_metres * sweep.radial_offset(i, j));
      }
    }
  }
  double largest = 0, difference = 0;
  for (std::size_t m = 0; m < motion[0].size(); ++m) {
    largest = std::max(largest, std::abs(motion[0][m]));
    difference = std::max(difference, std::abs(motion[0][m] - motion[1][m]));
  }
  EXPECT_GT(largest, 1e-6);
  EXPECT_LE(difference, 1e-9 * largest);
}

// A radial handle's spring is the wedge of flesh under it: ω = √(2E/ρ) / r, whatever the span.
TEST(MaterialMode, RadialHandlesRingAtTheirWedgesFrequency) {
  const SweepDef def = tube(kRadius, kRadius, 0.0);
  ElasticSweep sweep(def);
  sweep.set_radial_offset(9, 3, 1e-4);
  const double r = kScale * kRadius;
  const double omega = std::sqrt(2 * kYoung / kDensity) / r;
  const double period = 2 * std::numbers::pi / omega;
  // Undamped: after a quarter period it passes through rest, after half it is at the other side.
  sweep.step(period / 4);
  EXPECT_NEAR(sweep.radial_offset(9, 3), 0.0, 1e-12);
  sweep.step(period / 4);
  EXPECT_NEAR(sweep.radial_offset(9, 3), -1e-4, 1e-12);
}

TEST(Wind, ASteadyWindBendsTheTubeByQL4Over8EI) {
  // A steady cross wind U loads each span with the drag ½ ρ C_d d U² per unit length, uniform
  // along a round tube: the tip deflects by q L⁴ / 8EI (small deflection), like its own weight.
  const SweepDef def = tube(kRadius, kRadius, 1.0);
  const SectionProperties p = props_of(def);
  const double l = length_m(def), u = 0.2, half_rho_cd = 0.5 * 1.225 * 1.2;
  const double diameter = 2 * kScale * kRadius;
  // The polygon's mean radius is the circle's; its area (and I) is the 32-gon's.
  const double q = half_rho_cd * diameter * u * u;
  const double expected = q * std::pow(l, 4) / (8 * kYoung * p.i_xx);
  ElasticSweep sweep(def);
  ElasticSweep::BodyMotion air;
  air.wind = Vec3(u, 0, 0);
  air.drag = half_rho_cd;
  sweep.set_body_motion(air);
  const double w1 = std::sqrt(sweep.chain()->omega2[0]);
  for (int s = 0; s < 400; ++s) sweep.step(0.1 / w1);
  const double got = kScale * (sweep.deformed().frames.back().center.x() - def.rest.frames.back().center.x());
  std::printf("steady wind: %.6g m, qL^4/8EI %.6g m (%+.3f%%)\n", got, expected, 100 * (got / expected - 1));
  EXPECT_LT(expected, 1e-3 * l);
  EXPECT_NEAR(got / expected, 1.0, 0.01);
}

TEST(Wind, TheAirDampsAPartSwingingThroughIt) {
  // Still air (a wind of 0): the drag on the moving part takes energy out, never puts it in.
  ElasticSweep still(tube(kRadius, kRadius, 0.0)), in_air(tube(kRadius, kRadius, 0.0));
  ElasticSweep::BodyMotion air;
  air.drag = 0.5 * 1.225 * 1.2;
  in_air.set_body_motion(air);
  for (ElasticSweep* s : {&still, &in_air}) s->set_section_pose(20, Vec3::Zero(), Vec3(0.02, 0, 0));
  double e = in_air.energy();
  for (int s = 0; s < 2000; ++s) {
    still.step(1.0 / 480);
    in_air.step(1.0 / 480);
    ASSERT_LE(in_air.energy(), e * (1 + 1e-9));
    e = in_air.energy();
  }
  EXPECT_LT(in_air.energy(), (1 - 1e-3) * still.energy());  // (air is thin: 0.3% in 4 s here)
}

TEST(MaterialMode, AnImpulseGivesOnlyItsOwnKickNotTheWeights) {
  // An impulse is N·s at one instant; the weight is a force over time. (The impulse once took the
  // loads of the whole split with it: under unloaded gravity, a second of the part's weight.)
  ElasticSweep sweep(tube(kRadius, kRadius, 0.05));
  sweep.set_gravity(Vec3(0, -9.81, 0), false);
  ForceSpec nothing;
  nothing.t = 20;
  nothing.vector = Vec3::Zero();
  sweep.apply_impulse(nothing);
  EXPECT_EQ(sweep.max_speed(), 0.0);
}

TEST(MaterialMode, FreeMotionNeverGainsEnergy) {
  for (double zeta : {0.0, 0.05, 2.0}) {
    ElasticSweep sweep(tube(kRadius, kRadius, zeta));
    for (int i = 1; i < kSections; ++i) sweep.set_section_pose(i, Vec3(0.001, 0, 0.0005), Vec3(0.01, -0.02, 0.005));
    double e = sweep.energy();
    ASSERT_GT(e, 0.0);
    for (int s = 0; s < 2000; ++s) {
      sweep.step(s % 2 ? 1e-3 : 0.37);
      ASSERT_TRUE(sweep.is_finite());
      ASSERT_LE(sweep.energy(), e * (1 + 1e-9)) << "zeta " << zeta << ", step " << s;
      e = sweep.energy();
    }
  }
}

}  // namespace
}  // namespace sweep
