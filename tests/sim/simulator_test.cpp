// The simulator: scene timing, what it skips, sleep, substep independence, divergence.
#include "sweep/sim/simulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "core/sample_sweeps.h"
#include "fp_guard.h"
#include "sweep/core/error.h"

namespace sweep::sim {
namespace {

Rig two_sweep_rig() {
  Rig rig;
  rig.sweeps.push_back(test::sweep_def(test::straight_shape(6, 8, 0.3)));
  rig.sweeps.back().name = "tail";
  rig.sweeps.push_back(test::sweep_def(test::irregular_shape(5, 6)));
  rig.sweeps.back().name = "neck";
  return rig;
}

Scene one_force_scene(double start, double end, int substeps) {
  Scene s;
  s.duration = 2.0;
  s.fps = 30;
  s.substeps = substeps;
  SceneForce f;
  f.sweep = "tail";
  f.sweep_index = 0;
  f.spec.t = 5.0;
  f.spec.theta = 0.0;
  f.spec.vector = Vec3(0, 3, 0);
  f.spec.target = RotationTarget::chain;
  f.start = start;
  f.end = end;
  s.forces.push_back(f);
  return s;
}

TEST(Simulator, NoForceMeansNothingIsStepped) {
  const Rig rig = two_sweep_rig();
  Scene scene = one_force_scene(0, 1, 4);
  scene.forces.clear();
  Simulator sim(rig, scene);
  for (int k = 0; k < 10; ++k) sim.advance_frame();
  for (int i = 0; i < 2; ++i) {
    EXPECT_FALSE(sim.is_driven(i));
    EXPECT_EQ(sim.steps_taken(i), 0);
    EXPECT_FALSE(sim.moved_last_frame(i));
    EXPECT_EQ(sim.sweep(i).deformed().radii, sim.sweep(i).rest().radii);
  }
}

TEST(Simulator, OnlyTheSweepAForceReachesIsStepped) {
  const Rig rig = two_sweep_rig();
  const Scene scene = one_force_scene(0, 1, 4);
  Simulator sim(rig, scene);
  for (int k = 0; k < 10; ++k) sim.advance_frame();
  EXPECT_EQ(sim.steps_taken(0), 40);
  EXPECT_EQ(sim.steps_taken(1), 0);
  EXPECT_GT(sim.sweep(0).deformed().frames[5].center.y(), 0.0);
}

// Largest difference between the section frames of two runs of sweep 0.
double frame_difference(const Simulator& a, const Simulator& b) {
  double d = 0;
  for (int i = 0; i < a.sweep(0).rest().section_count(); ++i) {
    const Frame& fa = a.sweep(0).deformed().frames[i];
    const Frame& fb = b.sweep(0).deformed().frames[i];
    d = std::max({d, (fa.center - fb.center).norm(), fa.rotation.angularDistance(fb.rotation)});
  }
  for (std::size_t m = 0; m < a.sweep(0).deformed().radii.size(); ++m) {
    d = std::max(d, std::abs(a.sweep(0).deformed().radii[m] - b.sweep(0).deformed().radii[m]));
  }
  return d;
}

TEST(Simulator, OneOrSixteenSubstepsGiveTheSameFramesForAConstantForce) {
  const Rig rig = two_sweep_rig();
  // Positional and radial loads do not depend on the pose, so the force is constant in the
  // springs' own coordinates from frame 3 to frame 20 (times on frame boundaries): the exact
  // integrator must then give the same frames whatever the substep count.
  Scene coarse = one_force_scene(3.0 / 30, 20.0 / 30, 1), fine = one_force_scene(3.0 / 30, 20.0 / 30, 16);
  for (Scene* s : {&coarse, &fine}) {
    s->forces[0].spec.components = kPositional | kRadial;
    s->forces[0].spec.vector = Vec3(-1, 3, 0.5);
  }
  Simulator a(rig, coarse, {.enabled = false}), b(rig, fine, {.enabled = false});
  double peak = 0;
  for (int k = 1; k < coarse.frame_count(); ++k) {
    a.advance_frame();
    b.advance_frame();
    ASSERT_LT(frame_difference(a, b), 1e-12) << "frame " << k;
    peak = std::max(peak, a.sweep(0).max_displacement());
  }
  EXPECT_GT(peak, 1e-2);  // it did move
}

TEST(Simulator, PoseDependentLoadsConvergeAsSubstepsGrow) {
  // The rotational part is re-split on the moving surface every step (the force follows the
  // surface), so it is not constant over a frame: more substeps sample it more finely, and the
  // frames converge (first order in the step) rather than match.
  const Rig rig = two_sweep_rig();
  auto run = [&](int substeps) {
    Scene s = one_force_scene(0, 1, substeps);
    s.forces[0].spec.vector = Vec3(1, 3, 0.5);  // oblique: the load's direction changes with the pose
    auto sim = std::make_unique<Simulator>(rig, s, SleepSettings{.enabled = false});
    for (int k = 1; k < 31; ++k) sim->advance_frame();
    return sim;
  };
  const auto ref = run(256), s4 = run(4), s16 = run(16);
  const double e4 = frame_difference(*s4, *ref), e16 = frame_difference(*s16, *ref);
  EXPECT_GT(e4, 0.0);
  EXPECT_LT(e16, e4 / 3);
}

TEST(Simulator, MotionDiesOutAndTheSweepSleepsUntilWoken) {
  const Rig rig = two_sweep_rig();
  Scene scene = one_force_scene(0, 0.2, 4);
  scene.duration = 30;
  SceneForce again = scene.forces[0];
  again.start = 25.0;
  again.end = 25.1;
  scene.forces.push_back(again);
  Simulator sim(rig, scene);
  int asleep_at = -1;
  for (int k = 1; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    if (asleep_at < 0 && !sim.is_awake(0)) asleep_at = k;
    if (asleep_at > 0 && k > asleep_at && sim.time() < 25.0) {
      ASSERT_FALSE(sim.moved_last_frame(0)) << "frame " << k;  // asleep costs nothing
    }
    if (sim.time() > 25.05 && sim.time() < 25.2) {
      ASSERT_TRUE(sim.is_awake(0)) << "woken by its force, frame " << k;
    }
  }
  ASSERT_GT(asleep_at, 0);
  EXPECT_LT(asleep_at / 30.0, 25.0);
  // Sleeping only once the motion is below tolerance: the pose is back at rest to that tolerance.
  EXPECT_LT(sim.sweep(0).max_displacement(), 1e-3);
}

TEST(Simulator, ImpulseChangesVelocityOnce) {
  // J = 3 N·s along y at t = L, the tip: all of its positional part goes to section 5's spring
  // (mass m), whose velocity must jump by J/m at t = 0.5 s, once. From then on that spring swings
  // freely from its rest position, y(τ) = (J/m) e^(−ζω₀τ) sin(ω_d τ) / ω_d, τ = t − 0.5, and no
  // other spring moves: a second kick (in a later piece, substep or frame) would change the
  // amplitude or the phase of every later frame.
  const Rig rig = two_sweep_rig();
  Scene scene = one_force_scene(0.5, 0.5, 4);  // end == start: an impulse
  scene.forces[0].spec.components = kPositional;
  const SpringSettings& spring = rig.sweeps[0].springs[5].positional;
  const double jump = scene.forces[0].spec.vector.y() / spring.mass;  // J/m, m/s
  {
    ElasticSweep sweep(rig.sweeps[0]);
    sweep.apply_impulse(scene.forces[0].spec);
    EXPECT_DOUBLE_EQ(sweep.max_speed(), jump);
  }
  const double w0 = 2 * std::numbers::pi * spring.frequency_hz, zeta = spring.damping_ratio;
  const double wd = w0 * std::sqrt(1 - zeta * zeta);
  Simulator sim(rig, scene, {.enabled = false});
  for (int k = 0; k < 15; ++k) sim.advance_frame();  // until t = 0.5: nothing yet
  EXPECT_EQ(sim.sweep(0).max_speed(), 0.0);
  double peak = 0;
  for (int k = 16; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    const double tau = sim.time() - 0.5;
    const double y = jump * std::exp(-zeta * w0 * tau) * std::sin(wd * tau) / wd;
    const ElasticSweep& tail = sim.sweep(0);
    ASSERT_NEAR(tail.section_offset(5).y(), y, 1e-9 * jump / wd) << "frame " << k;
    ASSERT_EQ(tail.section_offset(5).x(), 0.0) << "frame " << k;
    ASSERT_EQ(tail.section_offset(5).z(), 0.0) << "frame " << k;
    for (int i = 0; i < 5; ++i) ASSERT_EQ(tail.section_offset(i), Vec3::Zero()) << "section " << i;
    peak = std::max(peak, std::abs(y));
  }
  EXPECT_GT(peak, 0.1 * jump / wd);  // it swung
}

TEST(Simulator, DivergenceIsReportedNotWritten) {
  test::FpTrapsOff traps_off;  // the explicit integrator overflows on purpose
  Rig rig = two_sweep_rig();
  for (SectionSprings& s : rig.sweeps[0].springs) s.bend.frequency_hz = s.twist.frequency_hz = 200;
  Scene scene = one_force_scene(0, 1, 1);
  scene.integrator = Integrator::semi_implicit_euler;  // unstable at ω·dt = 2π·200/30 ≫ 2
  Simulator sim(rig, scene);
  try {
    for (int k = 1; k < scene.frame_count(); ++k) sim.advance_frame();
    FAIL() << "no divergence reported";
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::diverged);
    EXPECT_NE(std::string(e.what()).find("sweep \"tail\""), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("semi-implicit-euler"), std::string::npos) << e.what();
  }
}

TEST(Simulator, ExactIntegratorIsStableWhereEulerIsNot) {
  // Every spring of the tail at 201.7 Hz and undamped: a frame's step (1/30 s) is ω·dt = 42 rad,
  // twenty times semi-implicit Euler's limit of 2. A push of f = 3 N along y at the tip, positional
  // only (a load that does not follow the pose), from t = 0 to 1 s: only section 5's spring is
  // loaded, and the closed form of a step force on and then off is
  //   y(t) = (f/k) [(1 − cos ωt) − H(t − 1)(1 − cos ω(t − 1))],
  // bounded by 2 f/k, with the energy ½ m v² + ½ k y² conserved once the force is off.
  Rig rig = two_sweep_rig();
  const double hz = 201.7;  // not a multiple of the frame rate: every frame shows a new phase
  for (SectionSprings& s : rig.sweeps[0].springs) {
    for (SpringSettings* k : {&s.positional, &s.bend, &s.twist, &s.radial}) {
      k->frequency_hz = hz;
      k->damping_ratio = 0;
    }
  }
  Scene scene = one_force_scene(0, 1, 1);
  scene.forces[0].spec.components = kPositional;
  const SpringSettings& spring = rig.sweeps[0].springs[5].positional;
  const double f = scene.forces[0].spec.vector.y(), w = 2 * std::numbers::pi * hz;
  const double static_offset = f / spring.stiffness();  // f/k
  ASSERT_GT(w * scene.step_seconds(), 20 * 2.0);        // one step a frame: ω dt past 20 × the limit

  // Semi-implicit Euler at that step grows by ~(ω dt)² a step: far past the exact bound at once,
  // then a runaway.
  {
    test::FpTrapsOff traps_off;
    Scene euler = scene;
    euler.integrator = Integrator::semi_implicit_euler;
    Simulator sim(rig, euler, {.enabled = false});
    int past_bound = -1;
    try {
      for (int k = 1; k < euler.frame_count(); ++k) {
        sim.advance_frame();
        if (past_bound < 0 && !(std::abs(sim.sweep(0).section_offset(5).y()) <= 2 * static_offset)) past_bound = k;
      }
      ADD_FAILURE() << "semi-implicit Euler did not diverge";
    } catch (const Error& e) {
      EXPECT_EQ(e.category(), ErrorCategory::diverged) << e.what();
    }
    EXPECT_EQ(past_bound, 1);
  }

  // The exact integrator: the closed form at every frame, so it moves, stays bounded and keeps its
  // energy.
  Simulator sim(rig, scene, {.enabled = false});
  double peak = 0, energy_at_release = -1;
  for (int k = 1; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    const double t = sim.time();
    const double y = static_offset * ((1 - std::cos(w * t)) - (t > 1 ? 1 - std::cos(w * (t - 1)) : 0.0));
    const ElasticSweep& tail = sim.sweep(0);
    ASSERT_TRUE(tail.is_finite()) << "frame " << k;
    ASSERT_NEAR(tail.section_offset(5).y(), y, 1e-9 * static_offset) << "frame " << k;
    ASSERT_LE(tail.max_displacement(), 2 * static_offset * (1 + 1e-9)) << "frame " << k;
    peak = std::max(peak, tail.max_displacement());
    if (k == 30) energy_at_release = tail.energy();
    if (k > 30) {
      ASSERT_NEAR(tail.energy(), energy_at_release, 1e-9 * energy_at_release) << "frame " << k;
    }
  }
  EXPECT_GT(peak, static_offset);  // it moved: past the static offset, up to twice it
  EXPECT_GT(energy_at_release, 0.0);
}

}  // namespace
}  // namespace sweep::sim
