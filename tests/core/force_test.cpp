// Force split, on cases computed by hand.
#include "sweep/core/force.h"

#include <gtest/gtest.h>

#include <numbers>

#include "sample_sweeps.h"
#include "sweep/core/elastic_sweep.h"
#include "test_constants.h"

namespace sweep {
namespace {

using ::sweep::test::kPi;

TEST(RotationalPart, AxisIsACrossFAndMagnitudeIsCRotTimesF) {
  // Point 2 units along +x from the centre, force 3 N along +y: a × f = (2,0,0)×(0,3,0) = (0,0,6).
  const Vec3 tau = rotational_torque(Vec3(2, 0, 0), Vec3::Zero(), Vec3(0, 3, 0), 0.5, MomentModel::scaled);
  EXPECT_NEAR(tau.x(), 0, 1e-15);
  EXPECT_NEAR(tau.y(), 0, 1e-15);
  EXPECT_NEAR(tau.z(), 0.5 * 3, 1e-15);  // C_rot |f| about +z
  // The physical model is the moment itself.
  EXPECT_EQ(rotational_torque(Vec3(2, 0, 0), Vec3::Zero(), Vec3(0, 3, 0), 0.5, MomentModel::physical), Vec3(0, 0, 6));
  // Force along a: no rotational part.
  EXPECT_EQ(rotational_torque(Vec3(2, 0, 0), Vec3::Zero(), Vec3(-4, 0, 0), 0.5, MomentModel::scaled), Vec3::Zero());
}

TEST(RotationalPart, AxisForAnObliqueForce) {
  const Vec3 p(1, 1, 0), c(0, 0, 1), f(0, 0, 2);
  // a = (1,1,-1); a × f = (1·2 − (−1)·0, (−1)·0 − 1·2, 0) = (2, −2, 0).
  const Vec3 tau = rotational_torque(p, c, f, 1.0, MomentModel::scaled);
  const Vec3 expected = 2.0 * Vec3(1, -1, 0).normalized();
  EXPECT_LT((tau - expected).norm(), 1e-15);
}

TEST(RadialPart, PushInwardIsPositivePullOutwardNegativeTangentialZero) {
  // Plane z = 0 through o = 0; p at radius 2 on +x.
  const Vec3 p(2, 0, 0), o(0, 0, 0), n(0, 0, 1);
  EXPECT_NEAR(radial_force(p, o, n, Vec3(-3, 0, 0), 0.5), 1.5, 1e-15);  // inward push
  EXPECT_NEAR(radial_force(p, o, n, Vec3(4, 0, 0), 0.5), -2.0, 1e-15);  // outward pull
  EXPECT_NEAR(radial_force(p, o, n, Vec3(0, 7, 0), 0.5), 0.0, 1e-15);   // tangential
  EXPECT_NEAR(radial_force(p, o, n, Vec3(0, 0, 9), 0.5), 0.0, 1e-15);   // along the axis
  // Oblique: only the in-plane radial component counts: (−1, 2, 5) → 1·C_rad.
  EXPECT_NEAR(radial_force(p, o, n, Vec3(-1, 2, 5), 1.0), 1.0, 1e-15);
}

TEST(RadialPart, BilinearWeightsSumToOneAndSitOnAHandle) {
  for (double u : {0.0, 0.25, 0.5, 0.9, 1.0}) {
    for (double w : {0.0, 0.1, 0.5, 0.75}) {
      const auto b = bilinear_weights(u, w);
      EXPECT_NEAR(b[0] + b[1] + b[2] + b[3], 1.0, 1e-15);
      for (double x : b) EXPECT_GE(x, 0.0);
    }
  }
  // Each corner gets the area of the opposite sub-rectangle: at (u, w) = (0.25, 0.1),
  // corner (i, j) gets (1−u)(1−w) = 0.675.
  EXPECT_NEAR(bilinear_weights(0.25, 0.1)[0], 0.675, 1e-15);
  EXPECT_NEAR(bilinear_weights(0.25, 0.1)[3], 0.025, 1e-15);
  const auto on = bilinear_weights(0.0, 0.0);
  EXPECT_EQ(on[0], 1.0);
  EXPECT_EQ(on[1] + on[2] + on[3], 0.0);
}

// A straight tube along z with sections at t = 0..4 and n = 4 handles (θ = 0, π/2, π, 3π/2).
SweepShape tube() {
  return test::straight_shape(5, 4, 0.5);
}

TEST(Accumulate, RadialPushOnAHandleGoesToThatHandleOnly) {
  const SweepShape s = tube();
  SectionLoads loads;
  loads.resize(5, 4);
  ForceSpec f;
  f.components = kRadial;
  f.vector = Vec3(-2, 0, 0);  // at θ = 0 the outward normal is +x: a push inward
  accumulate_force(s, f, 2.0, 0.0, 1.0, 0.75, loads);
  for (std::size_t m = 0; m < loads.radial.size(); ++m) {
    EXPECT_DOUBLE_EQ(loads.radial[m], m == 2 * 4 + 0 ? -1.5 : 0.0) << "handle " << m;
  }
  for (const Vec3& t : loads.torque) EXPECT_EQ(t, Vec3::Zero());
}

TEST(Accumulate, RadialPullBetweenHandlesIsSharedBilinearly) {
  const SweepShape s = tube();
  SectionLoads loads;
  loads.resize(5, 4);
  ForceSpec f;
  f.components = kRadial;
  // At θ = π/8 (w = 0.25 between handles 0 and 1) and t = 2.5 (u = 0.5 between sections 2, 3).
  const double th = kPi / 8;
  f.vector = 2.0 * Vec3(std::cos(th), std::sin(th), 0);  // outward pull of 2 N
  accumulate_force(s, f, 2.5, th, 1.0, 1.0, loads);
  EXPECT_NEAR(loads.radial[2 * 4 + 0], 2.0 * 0.5 * 0.75, 1e-14);
  EXPECT_NEAR(loads.radial[2 * 4 + 1], 2.0 * 0.5 * 0.25, 1e-14);
  EXPECT_NEAR(loads.radial[3 * 4 + 0], 2.0 * 0.5 * 0.75, 1e-14);
  EXPECT_NEAR(loads.radial[3 * 4 + 1], 2.0 * 0.5 * 0.25, 1e-14);
  double total = 0;
  for (double x : loads.radial) total += x;
  EXPECT_NEAR(total, 2.0, 1e-14);
}

TEST(Accumulate, RootTakesNoLoadAndNearestSectionTakesTheTorque) {
  const SweepShape s = tube();
  SectionLoads loads;
  loads.resize(5, 4);
  ForceSpec f;
  f.components = kRotational | kRadial;
  f.vector = Vec3(0, 1, 0);  // tangential at θ = 0
  accumulate_force(s, f, 3.2, 0.0, 2.0, 1.0, loads);
  // Nearest section to t = 3.2 is 3; a = p − c_3 = (0.5, 0, 0.2); a × f = (−0.2, 0, 0.5).
  const Vec3 expected = 2.0 * 1.0 * Vec3(-0.2, 0, 0.5).normalized();
  for (int i = 0; i < 5; ++i) {
    EXPECT_LT((loads.torque[i] - (i == 3 ? expected : Vec3::Zero())).norm(), 1e-14) << "section " << i;
  }
  for (double x : loads.radial) EXPECT_NEAR(x, 0.0, 1e-15);  // tangential: no radial part

  // Near the root the nearest movable section is 1, never the fixed root.
  loads.clear();
  accumulate_force(s, f, 0.1, 0.0, 1.0, 1.0, loads);
  EXPECT_EQ(loads.torque[0], Vec3::Zero());
  EXPECT_NE(loads.torque[1], Vec3::Zero());
}

TEST(Accumulate, ChainLoadsEverySectionFromTheRootToThePoint) {
  const SweepShape s = tube();
  SectionLoads loads;
  loads.resize(5, 4);
  ForceSpec f;
  f.components = kRotational;
  f.target = RotationTarget::chain;
  f.moment = MomentModel::physical;
  f.vector = Vec3(1, 0, 0);
  accumulate_force(s, f, 3.5, kPi / 2, 1.0, 1.0, loads);  // p = (0, 0.5, 3.5)
  for (int i = 0; i < 5; ++i) {
    // Physical moment about c_i = (0,0,i): (p − c_i) × f = (0, 0.5, 3.5 − i) × (1,0,0) = (0, 3.5 − i, −0.5).
    const Vec3 expected = (i >= 1 && i <= 3) ? Vec3(0, 3.5 - i, -0.5) : Vec3::Zero();
    EXPECT_LT((loads.torque[i] - expected).norm(), 1e-14) << "section " << i;
  }
}

TEST(Accumulate, PositionalPartIsSharedByTheTwoSectionsAround) {
  const SweepShape s = tube();
  SectionLoads loads;
  loads.resize(5, 4);
  ForceSpec f;
  f.components = kPositional;
  f.vector = Vec3(0, 4, 0);
  accumulate_force(s, f, 2.25, 0.0, 1.0, 1.0, loads);
  EXPECT_LT((loads.force[2] - Vec3(0, 3, 0)).norm(), 1e-14);
  EXPECT_LT((loads.force[3] - Vec3(0, 1, 0)).norm(), 1e-14);
}

TEST(ElasticSweepForces, TipPushBendsAlongTheForceAndReleaseDecaysToRest) {
  SweepDef def = test::sweep_def(test::straight_shape(6, 8, 0.3));
  ElasticSweep sweep(def);
  ForceSpec f;
  f.t = 5.0;
  f.theta = 0.0;
  f.vector = Vec3(0, 2, 0);  // sideways at the tip
  f.target = RotationTarget::chain;
  const ForceId id = sweep.add_force(f);
  for (int s = 0; s < 200; ++s) sweep.step(0.01);
  EXPECT_GT(sweep.deformed().frames[5].center.y(), 0.05);             // moved along the force
  EXPECT_NEAR(sweep.deformed().frames[0].center.norm(), 0.0, 1e-15);  // the root never moves
  ASSERT_TRUE(sweep.remove_force(id));
  for (int s = 0; s < 3000; ++s) sweep.step(0.01);
  EXPECT_LT((sweep.deformed().frames[5].center - sweep.rest().frames[5].center).norm(), 1e-6);
  EXPECT_LT(sweep.energy(), 1e-10);
}

TEST(ElasticSweepForces, AnImpulseOnTheFixedRootLeavesNothingMoving) {
  // The root ring's handles and its positional spring take the loads of a push on the root ring
  // (the rotational part goes to section 1, the nearest that can turn), but the root never moves:
  // a kick there must not become a speed that never decays (energy, sleep).
  ElasticSweep sweep(test::sweep_def(test::straight_shape(6, 8, 0.3)));
  ForceSpec f;
  f.t = 0.0;
  f.theta = 0.4;
  f.vector = Vec3(-3, 1, 2);
  f.components = kPositional | kRadial;
  sweep.apply_impulse(f);
  EXPECT_EQ(sweep.max_speed(), 0.0);
  EXPECT_EQ(sweep.energy(), 0.0);
}

TEST(ElasticSweepForces, ForceAtAWorldPointIsProjectedToTheSurface) {
  ElasticSweep sweep(test::sweep_def(test::straight_shape(5, 8, 0.5)));
  ForceSpec f;
  f.at_world_point = true;
  f.point = Vec3(0, 3.0, 2.5);  // outside the tube, beside t = 2.5 at θ = π/2
  f.components = kRadial;
  f.vector = Vec3(0, -1, 0);
  sweep.add_force(f);
  for (int s = 0; s < 20; ++s) sweep.step(0.01);
  // Handles at θ = π/2 (j = 2) of sections 2 and 3 are pushed in; the opposite side is not.
  EXPECT_LT(sweep.radial_offset(2, 2), 0.0);
  EXPECT_LT(sweep.radial_offset(3, 2), 0.0);
  EXPECT_EQ(sweep.radial_offset(2, 6), 0.0);
  EXPECT_FALSE(sweep.positional_active());
  EXPECT_FALSE(sweep.rotational_active());
}

}  // namespace
}  // namespace sweep

namespace sweep {
namespace {

TEST(SurfaceFrame, OutwardTangentialAndAxialFollowTheSection) {
  // Section frames turned by 90° about z: local x is world y. At θ = 0 the outward direction is
  // local x (world +y), tangential is local y (world −x), axial is local z (world z).
  SweepShape s = test::straight_shape(4, 4, 0.5);
  for (Frame& f : s.frames) f.rotation = Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
  SectionLoads loads;
  loads.resize(4, 4);
  ForceSpec squeeze;
  squeeze.frame = VectorFrame::surface;
  squeeze.components = kRadial;
  squeeze.vector = Vec3(-2, 0, 0);  // inward
  accumulate_force(s, squeeze, 2.0, 0.0, 1.0, 1.0, loads);
  EXPECT_NEAR(loads.radial[2 * 4 + 0], -2.0, 1e-12);  // the handle under it shrinks
  loads.clear();
  ForceSpec twist = squeeze;
  twist.components = kRotational;
  twist.vector = Vec3(0, 1, 0);  // tangential: a torque about the axis only
  accumulate_force(s, twist, 2.0, 0.0, 1.0, 1.0, loads);
  EXPECT_LT((loads.torque[2] - Vec3(0, 0, 1)).norm(), 1e-12);
}

}  // namespace
}  // namespace sweep

namespace sweep {
namespace {

TEST(ElasticSweepDecay, FreeMotionEndsAtExactlyZeroNotInSubnormals) {
  ElasticSweep sweep(test::sweep_def(test::straight_shape(5, 6, 0.3)));
  ForceSpec f;
  f.t = 4.0;
  f.vector = Vec3(0, 2, 1);
  f.components = kRotational | kRadial | kPositional;
  const ForceId id = sweep.add_force(f);
  for (int s = 0; s < 30; ++s) sweep.step(1.0 / 60);
  sweep.remove_force(id);
  // ζ = 0.3 at 1.5 Hz loses a factor e^-2.8 a second: 1e-200 is reached within ~170 s.
  for (int s = 0; s < 60 * 240; ++s) sweep.step(1.0 / 60);
  EXPECT_EQ(sweep.energy(), 0.0);
  EXPECT_EQ(sweep.max_displacement(), 0.0);
  EXPECT_EQ(sweep.max_speed(), 0.0);
}

}  // namespace
}  // namespace sweep
