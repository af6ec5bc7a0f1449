// The automatic dynamics (ElasticSweep::Dynamics::automatic): the rest-pose modes while a material
// part's motion is small, the geometrically exact chain once a section has turned farther than
// ElasticSweep::kSwitchAngle from its rest pose. On the generated K = 32 tube of beam_tubes.h.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "core/beam_tubes.h"
#include "sweep/core/elastic_sweep.h"

namespace sweep {
namespace {

// The tube undamped, posed in its first bending mode so that its most turned section is turned by
// `amplitude` (rad) and released, then stepped one period of that mode by the rest-pose modes and
// by the exact chain side by side: the largest distance (a fraction of the length) between their
// sections' centres, both read from the joints' pose.
double modes_stray_over_a_period(double amplitude) {
  const SweepDef def = test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.0);
  ElasticSweep modal(def), exact(def);
  modal.set_exact_chain(false);
  exact.set_exact_chain(true);
  const ChainModel& chain = *modal.chain();
  const auto pose = [&](ElasticSweep& sweep, double scale) {
    for (int i = 1; i <= chain.joints; ++i)
      sweep.set_section_pose(i, Vec3::Zero(), scale * chain.modes.col(0).segment<3>(3 * (i - 1)));
  };
  pose(modal, 1.0);
  const double scale = amplitude / modal.largest_rotation();
  pose(modal, scale);
  pose(exact, scale);
  const double period = 2 * test::kPi / std::sqrt(chain.omega2[0]);
  const int steps = 400;
  const double length = test::beam::length_m(def);
  double stray = 0;
  for (int s = 0; s < steps; ++s) {
    modal.step(period / steps);
    exact.step(period / steps);
    const std::vector<Vec3>& a = modal.exact_chain_state()->centres();
    const std::vector<Vec3>& b = exact.exact_chain_state()->centres();
    for (std::size_t i = 0; i < a.size(); ++i) stray = std::max(stray, (a[i] - b[i]).norm() / length);
  }
  return stray;
}

// Where the switch angle comes from: the modes' error against the exact chain over a period of
// free swinging grows as the amplitude cubed (the rest pose's mass matrix is wrong to first order
// in the pose, the velocity terms to second, each acting on a motion of that amplitude), and at
// the switch angle it is 3e-5 of the length: invisible. At four times it, the error has grown
// more than twenty-fold (64-fold if cubic), past 1e-3: the modes are measurably wrong.
TEST(AutoChain, TheModesStrayFromTheExactChainAsTheAmplitudeCubedAndLittleAtTheSwitchAngle) {
  const double at = ElasticSweep::kSwitchAngle;
  const double small = modes_stray_over_a_period(0.5 * at), on = modes_stray_over_a_period(at),
               large = modes_stray_over_a_period(4 * at);
  std::printf("first-mode swing: the modes stray %.3g L at %.3g rad, %.3g L at %.3g rad, %.3g L at %.3g rad\n", small,
              0.5 * at, on, at, large, 4 * at);
  EXPECT_LT(on, 1e-3);
  EXPECT_GT(large, 1e-3);
  EXPECT_GT(on / small, 4.0);   // faster than linear: 8 if cubic
  EXPECT_GT(large / on, 20.0);  // 64 if cubic
}

// The switch: not below the angle, at the first check above it, once; the joints' state carries
// over as it stands (φ and w, with the modes consistent with them), and from there the automatic
// sweep moves as a sweep on the exact chain from the same state, bit for bit; reset() puts it back
// on the modes.
TEST(AutoChain, TheSwitchIsOneWayAndCarriesTheJointsStateOverExactly) {
  const SweepDef def = test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.05);
  ElasticSweep automatic(def), modal(def);
  automatic.set_dynamics(ElasticSweep::Dynamics::automatic);
  modal.set_exact_chain(false);
  ForceSpec kick;
  kick.t = def.rest.length();
  kick.vector = Vec3(4, 0, 0);  // N·s at the tip, across the axis
  kick.moment = MomentModel::physical;
  kick.target = RotationTarget::chain;
  automatic.apply_impulse(kick);
  modal.apply_impulse(kick);
  const double h = 1.0 / 480;
  int switched_at = -1;
  for (int s = 0; s < 2000 && switched_at < 0; ++s) {
    automatic.step(h);
    modal.step(h);
    const bool beyond = automatic.largest_rotation() > ElasticSweep::kSwitchAngle;
    ASSERT_FALSE(automatic.exact_chain());
    ASSERT_EQ(automatic.switch_if_large(), beyond) << "at step " << s;
    if (beyond) switched_at = s;
  }
  ASSERT_GE(switched_at, 0) << "the kick turned the tube past the switch angle";
  EXPECT_TRUE(automatic.exact_chain());
  EXPECT_TRUE(automatic.switched());
  EXPECT_FALSE(automatic.switch_if_large());  // once
  // Up to the switch the automatic sweep was the modal one, bit for bit, and its state is theirs.
  for (int i = 1; i < def.rest.section_count(); ++i) {
    ASSERT_EQ(automatic.rotation_vector(i), modal.rotation_vector(i));
    ASSERT_EQ(automatic.section_offset(i), modal.section_offset(i));
  }
  // From the same state, a sweep on the exact chain throughout the rest of the way.
  ElasticSweep exact(def);
  exact.copy_state_from(modal);
  exact.set_exact_chain(true);
  EXPECT_EQ(automatic.exact_chain_state()->kinetic_energy(), exact.exact_chain_state()->kinetic_energy());
  for (int s = 0; s < 100; ++s) {
    automatic.step(h);
    exact.step(h);
  }
  for (int i = 1; i < def.rest.section_count(); ++i) {
    ASSERT_EQ(automatic.rotation_vector(i), exact.rotation_vector(i)) << "section " << i;
    ASSERT_EQ(automatic.exact_chain_state()->speed(i), exact.exact_chain_state()->speed(i)) << "section " << i;
  }
  automatic.reset();
  EXPECT_FALSE(automatic.exact_chain());
  EXPECT_EQ(automatic.dynamics(), ElasticSweep::Dynamics::automatic);
}

// The exact chain's steps and kicks bring the modes to its joints only when something reads them:
// when the rest-pose modes take over (set_exact_chain(false), or an explicit integrator, which
// moves the joints by the modes), they start from the joints as the exact chain left them, after a
// kick with no step after it too. A nanosecond's step later the joints are where the chain left
// them, to their own motion over it — not where the modes last stood (at rest: the chain moved
// from the start).
TEST(AutoChain, TheModesTakeOverFromTheJointsTheExactChainLeft) {
  const SweepDef def = test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.05);
  for (const bool by_integrator : {false, true}) {
    ElasticSweep sweep(def);
    sweep.set_exact_chain(true);
    const double h = 1.0 / 480;
    sweep.apply_body_kick(Vec3(0, 0, 2), Vec3(0, 1, 0));  // the body's jumps of velocity, m/s and rad/s
    for (int s = 0; s < 20; ++s) sweep.step(h);
    sweep.apply_body_kick(Vec3(0, 1, 0), Vec3::Zero());
    const int k = def.rest.section_count();
    std::vector<Vec3> left;
    double largest = 0, fastest = 0;
    for (int i = 1; i < k; ++i) {
      left.push_back(sweep.rotation_vector(i));
      largest = std::max(largest, left.back().norm());
      fastest = std::max(fastest, sweep.exact_chain_state()->speed(i).norm());
    }
    ASSERT_GT(largest, 1e-3) << "the kicks turned the tube";
    if (by_integrator) {
      sweep.set_integrator(Integrator::semi_implicit_euler);
    } else {
      sweep.set_exact_chain(false);
    }
    ASSERT_FALSE(sweep.exact_chain());
    const double dt = 1e-9;
    sweep.step(dt);
    // Over dt the joints turn by their speed × dt (twice it: the modes' speeds are the chain's to
    // first order in the turn); the modes give the joints back to rounding (Φ Φᵀ M = 1).
    const double tolerance = 2 * fastest * dt + 1e-9 * largest;
    for (int i = 1; i < k; ++i)
      EXPECT_LT((sweep.rotation_vector(i) - left[i - 1]).norm(), tolerance)
          << "section " << i << (by_integrator ? ", the integrator switched" : ", the dynamics switched");
  }
}

}  // namespace
}  // namespace sweep
