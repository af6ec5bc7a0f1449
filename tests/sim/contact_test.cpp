// Colliders: shapes against their closed forms, and parts that hit them — a fast swing
// into a thin plate, a thin capsule between two key sections, a part coming to rest on the ground
// — measured on the deformed surface itself, densely sampled, not on the solver's own stations.
#include "sweep/sim/contact.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include "core/beam_tubes.h"
#include "core/sample_sweeps.h"
#include "sim/surface_probes.h"
#include "sweep/core/error.h"
#include "sweep/sim/simulator.h"
#include "test_constants.h"

namespace sweep::sim {
namespace {

using ::sweep::test::kPi;
using test_probes::for_each_surface_sample;
using test_probes::penetration;
using test_probes::tip_impulse;

// The largest local coordinate `axis` of the surface in a box's frame, over the points within
// the box's span in its other two axes (which side of a plate the part is on where the plate is).
double farthest(const SweepShape& shape, const Collider& c, int axis) {
  double far = -1e300;
  for_each_surface_sample(shape, [&](const Vec3& world) {
    const Vec3 p = c.pose.to_local(world);
    bool behind = true;
    for (int o = 0; o < 3; ++o) behind = behind && (o == axis || std::abs(p[o]) <= c.half_size[o]);
    if (behind) far = std::max(far, p[axis]);
  });
  return far;
}

// Every contact test runs with the scene's default dynamics (automatic, which in a scene with
// colliders keeps the rest-pose modes: let switch to the exact chain here, three of the four
// exact-chain cases below failed — the thin plate, the coarse step far from colliders, energy after
// a hit — and so did a friction hold's energy bound) and, with SWEEP_TEST_EXACT_CONTACTS=1 in the
// environment, with the geometrically exact chain too, whose contact couplings, kicks and moves
// come from its current pose (core/contact_rows.cpp). Not in the default run: the exact chain's run
// takes minutes (one case alone 133 s) and four of its cases do not pass yet (the thin plate,
// friction on the slope, a coarse step far from colliders, energy after a hit).
bool exact_dynamics = false;
Scene new_scene() {
  Scene scene;
  if (exact_dynamics) scene.dynamics = ElasticSweep::Dynamics::exact;
  return scene;
}
class Contact : public ::testing::TestWithParam<bool> {
 protected:
  void SetUp() override { exact_dynamics = GetParam(); }
  void TearDown() override { exact_dynamics = false; }
};
std::vector<bool> dynamics_to_run() {
  const char* exact = std::getenv("SWEEP_TEST_EXACT_CONTACTS");
  if (exact != nullptr && std::string(exact) == "1") return {false, true};
  return {false};
}
std::string dynamics_name(const ::testing::TestParamInfo<bool>& param) {
  return param.param ? "exact" : "modal";
}
INSTANTIATE_TEST_SUITE_P(Dynamics, Contact, ::testing::ValuesIn(dynamics_to_run()), dynamics_name);

Rig rubber_tube(double damping_ratio) {
  Rig rig;
  rig.sweeps.push_back(test::beam::tube(test::beam::kRadius, test::beam::kRadius, damping_ratio));
  rig.sweeps.back().name = "tube";
  return rig;
}

TEST(Collider, DistancesMatchTheirClosedForms) {
  Vec3 out;
  const Collider s = Collider::sphere(Vec3(1, 2, 3), 2);
  EXPECT_NEAR(s.local_distance(s.pose.to_local(Vec3(1, 2, 8)), &out), 3, 1e-12);
  EXPECT_NEAR(out.z(), 1, 1e-12);
  const Collider c = Collider::capsule(Vec3(0, 0, 0), Vec3(4, 0, 0), 0.5);
  EXPECT_NEAR(c.local_distance(c.pose.to_local(Vec3(2, 3, 0)), &out), 2.5, 1e-12);  // beside the segment
  EXPECT_NEAR(c.local_distance(c.pose.to_local(Vec3(7, 0, 4)), &out), 4.5, 1e-12);  // past its end: 3-4-5
  EXPECT_NEAR(c.local_distance(c.pose.to_local(Vec3(1, 0.1, 0)), &out), -0.4, 1e-12);
  const Collider b = Collider::box(Vec3::Zero(), Vec3(1, 2, 3), Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ())));
  // Turned a quarter about z, the box's local x (half size 1) lies along world y.
  EXPECT_NEAR(b.local_distance(b.pose.to_local(Vec3(0, 4, 0)), &out), 3, 1e-12);
  EXPECT_NEAR(b.local_distance(b.pose.to_local(Vec3(0, 0.25, 0)), &out), -0.75, 1e-12);  // nearest face: ±y
  EXPECT_NEAR(std::abs((b.pose.rotation * out).y()), 1, 1e-12);
  EXPECT_NEAR(b.local_distance(b.pose.to_local(Vec3(5, 4, 6)), &out), std::sqrt(9.0 + 9 + 9), 1e-12);  // a corner
  const Collider p = Collider::plane(Vec3(0, -1, 0), Vec3(0, 2, 0));
  EXPECT_NEAR(p.local_distance(p.pose.to_local(Vec3(5, 1, 7)), &out), 2, 1e-12);
  EXPECT_NEAR(p.local_distance(p.pose.to_local(Vec3(5, -3, 7)), &out), -2, 1e-12);
  EXPECT_NE(Collider::sphere(Vec3::Zero(), 0).check(), "");
  EXPECT_NE(Collider::box(Vec3::Zero(), Vec3(1, 0, 1)).check(), "");
  EXPECT_EQ(Collider::capsule(Vec3::Zero(), Vec3(0, 1, 0), 0.1).check(), "");
  EXPECT_EQ(Collider::plane(Vec3::Zero(), Vec3::Zero()).check(), "its normal must not be zero");
  // Ends a rounding apart: a sphere, not a capsule along a direction that squared to nothing.
  const Collider dot = Collider::capsule(Vec3(1, 2, 3), Vec3(1, 2, 3 + 1e-200), 0.5);
  EXPECT_EQ(dot.check(), "");
  EXPECT_EQ(dot.half_length, 0.0);
  EXPECT_NEAR(dot.local_distance(dot.pose.to_local(Vec3(1, 2, 5)), &out), 1.5, 1e-12);
}

// The rubber tube (3.1 m, 31 units) kicked sideways at its tip at `fps`; returns the deepest the
// surface went into `plate` over every output frame, and where the tube's far side got to.
struct Swing {
  double deepest = 0;
  double far_side = -1e300;  // the largest local x of the surface in the plate's frame
};
Swing swing_into(const Rig& rig, const std::vector<Collider>& colliders, double fps, double duration) {
  Scene scene = new_scene();
  scene.duration = duration;
  scene.fps = fps;
  scene.forces.push_back(tip_impulse(rig.sweeps[0], Vec3(40, 0, 0)));
  scene.colliders = colliders;
  Simulator sim(rig, scene);
  Swing out;
  for (int k = 1; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    const SweepShape& shape = sim.sweep(0).deformed();
    for (const Collider& c : colliders) {
      out.deepest = std::max(out.deepest, penetration(shape, c));
      out.far_side = std::max(out.far_side, farthest(shape, c, 0));
    }
  }
  return out;
}

TEST_P(Contact, AFastSwingNeverEndsAFrameThroughAThinPlate) {
  const Rig rig = rubber_tube(0.02);
  const double length = rig.sweeps[0].rest.length();
  // A plate 0.02 units thick (1/1550 of the length) beside the outer half of the tube, 1.5 radii
  // from its axis, across the way the kick sends it.
  const Collider plate =
      Collider::box(Vec3(1.5 * test::beam::kRadius + 0.01, 0, 0.75 * length), Vec3(0.01, 5, 0.25 * length + 1));
  // Without it the tube swings far past where the plate is, moving many plate thicknesses a step.
  // A frame a contact step (480 fps): the tip's largest move in one step near the plate.
  Scene probe = new_scene();
  probe.duration = 0.25;
  probe.fps = 1 / Scene::kDefaultContactStep;
  probe.forces.push_back(tip_impulse(rig.sweeps[0], Vec3(40, 0, 0)));
  Simulator sim(rig, probe);
  double reach = 0, fastest_step = 0;
  Vec3 last = sim.sweep(0).deformed().frames.back().center;
  for (int k = 1; k < probe.frame_count(); ++k) {
    sim.advance_frame();
    const Vec3 tip = sim.sweep(0).deformed().frames.back().center;
    reach = std::max(reach, tip.x());
    fastest_step = std::max(fastest_step, (tip - last).norm());
    last = tip;
  }
  ASSERT_GT(reach, 4 * test::beam::kRadius) << "the kick must send the tube well past the plate";
  ASSERT_GT(fastest_step, 10 * 0.02) << "the tip must outrun the plate: ten thicknesses a step";
  for (const double fps : {24.0, 144.0}) {
    const Swing hit = swing_into(rig, {plate}, fps, 0.25);
    EXPECT_LE(hit.deepest, 1e-3 * length) << fps << " fps";
    EXPECT_LT(hit.far_side, -0.01 + 1e-3 * length) << fps << " fps: the surface got past the plate's near face";
  }
}

TEST_P(Contact, AThinCapsuleBetweenTwoKeySectionsIsCaught) {
  // Four key sections 10 units apart: a rod 0.1 thick across the tube's way, half-way between
  // sections 2 and 3, touches no key section and no sample point there — only the surface between.
  SweepDef def = test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.02, 4);
  def.name = "tube";
  Rig rig;
  rig.sweeps.push_back(def);
  const double length = def.rest.length();
  const double z = 0.5 * (def.rest.t[2] + def.rest.t[3]);
  const Collider rod = Collider::capsule(Vec3(1.0, -3, z), Vec3(1.0, 3, z), 0.05);
  Scene scene = new_scene();
  scene.duration = 0.3;
  scene.fps = 60;
  scene.forces.push_back(tip_impulse(def, Vec3(40, 0, 0)));
  // Unhindered, the tube passes where the rod is.
  Scene free = scene;
  Simulator probe(rig, free);
  double reach = 0;
  for (int k = 1; k < free.frame_count(); ++k) {
    probe.advance_frame();
    reach = std::max(reach, center_at(probe.sweep(0).deformed(), z).x());
  }
  ASSERT_GT(reach, 1.0 + 0.05 + 2 * test::beam::kRadius);
  scene.colliders = {rod};
  Simulator sim(rig, scene);
  double deepest = 0, farthest_there = -1e300;
  for (int k = 1; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    deepest = std::max(deepest, penetration(sim.sweep(0).deformed(), rod));
    farthest_there = std::max(farthest_there, center_at(sim.sweep(0).deformed(), z).x());
  }
  EXPECT_LE(deepest, 1e-3 * length);
  // Stopped on the rod's near side: its axis at most a radius and the rod's radius short of it.
  EXPECT_LE(farthest_there, 1.0 - 0.05 - test::beam::kRadius + 1e-3 * length);
}

TEST_P(Contact, APartLaidOnTheGroundSettlesOutsideItAndSleeps) {
  // A stiff rubber tube held out level sags under its weight onto a floor 0.3 units below it, and
  // comes to rest on it, keeping the floor's margin.
  Rig rig;
  rig.sweeps.push_back(test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.2, 16));
  rig.sweeps[0].name = "tube";
  test::beam::set_youngs_modulus(rig.sweeps[0], 2e8);
  Scene scene = new_scene();
#if defined(SWEEP_SANITIZED)
  scene.duration = 2;  // under the sanitizers (68 s for 8 s; 0.34 s against 0.69 s optimised): asleep at frame 31 of 60
#else
  scene.duration = 8;
#endif
  scene.fps = 30;
  scene.gravity = Vec3(0, -9.81, 0);
  scene.gravity_start = Scene::GravityStart::unloaded;  // starts unloaded: it sags from frame 0
  Collider floor = Collider::plane(Vec3(0, -test::beam::kRadius - 0.3, 0), Vec3(0, 1, 0));
  floor.margin = 0.02;
  scene.colliders = {floor};
  const double length = rig.sweeps[0].rest.length();
  // Without the floor it sags well below it.
  {
    Scene free = scene;
    free.colliders.clear();
    free.duration = 2;
    Simulator sim(rig, free);
    double lowest = 0;
    for (int k = 1; k < free.frame_count(); ++k) {
      sim.advance_frame();
      lowest = std::min(lowest, sim.sweep(0).deformed().frames.back().center.y());
    }
    ASSERT_LT(lowest, -1.0);
  }
  Simulator sim(rig, scene);
  Collider inflated = floor;  // the floor and its margin
  inflated.pose.center.y() += floor.margin;
  int slept_at = -1;
  long long steps_when_asleep = 0;
  double deepest = 0;
  for (int k = 1; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    deepest = std::max(deepest, penetration(sim.sweep(0).deformed(), floor));
    if (!sim.is_awake(0) && slept_at < 0) {
      slept_at = k;
      steps_when_asleep = sim.steps_taken(0);
    }
    if (slept_at >= 0) {
      EXPECT_FALSE(sim.is_awake(0)) << "woke at frame " << k;
    }
  }
  EXPECT_EQ(deepest, 0.0) << "into the floor itself";
  const SweepShape& rest = sim.sweep(0).deformed();
  EXPECT_LE(penetration(rest, inflated), 1e-4 * length) << "at rest, within the margin";
  EXPECT_LT(sim.sweep(0).deformed().frames.back().center.y(), -0.2) << "it did come down onto the floor";
  ASSERT_GE(slept_at, 0) << "never fell asleep";
  EXPECT_EQ(sim.steps_taken(0), steps_when_asleep) << "asleep, it is not stepped";
}

// A cantilever lying along a frictionless floor (or slope) from its root, the floor a thousandth
// of a unit below its rest surface, gravity not pre-loaded: beyond its last contact only its weight
// loads it, which bends it down, so no section may end a frame above its rest height (along the
// floor's normal). Guards the push out of the floor (ContactRows::move_rows): shaped by the
// springs' compliance alone, with its speed Δq/dt, the push on a station near the root swung the
// whole tube up about it (E = 2e8: +1.15 units; 2e9: +0.07; the rubber tube flung 20 units up, and
// 3.3 off a 20° slope).
struct Lying {
  double highest = -1e300;  // the highest section above its rest height, along the floor's normal
  double farthest = 0;      // the farthest any section went down the slope, across the tube
};
Lying lying_on(double youngs_modulus, double slope, double friction = 0, double step = 0,
               double contact_step = Scene::kDefaultContactStep, double duration = 1) {
  Rig rig;
  rig.sweeps.push_back(test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.2));
  rig.sweeps[0].name = "tube";
  test::beam::set_youngs_modulus(rig.sweeps[0], youngs_modulus);
  Scene scene = new_scene();
  scene.duration = duration;
  scene.fps = 30;
  scene.gravity = Vec3(0, -9.81, 0);
  scene.gravity_start = Scene::GravityStart::unloaded;
  scene.step = step;
  scene.contact_step = contact_step;
  // Tilted about the tube's axis: its fall across the tube, +x and down.
  const Vec3 n(std::sin(slope), std::cos(slope), 0);
  Collider floor = Collider::plane(-(test::beam::kRadius + 0.001) * n, n);
  floor.friction = friction;
  scene.colliders = {floor};
  const Vec3 down(std::cos(slope), -std::sin(slope), 0);  // the slope's fall, across the tube
  Simulator sim(rig, scene);
  Lying out;
  for (int k = 1; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    for (const Frame& f : sim.sweep(0).deformed().frames) {
      out.highest = std::max(out.highest, n.dot(f.center));
      out.farthest = std::max(out.farthest, down.dot(f.center));
    }
  }
  return out;
}
double highest_lying(double youngs_modulus, double slope, double friction = 0, double step = 0,
                     double contact_step = Scene::kDefaultContactStep) {
  return lying_on(youngs_modulus, slope, friction, step, contact_step).highest;
}

TEST_P(Contact, ATubeLyingAlongTheFloorFromItsRootStaysOnIt) {
  // At rest height, to the contact's tolerance (1e-4 of the length, as the ground test's margin).
  // Measured 0 for E = 2e8 and 2e9.
  const double length = test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.2).rest.length();
#if defined(SWEEP_SANITIZED)
  // Under the sanitizers (22 s a run there) the stiffer tube alone: the same code, the same contacts.
  for (const double e : {2e8}) EXPECT_LE(highest_lying(e, 0), 1e-4 * length) << "E = " << e;
#else
  for (const double e : {2e8, 2e9}) EXPECT_LE(highest_lying(e, 0), 1e-4 * length) << "E = " << e;
#endif
}

TEST_P(Contact, ATubeLyingAlongASlopeOrASoftOneStaysOnTheFloor) {
  const double length = test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.2).rest.length();
  // On a 20° slope it slides down across (measured 0).
  EXPECT_LE(highest_lying(2e8, 20 * kPi / 180), 1e-4 * length) << "on the slope";
  // The rubber tube (E = 1e7), to the contacts' tolerance on the true surface (1e-3 of the length,
  // as the thin plate's): measured +0.012 units on the floor and +0.015 on the slope. What is left
  // is its first span's shear sag (about 1.1 mm, the whole tube's weight over κGA/h: no move
  // relieves material mode's shear springs of a load, ElasticSweep::positional_share; with them in
  // the move, tried, it is 0), which the bending lifts the rest over.
  EXPECT_LE(highest_lying(1e7, 0), 1e-3 * length);
  EXPECT_LE(highest_lying(1e7, 20 * kPi / 180), 1e-3 * length) << "on the slope";
}

// The rubber tube (E = 1e7) lying along a frictionless 20° slope from its root, released unloaded,
// its joints moved by the exact chain: the contact solver once kicked and moved them by the rest
// pose's modes, and it was thrown 15 units off the slope. Now it stays on it, to the contacts'
// tolerance (1e-3 of the length, as the modal run's). Its chain's energy (kinetic, elastic and
// gravity's) is printed, not bounded: it still gains 1.4 % of m g L here (the positional springs,
// stepped apart from the chain, are not part of that balance; not yet understood).
TEST(ContactExactChain, ATubeLyingAlongASlopeStaysOnIt_long) {
  Rig rig;
  rig.sweeps.push_back(test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.2));
  rig.sweeps[0].name = "tube";
  test::beam::set_youngs_modulus(rig.sweeps[0], 1e7);
  Scene scene;
  scene.dynamics = ElasticSweep::Dynamics::exact;
  scene.duration = 1;
  scene.fps = 30;
  const Vec3 g(0, -9.81, 0);
  scene.gravity = g;
  scene.gravity_start = Scene::GravityStart::unloaded;
  const double slope = 20 * kPi / 180;
  const Vec3 n(std::sin(slope), std::cos(slope), 0);
  scene.colliders = {Collider::plane(-(test::beam::kRadius + 0.001) * n, n)};
  Simulator sim(rig, scene);
  const ElasticSweep& tube = sim.sweep(0);
  ASSERT_TRUE(tube.exact_chain());
  const auto energy = [&] {
    const ChainDynamics& chain = *tube.exact_chain_state();
    return chain.kinetic_energy() + chain.elastic_energy() + chain.gravity_potential(g);
  };
  double mass = 0;
  for (const double m : tube.chain()->node_mass) mass += m;
  const double length = tube.rest().length();
  const double weight_work = mass * g.norm() * tube.chain()->metres_per_unit * length;
  const double start = energy();
  double most = -1e300, highest = -1e300;
  for (int k = 1; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    most = std::max(most, energy() - start);
    for (const Frame& f : tube.deformed().frames) highest = std::max(highest, n.dot(f.center));
  }
  std::printf("exact chain on the slope: energy gained at most %.3g J (m g L = %.3g J), highest %+.3g units\n", most,
              weight_work, highest);
  EXPECT_LE(highest, 1e-3 * length);
}

// With friction too (found in review): the rubber tube on the 20° slope was thrown +10.5 units
// at μ = 2 and +0.040 at 0.5. The friction hold (sim/contact_stick.cpp) held each station whose
// springs' force stayed in the cone, however fast the whipping tube carried it off its anchor
// (1.5 to 22 units a step), moving it back through the compliance each step and stopping its
// speed for free: each hold stored 5 to 200 J in the springs. A hold now stops no more momentum
// than the cone gives over the step (μN·dt); past that the station slides.
TEST_P(Contact, ASoftTubeLyingOnAFrictionalSlopeStaysOnIt) {
  const double length = test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.2).rest.length();
  for (const double mu : {0.5, 2.0}) {
    const double highest = highest_lying(1e7, 20 * kPi / 180, mu);
    std::printf("rubber on the 20 degree slope, mu %.1f: highest %+.4g units\n", mu, highest);
    EXPECT_LE(highest, 1e-3 * length) << "mu " << mu;
  }
}

// Coulomb's cone on a slope: a tube lying along a 20° slope from its root (tan θ = 0.364) stays
// where it lies at μ = 0.5 and 2, stiff (E = 2e8) or rubber (1e7), and slides down it at
// μ = 0.5 tan θ. (Frictionless, over 2 s, the stiff tube swings up to 5.1 units down it, the rubber
// one 27.) Before friction per patch both slid at any μ: the stiff tube 2.4 units at μ = 2, the rubber one
// 5.8 at μ = 0.5 and 1.1 at 2 — the hold read each station's cone alone, and the normal force
// along a part lying on the ground is unevenly shared (every other station pressed, some at a
// twentieth of their weight: the contact is statically indeterminate), and the momentum its move
// stops row by row (20–40× the stations' own). A patch of neighbouring stations now shares its
// cones and its momentum is its stations' together (sim/contact_stick.cpp).
TEST_P(Contact, ATubeLyingOnAFrictionalSlopeStaysAboveTanThetaAndSlidesBelowIt) {
  const double length = test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.2).rest.length();
  const double slope = 20 * kPi / 180;
  for (const double e : {2e8, 1e7}) {
    for (const double mu : {0.5, 2.0}) {
      const double farthest = lying_on(e, slope, mu, 0, Scene::kDefaultContactStep, 1.5).farthest;
      std::printf("E %.0e on the 20 degree slope, mu %.2f: farthest down it %.4g units\n", e, mu, farthest);
      // Measured 0.0045 (stiff) and 0.06–0.07 (rubber: the slip of the first step of each
      // contact as it lands, the speeds' friction's).
      EXPECT_LE(farthest, 3e-3 * length) << "E " << e << " mu " << mu;
    }
    const double slid = lying_on(e, slope, 0.5 * std::tan(slope), 0, Scene::kDefaultContactStep, 1.5).farthest;
    std::printf("E %.0e on the 20 degree slope, mu tan/2: farthest down it %.4g units\n", e, slid);
    EXPECT_GT(slid, 0.01 * length) << "E " << e << ": below tan theta it slides";
  }
}

// A coarse internal step (1/30 s, one a frame) near a collider is cut into pieces of
// Scene::contact_step: the contacts' push out and friction are first order in the step, and at
// 1/30 s each free step carried the swinging rubber tube 5 to 9 units into the slope and the push
// out lifted it, the springs' energy climbing from 4 to 460 J against the 139 J gravity can give:
// it was thrown 7.7 to 23.6 units up (1/60 s: 0.45 to 1.31).
TEST_P(Contact, ACoarseStepIsCutIntoContactStepsNearACollider) {
  const double length = test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.2).rest.length();
  const double slope = 20 * kPi / 180;
  for (const double mu : {0.0, 2.0}) {
    const double coarse = highest_lying(1e7, slope, mu, 1.0 / 30);
    std::printf("rubber on the 20 degree slope, step 1/30 s, mu %.1f: highest %+.4g units\n", mu, coarse);
    EXPECT_LE(coarse, 1e-3 * length) << "mu " << mu;
    // The same motion as at the default step: both are cut into pieces of 1/480 s, to rounding.
    EXPECT_NEAR(coarse, highest_lying(1e7, slope, mu), 1e-9 * length) << "mu " << mu;
  }
}

// Far from every collider a coarse step stays whole: the frames are those of the scene without the
// collider, to the bit. (On the modes or the exact chain alone: the automatic dynamics keep the
// modes in any scene with colliders and switch without one, and this kick turns the tube far.)
TEST_P(Contact, ACoarseStepFarFromEveryColliderIsNotCut) {
  const Rig rig = rubber_tube(0.1);
  Scene scene = new_scene();
  if (!exact_dynamics) scene.dynamics = ElasticSweep::Dynamics::modal;
  scene.duration = 0.5;
  scene.fps = 30;
  scene.step = 1.0 / 30;
  scene.forces.push_back(tip_impulse(rig.sweeps[0], Vec3(20, 0, 0)));
  Scene far = scene;
  // The tube is 31 units long from its root at the origin: its reach is 62 units and its radius.
  far.colliders = {Collider::sphere(Vec3(0, 70, 0), 1.0)};
  Simulator alone(rig, scene), beside(rig, far);
  for (int k = 1; k < scene.frame_count(); ++k) {
    alone.advance_frame();
    beside.advance_frame();
    const auto& a = alone.sweep(0).deformed().frames;
    const auto& b = beside.sweep(0).deformed().frames;
    for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i].center, b[i].center) << "frame " << k << " section " << i;
  }
  // Within its reach (a sphere it never touches), the pieces change the frames by rounding alone
  // here, where nothing loads the part over the steps (with the body moving, its loads are sampled
  // at each piece's middle: a finer step's motion, 8e-5 of the length off in a review's probe).
  Scene within = scene;
  within.colliders = {Collider::sphere(Vec3(0, 50, 0), 1.0)};
  Simulator cut(rig, within), whole(rig, scene);
  double most = 0;
  for (int k = 1; k < scene.frame_count(); ++k) {
    cut.advance_frame();
    whole.advance_frame();
    const auto& a = cut.sweep(0).deformed().frames;
    const auto& b = whole.sweep(0).deformed().frames;
    for (std::size_t i = 0; i < a.size(); ++i) most = std::max(most, (a[i].center - b[i].center).norm());
  }
  EXPECT_GT(most, 0.0) << "not cut: the pieces round differently";
  EXPECT_LT(most, 1e-9 * rig.sweeps[0].rest.length());
}

// A scene built in code, not read from a file, is checked by the simulator itself.
TEST_P(Contact, TheSimulatorRefusesAContactStepOrStationCountOutOfRange) {
  const Rig rig = rubber_tube(0.1);
  const auto refused = [&](const Scene& scene) {
    try {
      Simulator sim(rig, scene);
    } catch (const Error& e) {
      EXPECT_EQ(e.category(), ErrorCategory::usage);
      return std::string(e.what());
    }
    return std::string();
  };
  for (const double step : {0.0, -1.0, 2.0, std::nan("")}) {
    Scene scene = new_scene();
    scene.contact_step = step;
    EXPECT_NE(refused(scene).find("Scene::contact_step must be between 1e-06 and 1 s"), std::string::npos) << step;
  }
  Scene scene = new_scene();
  scene.contact_stations = 0;
  EXPECT_NE(refused(scene).find("Scene::contact_stations must be between 1 and 64"), std::string::npos);
  EXPECT_EQ(refused(Scene{}), "");
}

// Undamped, kicked into a sphere: what the springs hold (kinetic and elastic, in joules in
// material mode) never grows past the kick's energy, and the inelastic hit takes some of it (the
// part's own ringing keeps most).
// At the default step and at a coarse one (1/30 s, cut into contact steps near the sphere).
void expect_no_energy_gain(const Rig& rig, const Vec3& kick, const Collider& ball, double step = 0) {
  Scene scene = new_scene();
  scene.duration = 1;
  scene.fps = 240;
  scene.step = step;
  scene.forces.push_back(tip_impulse(rig.sweeps[0], kick));
  scene.colliders = {ball};
  Simulator sim(rig, scene);
  sim.advance_frame();
  const double kicked = sim.sweep(0).energy();
  ASSERT_GE(clearance(sim.sweep(0).deformed(), {&ball, ball.pose}, 4).gap, 0.0) << "not touching yet";
  double most = 0, last = 0;
  for (int k = 2; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    last = sim.sweep(0).energy();
    most = std::max(most, last);
  }
  EXPECT_LE(most, kicked * (1 + 1e-9));
  // Undamped and untouched, the closed-form springs keep it to rounding (4e-15 here): a loss
  // beyond that is the hit's.
  EXPECT_LT(last, (1 - 1e-4) * kicked) << "the hit took none (the test must touch)";
}

TEST_P(Contact, ContactsNeverAddEnergy) {
  Rig material = rubber_tube(0.0);
  test::beam::set_youngs_modulus(material.sweeps[0], 2e8);
  for (const double step : {0.0, 1.0 / 30}) {
    SCOPED_TRACE(step);
    expect_no_energy_gain(material, Vec3(40, 0, 0), Collider::sphere(Vec3(2.5, 0, 0.8 * 31), 1.0), step);
  }
  // The paper's independent springs, undamped.
  Rig paper;
  paper.sweeps.push_back(test::sweep_def(test::straight_shape(12, 16, 0.3)));
  paper.sweeps[0].name = "tube";
  for (SectionSprings& s : paper.sweeps[0].springs) {
    for (SpringSettings* k : {&s.positional, &s.bend, &s.twist, &s.radial}) k->damping_ratio = 0;
  }
  for (const double step : {0.0, 1.0 / 30}) {
    SCOPED_TRACE(step);
    expect_no_energy_gain(paper, Vec3(1, 0, 0), Collider::sphere(Vec3(0.6 + 0.3 + 0.1, 0, 8.8), 0.1), step);
  }
}

TEST_P(Contact, TheSameMotionAtEveryFrameRate) {
  // Contacts are resolved on the internal clock: frames at a shared time are the same bits.
  const Rig rig = rubber_tube(0.02);
  const auto pose_at_one_second = [&](double fps, bool with_box) {
    Scene scene = new_scene();
    scene.duration = 1;
    scene.fps = fps;
    scene.forces.push_back(tip_impulse(rig.sweeps[0], Vec3(40, 0, 0)));
    if (with_box) scene.colliders = {Collider::box(Vec3(1.3, 0, 25), Vec3(0.05, 4, 4))};
    Simulator sim(rig, scene);
    for (int k = 1; k < scene.frame_count(); ++k) sim.advance_frame();
    std::vector<double> pose;
    for (const Frame& f : sim.sweep(0).deformed().frames) pose.insert(pose.end(), f.center.data(), f.center.data() + 3);
    return pose;
  };
  const std::vector<double> at24 = pose_at_one_second(24, true);
  ASSERT_NE(at24, pose_at_one_second(24, false)) << "the box must change the motion (the test must touch)";
  for (const double fps : {30.0, 60.0, 144.0}) EXPECT_EQ(pose_at_one_second(fps, true), at24) << fps << " fps";
}

TEST_P(Contact, FrictionDragsAPartTheBodyPullsOverTheGround) {
  // A tube held out level lies on a world floor while the body glides along +x at constant
  // velocity (no inertial load). Without friction the floor only holds it up; with friction it drags
  // the part back (−x).
  Rig rig;
  rig.sweeps.push_back(test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.2, 12));
  rig.sweeps[0].name = "tube";
  test::beam::set_youngs_modulus(rig.sweeps[0], 2e8);
#if defined(SWEEP_SANITIZED)
  // Under the sanitizers (45 s for 2 s) the first 0.4 s: the drag grows steadily from the first
  // frames (0.12 units at 0.2 s, 2.2 at 2 s, μ = 1).
  constexpr double kDragSeconds = 0.4;
#else
  constexpr double kDragSeconds = 2;
#endif
  const auto lag = [&](double mu) {
    Scene scene = new_scene();
    scene.duration = kDragSeconds;
    scene.fps = 30;
    scene.gravity = Vec3(0, -9.81, 0);
    scene.gravity_start = Scene::GravityStart::unloaded;
    scene.body = BodyPath({{0, Vec3::Zero(), Quat::Identity()}, {10, Vec3(10, 0, 0), Quat::Identity()}},
                          BodyInterpolation::linear);
    Collider floor = Collider::plane(Vec3(0, -test::beam::kRadius - 0.3, 0), Vec3(0, 1, 0));
    floor.friction = mu;
    scene.colliders = {floor};
    Simulator sim(rig, scene);
    double most = 0;
    for (int k = 1; k < scene.frame_count(); ++k) {
      sim.advance_frame();
      most = std::max(most, -sim.sweep(0).deformed().frames.back().center.x());
    }
    return most;
  };
  EXPECT_LT(lag(0), 1e-6 * 31) << "no friction, no drag";
#if defined(SWEEP_SANITIZED)
  // Under the sanitizers (26 s a run there) one friction: the same hold and slide code.
  for (const double mu : {1.0}) EXPECT_GT(lag(mu), 0.01) << "friction " << mu << " drags the tip back";
#else
  for (const double mu : {0.3, 1.0}) EXPECT_GT(lag(mu), 0.01) << "friction " << mu << " drags the tip back";
#endif
}

TEST_P(Contact, CollidersOutOfReachChangeNothing) {
  // Far from the part, or beside it but out of its way (the broad phase's business), carried by the
  // body or not: the same bits as none. (On the modes or the exact chain alone: the automatic
  // dynamics keep the modes in any scene with colliders and switch without one.)
  const Rig rig = rubber_tube(0.02);
  Scene scene = new_scene();
  if (!exact_dynamics) scene.dynamics = ElasticSweep::Dynamics::modal;
  scene.duration = 0.5;
  scene.fps = 30;
  scene.forces.push_back(tip_impulse(rig.sweeps[0], Vec3(40, 0, 0)));
  scene.forces[0].spec.vector = Vec3(4, 0, 0);  // a swing of about 2 units at the tip, in x
  // At the contact step: a coarser step is cut into contact steps within a collider's reach
  // (Scene::contact_step), which changes its rounding there.
  scene.step = Scene::kDefaultContactStep;
  Simulator plain(rig, scene);
  Scene others = scene;  // (a simulator keeps a reference to its scene)
  Collider riding = Collider::capsule(Vec3(-20, 0, 0), Vec3(-20, 0, 30), 2);
  riding.carried = true;
  // The last ball is inside the part's bounding sphere, beside it in y: only the span and chord
  // culls keep it out.
  others.colliders = {Collider::sphere(Vec3(100, 0, 0), 1), Collider::plane(Vec3(0, -50, 0), Vec3(0, 1, 0)), riding,
                      Collider::sphere(Vec3(0, 3, 20), 0.5)};
  Simulator far(rig, others);
  for (int k = 1; k < scene.frame_count(); ++k) {
    plain.advance_frame();
    far.advance_frame();
    for (int i = 0; i < rig.sweeps[0].rest.section_count(); ++i)
      ASSERT_EQ(plain.sweep(0).deformed().frames[i].center, far.sweep(0).deformed().frames[i].center) << k;
  }
}

TEST_P(Contact, AWorldColliderStaysPutWhileACarriedOneMovesWithTheBody) {
  // The body glides along +x at 2 units/s (constant velocity: no load on the part). A ball fixed in
  // the world ahead of the tube's outer half is met and pushes the part back; the same ball carried
  // by the body never comes nearer, and the part never moves.
  const Rig rig = rubber_tube(0.1);
  const double length = rig.sweeps[0].rest.length();
  Scene scene = new_scene();
  scene.duration = 2;
  scene.fps = 30;
  scene.body = BodyPath({{0, Vec3::Zero(), Quat::Identity()}, {10, Vec3(20, 0, 0), Quat::Identity()}},
                        BodyInterpolation::linear);
  Collider ball = Collider::sphere(Vec3(2.0, 0, 0.8 * length), 0.5);
  scene.colliders = {ball};
  Simulator world(rig, scene);
  Scene riding = scene;  // (a simulator keeps a reference to its scene)
  riding.colliders[0].carried = true;
  Simulator carried(rig, riding);
  const std::vector<Frame> rest = rig.sweeps[0].rest.frames;
  double deepest = 0, pushed = 0;
  for (int k = 1; k < scene.frame_count(); ++k) {
    world.advance_frame();
    carried.advance_frame();
    // The world ball in mesh coordinates now: it has moved by −(the body's travel).
    const BodyState b = world.body();
    Collider here = ball;
    here.pose = Frame{b.rotation, b.translation}.inverse() * ball.pose;
    deepest = std::max(deepest, penetration(world.sweep(0).deformed(), here));
    pushed = std::min(pushed, world.sweep(0).deformed().frames.back().center.x());
    for (std::size_t i = 0; i < rest.size(); ++i)
      ASSERT_EQ(carried.sweep(0).deformed().frames[i].center, rest[i].center) << "frame " << k;
  }
  EXPECT_LT(pushed, -0.5) << "the world ball met the part and pushed its tip back";
  EXPECT_LE(deepest, 1e-3 * length);
}

TEST_P(Contact, ARestPoseInsideAColliderIsNamed) {
  const Rig rig = rubber_tube(0.02);
  // Its centre 0.3 beside the axis, 0.5 in radius: the tube's surface (radius 0.5) is 0.7 inside.
  Collider ball = Collider::sphere(Vec3(0.3, 0, 20), 0.5);
  ball.name = "ball";
  const std::vector<std::string> found =
      rest_pose_overlaps(rig, {ball, Collider::sphere(Vec3(9, 0, 0), 1)}, Frame{}, 4);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_NE(found[0].find("\"ball\""), std::string::npos) << found[0];
  EXPECT_NE(found[0].find("\"tube\""), std::string::npos) << found[0];
  EXPECT_NE(found[0].find("0.7 deep"), std::string::npos) << found[0];
}

// A body keyed to glide along +x at `speed` (mesh units/s, constant: no load on the part) carries
// the rubber tube (along z, 31 units) into a world collider whose centre lies on the tube's axis
// at 0.8 of its length, `ahead` units down the path. One frame, at the instant the tube's root is
// level with the collider's centre: a part that crossed the collider's path untouched is at rest,
// the collider's centre on its axis.
struct Crossing {
  double deepest = 0;  // how deep the surface is inside the collider at that frame
  std::vector<int> teleports;
  std::vector<std::string> skipped;
};
Crossing cross(const Collider& c, double ahead, double speed, bool teleport) {
  const Rig rig = rubber_tube(0.1);
  Scene scene = new_scene();
  scene.fps = speed / ahead;
  scene.duration = 1 / scene.fps;
  scene.teleport_enabled = teleport;
  scene.body = BodyPath({{0, Vec3::Zero(), Quat::Identity()}, {1, Vec3(speed, 0, 0), Quat::Identity()}},
                        BodyInterpolation::linear);
  scene.colliders = {c};
  Simulator sim(rig, scene);
  EXPECT_EQ(scene.frame_count(), 2);
  sim.advance_frame();
  const BodyState b = sim.body();
  EXPECT_NEAR(b.translation.x(), ahead, 1e-9 * ahead);
  Collider here = c;
  here.pose = Frame{b.rotation, b.translation}.inverse() * c.pose;
  return {penetration(sim.sweep(0).deformed(), here), sim.teleports(), sim.skipped_colliders()};
}

// The colliders across the tube's path: a ball, a box 40 units thick and a rod across the path.
std::vector<std::pair<Collider, double>> across_the_path() {
  const double z = 0.8 * test::beam::kLengthUnits;
  std::vector<std::pair<Collider, double>> out = {{Collider::sphere(Vec3(52, 0, z), 2), 52},
                                                  {Collider::box(Vec3(70, 0, z), Vec3(20, 5, 7)), 70},
                                                  {Collider::capsule(Vec3(51, -5, z), Vec3(51, 5, z), 1), 51}};
  for (auto& [c, x] : out) c.name = shape_name(c.shape);
  return out;
}

TEST_P(Contact, AFastBodyCannotCarryAPartThroughAWorldCollider) {
  // Without the teleport rule, the body's move is motion at any speed: 3,000 units/s crosses 6 units
  // a step of 1/480 s, 100,000 units/s 208 (past the ball, the box and the rod, and far past the
  // tube's own size, in one step).
  const double length = test::beam::kLengthUnits;
  for (const auto& [c, x] : across_the_path()) {
    for (const double speed : {3000.0, 10000.0, 100000.0}) {
      const Crossing r = cross(c, x, speed, false);
      EXPECT_TRUE(r.teleports.empty());
      EXPECT_LE(r.deepest, 1e-3 * length) << c.name << " at " << speed << " units/s";
    }
  }
}

TEST_P(Contact, ATeleportThatCarriesAPartThroughAWorldColliderIsSaid) {
  // The same moves under the default teleport rule (farther than the tube's 31 units within a
  // frame's time: 52 to 70 here) are cuts: the tube is put to rest in the new place and passes the
  // collider unmet, which is said, naming the collider, the part and the frame.
  for (const auto& [c, x] : across_the_path()) {
    for (const double speed : {3000.0, 10000.0, 100000.0}) {
      const Crossing r = cross(c, x, speed, true);
      ASSERT_EQ(r.teleports, std::vector<int>{1});
      ASSERT_EQ(r.skipped.size(), 1u) << c.name << " at " << speed;
      EXPECT_GT(r.deepest, 0.5) << "at rest in the new place, the collider's centre on its axis";
      EXPECT_EQ(r.skipped[0].rfind("frame 1: ", 0), 0u) << r.skipped[0];
      EXPECT_NE(r.skipped[0].find("collider \"" + c.name + "\""), std::string::npos) << r.skipped[0];
      EXPECT_NE(r.skipped[0].find("sweep \"tube\""), std::string::npos) << r.skipped[0];
    }
  }
  // A teleport past a collider off its way says nothing.
  Collider aside = Collider::sphere(Vec3(52, 40, 20), 2);
  aside.name = "aside";
  const Crossing r = cross(aside, 52, 10000, true);
  EXPECT_EQ(r.teleports, std::vector<int>{1});
  EXPECT_TRUE(r.skipped.empty()) << r.skipped[0];
}

}  // namespace
}  // namespace sweep::sim
