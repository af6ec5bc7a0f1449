// The simulator's own clock: the internal step does not depend on the frame rate,
// output frames are reached by an exact partial step, and forces switch exactly at their times.
#include <gtest/gtest.h>

#include <map>
#include <numeric>

#include "core/sample_sweeps.h"
#include "sim/sweep_pose.h"
#include "sweep/sim/simulator.h"

namespace sweep::sim {
namespace {

using test_pose::max_difference;
using test_pose::pose;

Rig bent_rig() {
  Rig rig;
  rig.sweeps.push_back(test::sweep_def(test::irregular_shape(7, 8)));
  rig.sweeps.back().name = "tail";
  return rig;
}

SceneForce force(double t, double theta, Vec3 v, double start, double end, std::uint8_t comp) {
  SceneForce f;
  f.sweep = "tail";
  f.sweep_index = 0;
  f.spec.t = t;
  f.spec.theta = theta;
  f.spec.vector = v;
  f.spec.components = comp;
  f.spec.target = RotationTarget::chain;
  f.start = start;
  f.end = end;
  return f;
}

// Switching times on shared frame times (1/6 s, 2/3 s) and between any frame and step (0.1234 s,
// 0.4321 s), an impulse at 0.95 s, and loads that follow the moving surface.
Scene busy_scene(double fps, double step) {
  Scene s;
  s.duration = 1.5;
  s.fps = fps;
  s.step = step;
  s.forces.push_back(force(5.0, 0.3, Vec3(1, 3, 0.5), 1.0 / 6, 2.0 / 3, kRotational | kRadial));
  s.forces.push_back(force(3.0, 1.9, Vec3(-2, 0.5, 1), 0.1234, 0.4321, kPositional | kRotational));
  s.forces.push_back(force(4.5, 0.0, Vec3(0, 0, 0.7), 0.95, 0.95, kRotational));
  return s;
}

// Poses at every frame, keyed by the frame's time in units of 1/720 s (a multiple of 1/24, 1/30,
// 1/60 and 1/144 s is an integer there).
std::map<long long, std::vector<double>> bake(const Rig& rig, const Scene& scene) {
  Simulator sim(rig, scene);
  std::map<long long, std::vector<double>> out;
  const long long per_frame = std::llround(720 / scene.fps);
  out[0] = pose(sim.sweep(0));
  for (int k = 1; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    out[k * per_frame] = pose(sim.sweep(0));
  }
  return out;
}

TEST(Clock, AnyFrameRateGivesTheSamePoseAtEverySharedTime) {
  const Rig rig = bent_rig();
  const double length = rig.sweeps[0].rest.length();
  const double step = 1.0 / 700;  // divides none of the frame intervals
  const auto ref = bake(rig, busy_scene(144, step));
  int shared = 0;
  double moved = 0;
  for (double fps : {24.0, 30.0, 60.0}) {
    const auto poses = bake(rig, busy_scene(fps, step));
    for (const auto& [time, p] : poses) {
      const auto it = ref.find(time);
      if (it == ref.end()) continue;
      ++shared;
      moved = std::max(moved, max_difference(p, ref.at(0)));
      ASSERT_LE(max_difference(p, it->second), 1e-9 * length) << fps << " fps, t = " << time / 720.0;
    }
  }
  EXPECT_GE(shared, 3 * 9);  // every 1/6 s at least, switching times 1/6 and 2/3 s among them
  EXPECT_GT(moved, 1e-3 * length);
}

TEST(Clock, ForcesSwitchExactlyAtTheirTimesWhateverTheStep) {
  // Positional and radial loads do not depend on the pose, so the exact integrator must give the
  // same motion at any step — but only if a force switching between two internal times switches
  // there, not at the nearest step boundary.
  const Rig rig = bent_rig();
  auto scene = [](double step) {
    Scene s;
    s.duration = 1.0;
    s.fps = 30;
    s.step = step;
    s.forces.push_back(force(3.7, 0.4, Vec3(-1, 3, 0.5), 0.1234, 0.4321, kPositional | kRadial));
    return s;
  };
  const auto a = bake(rig, scene(1.0 / 90)), b = bake(rig, scene(1.0 / 1001));
  for (const auto& [time, p] : a) ASSERT_LE(max_difference(p, b.at(time)), 1e-12) << time / 720.0;
  EXPECT_GT(max_difference(a.at(720 / 2), a.at(0)), 1e-3);
}

TEST(Clock, SubstepsWithoutAStepKeepTheirMeaningAndTheDefaultStepIsUsedOtherwise) {
  Scene s;
  s.fps = 24;
  EXPECT_DOUBLE_EQ(s.step_seconds(), Scene::kDefaultStep);
  s.substeps = 4;
  EXPECT_DOUBLE_EQ(s.step_seconds(), 1.0 / 96);
  s.step = 0.002;
  EXPECT_DOUBLE_EQ(s.step_seconds(), 0.002);
}

TEST(Clock, InternalStepsDoNotDependOnTheFrameRate) {
  // 1 s at 144 fps or 24 fps: the same number of internal steps (plus one partial step per frame
  // between them, on a copy, which does not count).
  const Rig rig = bent_rig();
  long long steps[2];
  int r = 0;
  for (double fps : {144.0, 24.0}) {
    Scene s;
    s.duration = 1.0;
    s.fps = fps;
    s.step = 1.0 / 700;
    s.forces.push_back(force(5.0, 0.3, Vec3(1, 3, 0.5), 0.0, 1.0, kRotational));
    Simulator sim(rig, s, {.enabled = false});
    for (int k = 1; k < s.frame_count(); ++k) sim.advance_frame();
    steps[r++] = sim.steps_taken(0);
  }
  EXPECT_EQ(steps[0], 700);
  EXPECT_EQ(steps[1], 700);
}

}  // namespace
}  // namespace sweep::sim
