// The simulator fed live (Simulator::advance_to, set_body_pose, add_force, set_gravity): what a
// game's loop gives equals what a scene file gives, and how the loop slices time changes nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/sample_sweeps.h"
#include "sim/sweep_pose.h"
#include "sweep/core/error.h"
#include "sweep/sim/simulator.h"

namespace sweep::sim {
namespace {

using test_pose::max_difference;
using test_pose::pose;

Rig material_part() {
  Rig rig = test::bent_part();
  Material m;
  m.youngs_modulus = 2e5;
  m.metres_per_unit = 0.1;
  rig.sweeps[0].material = m;
  rig.sweeps[0].section_materials.assign(rig.sweeps[0].rest.section_count(), m);
  return rig;
}

SceneForce push(double start, double end, const Vec3& v) {
  SceneForce f;
  f.sweep = "part";
  f.sweep_index = 0;
  f.spec.t = 5.0;
  f.spec.theta = 0.4;
  f.spec.vector = v;
  f.spec.target = RotationTarget::chain;
  f.start = start;
  f.end = end;
  return f;
}

// A linear body path that walks, turns and stops.
BodyPath walk() {
  const auto turn = [](double a) { return Quat(Eigen::AngleAxisd(a, Vec3(0.2, 1, 0.1).normalized())); };
  return BodyPath({{0.25, Vec3::Zero(), turn(0)},
                   {0.75, Vec3(1.5, 0, 0.3), turn(0.5)},
                   {1.25, Vec3(2, 0.4, 0.3), turn(-0.2)},
                   {1.5, Vec3(2, 0.4, 0.3), turn(-0.2)}},
                  BodyInterpolation::linear);
}

// advance_to in irregular slices (1/60, 1/144, 1/30 s and 7/720 s mixed) lands on the same pose at
// the same times as regular 1/60 s frames: forces switching between steps, the body on its path.
TEST(Live, IrregularFrameTimesGiveTheSamePoses) {
  const Rig rig = test::bent_part();
  Scene scene;
  scene.body = walk();
  scene.forces = {push(0.1234, 0.61, Vec3(1, 2, 0.5)), push(0.95, 0.95, Vec3(0, 0, 1.5))};
  Simulator regular(rig, scene), irregular(rig, scene);
  const int pattern[] = {12, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 24, 12, 24, 5, 7, 24, 12};  // 1/720 s
  int regular_units = 0, irregular_units = 0, compared = 0;
  double largest = 0, moved = 0;
  const std::vector<double> rest = pose(regular.sweep(0));
  while (irregular_units < 2 * 720) {
    for (const int units : pattern) {
      irregular_units += units;
      irregular.advance_to(irregular_units / 720.0);
      if (irregular_units % 12 != 0) continue;
      while (regular_units < irregular_units) {
        regular_units += 12;
        regular.advance_to(regular_units / 720.0);
      }
      largest = std::max(largest, max_difference(pose(regular.sweep(0)), pose(irregular.sweep(0))));
      moved = std::max(moved, max_difference(pose(regular.sweep(0)), rest));
      ++compared;
    }
  }
  EXPECT_GE(compared, 64);  // 8 rounds of 8
  EXPECT_LE(largest, 1e-9 * rig.sweeps[0].rest.length());
  EXPECT_GT(moved, 0.01 * rig.sweeps[0].rest.length());
}

// The scene player's frames and advance_to the same times are the same motion.
TEST(Live, AdvanceToFrameTimesIsAdvanceFrame) {
  const Rig rig = test::bent_part();
  Scene scene;
  scene.fps = 24;
  scene.body = walk();
  scene.forces = {push(0.1234, 0.61, Vec3(1, 2, 0.5))};
  Simulator player(rig, scene), live(rig, scene);
  for (int k = 1; k <= 48; ++k) {
    player.advance_frame();
    live.advance_to(k / 24.0);
    ASSERT_LE(max_difference(pose(player.sweep(0)), pose(live.sweep(0))), 1e-12 * rig.sweeps[0].rest.length()) << k;
  }
}

// A body pose given before each advance (the path sampled at the frame's end) moves the body as
// the same keyed path in the scene does: the live pieces are that path's pieces cut at the frames.
TEST(Live, BodyPosesGivenEachFrameAreTheScenesPath) {
  const Rig rig = test::bent_part();
  Scene keyed;
  keyed.body = walk();
  Simulator from_scene(rig, keyed), live(rig, Scene{});
  double largest = 0, moved = 0;
  const std::vector<double> rest = pose(live.sweep(0));
  for (int k = 1; k <= 120; ++k) {
    const double t = k / 60.0;
    const BodyState b = keyed.body.at(t);
    live.set_body_pose(b.rotation, b.translation);
    from_scene.advance_to(t);
    live.advance_to(t);
    EXPECT_LE((live.body().translation - from_scene.body().translation).norm(), 1e-12);
    largest = std::max(largest, max_difference(pose(from_scene.sweep(0)), pose(live.sweep(0))));
    moved = std::max(moved, max_difference(pose(live.sweep(0)), rest));
  }
  EXPECT_LE(largest, 1e-9 * rig.sweeps[0].rest.length());
  EXPECT_GT(moved, 0.01 * rig.sweeps[0].rest.length());  // the body's motion loads the part
}

// Forces added live, as they come, are the scene's forces: held ones and an impulse, at times
// between internal steps; old ones are dropped as new ones come, without changing the motion.
TEST(Live, ForcesAddedLiveAreTheScenesForces) {
  const Rig rig = test::bent_part();
  Scene scene;
  std::vector<SceneForce> forces;
  for (int k = 0; k < 12; ++k) {
    const double start = 0.05 + k * 0.13;
    forces.push_back(push(start, k % 3 == 2 ? start : start + 0.07 * (k % 4 + 1), Vec3(std::sin(k), 1.5, std::cos(k))));
  }
  scene.forces = forces;
  Simulator from_scene(rig, scene), live(rig, Scene{});
  std::size_t next = 0;
  double largest = 0;
  for (int k = 1; k <= 150; ++k) {
    const double t = k / 60.0;
    // The forces that start within this frame are given at its start, their times unchanged.
    while (next < forces.size() && forces[next].start < t) live.add_force(forces[next++]);
    from_scene.advance_to(t);
    live.advance_to(t);
    largest = std::max(largest, max_difference(pose(from_scene.sweep(0)), pose(live.sweep(0))));
  }
  EXPECT_EQ(next, forces.size());
  EXPECT_LT(live.scene().forces.size(), forces.size());  // the finished ones were dropped
  EXPECT_EQ(largest, 0.0);
}

// Gravity switched on live at time 0 is the scene's gravity from an unloaded start.
TEST(Live, GravityGivenLiveIsTheScenesGravity) {
  const Rig rig = material_part();
  Scene heavy;
  heavy.gravity = Vec3(0, -9.81, 0);
  heavy.gravity_start = Scene::GravityStart::unloaded;
  Scene light;
  light.gravity_start = Scene::GravityStart::unloaded;
  Simulator from_scene(rig, heavy), live(rig, light);
  live.set_gravity(heavy.gravity);
  double largest = 0, moved = 0;
  const std::vector<double> rest = pose(live.sweep(0));
  for (int k = 1; k <= 60; ++k) {
    from_scene.advance_to(k / 60.0);
    live.advance_to(k / 60.0);
    largest = std::max(largest, max_difference(pose(from_scene.sweep(0)), pose(live.sweep(0))));
    moved = std::max(moved, max_difference(pose(live.sweep(0)), rest));
  }
  EXPECT_LE(largest, 1e-12 * rig.sweeps[0].rest.length());
  EXPECT_GT(moved, 1e-3 * rig.sweeps[0].rest.length());  // it sags
}

// Wind switched on live at time 0 is the scene's wind, gusts and turbulence included; switched
// off, the part settles back to its rest.
TEST(Live, WindGivenLiveIsTheScenesWind) {
  const Rig rig = material_part();
  WindSettings w;
  w.velocity = Vec3(4, 0, 1);
  w.gust = 0.4;
  w.turbulence = 0.3;
  w.seed = 7;
  w.enabled = true;
  Scene windy;
  windy.wind = Wind(w);
  Simulator from_scene(rig, windy), live(rig, Scene{});
  live.set_wind(w);
  double largest = 0, moved = 0;
  const std::vector<double> rest = pose(live.sweep(0));
  for (int k = 1; k <= 60; ++k) {
    from_scene.advance_to(k / 60.0);
    live.advance_to(k / 60.0);
    largest = std::max(largest, max_difference(pose(from_scene.sweep(0)), pose(live.sweep(0))));
    moved = std::max(moved, max_difference(pose(live.sweep(0)), rest));
  }
  EXPECT_LE(largest, 1e-12 * rig.sweeps[0].rest.length());
  EXPECT_GT(moved, 1e-4 * rig.sweeps[0].rest.length());  // the wind bends it
  live.set_wind(WindSettings{});
  for (int k = 61; k <= 60 * 30; ++k) live.advance_to(k / 60.0);
  EXPECT_LT(max_difference(pose(live.sweep(0)), rest), 0.01 * moved);
}

TEST(Live, BadLiveInputIsRefused) {
  const Rig rig = test::bent_part();
  Simulator sim(rig, Scene{});
  sim.advance_to(0.5);
  EXPECT_THROW(sim.advance_to(0.4), Error);
  EXPECT_THROW(sim.advance_to(std::numeric_limits<double>::infinity()), Error);
  EXPECT_THROW(sim.add_force(push(0.3, 0.4, Vec3(0, 1, 0))), Error);  // starts in the past
  SceneForce wrong = push(0.6, 0.7, Vec3(0, 1, 0));
  wrong.sweep_index = 3;
  EXPECT_THROW(sim.add_force(wrong), Error);
  EXPECT_THROW(sim.set_body_pose(Quat(2, 0, 0, 0), Vec3::Zero()), Error);
  WindSettings gale;
  gale.gust = 2;
  EXPECT_THROW(sim.set_wind(gale), Error);
  EXPECT_EQ(sim.time(), 0.5);
}

}  // namespace
}  // namespace sweep::sim
