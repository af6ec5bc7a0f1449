// Follower loads to second order: a force that follows the moving surface is
// re-split at the predicted mid-step pose, so halving the step quarters the error.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <vector>

#include "bind/support.h"
#include "core/sample_sweeps.h"
#include "diplodocus_seeds.h"
#include "sweep/io/scene_json.h"
#include "sweep/sim/simulator.h"

using sweep::io::read_scene;

namespace sweep::sim {
namespace {

// Largest difference between two runs' section poses: centres and radii (mesh units), rotations
// as the angle times the length (how far they move the tip).
double pose_difference(const ElasticSweep& a, const ElasticSweep& b) {
  const double len = a.rest().length();
  double d = 0;
  for (int i = 0; i < a.rest().section_count(); ++i) {
    const Frame& fa = a.deformed().frames[i];
    const Frame& fb = b.deformed().frames[i];
    d = std::max({d, (fa.center - fb.center).norm(), len * fa.rotation.angularDistance(fb.rotation)});
  }
  for (std::size_t m = 0; m < a.deformed().radii.size(); ++m)
    d = std::max(d, std::abs(a.deformed().radii[m] - b.deformed().radii[m]));
  return d;
}

// Largest pose difference over every frame and sweep, relative to each sweep's length.
double run_difference(const Rig& rig, Scene a, Scene b) {
  Simulator sa(rig, a, {.enabled = false}), sb(rig, b, {.enabled = false});
  double worst = 0;
  for (int k = 1; k < a.frame_count(); ++k) {
    sa.advance_frame();
    sb.advance_frame();
    for (int i = 0; i < sa.sweep_count(); ++i) {
      worst = std::max(worst, pose_difference(sa.sweep(i), sb.sweep(i)) / sa.sweep(i).rest().length());
    }
  }
  return worst;
}

// The same for several runs against one reference, stepped side by side.
std::vector<double> run_differences(const Rig& rig, const Scene& reference, const std::vector<Scene>& runs) {
  Simulator ref(rig, reference, {.enabled = false});
  std::vector<std::unique_ptr<Simulator>> sims;
  for (const Scene& s : runs) sims.push_back(std::make_unique<Simulator>(rig, s, SleepSettings{.enabled = false}));
  std::vector<double> worst(runs.size(), 0.0);
  for (int k = 1; k < reference.frame_count(); ++k) {
    ref.advance_frame();
    for (std::size_t r = 0; r < sims.size(); ++r) {
      sims[r]->advance_frame();
      for (int i = 0; i < ref.sweep_count(); ++i)
        worst[r] = std::max(worst[r], pose_difference(sims[r]->sweep(i), ref.sweep(i)) / ref.sweep(i).rest().length());
    }
  }
  return worst;
}

Scene oblique_push(double step) {
  Scene s;
  s.duration = 1.0;
  s.fps = 30;
  s.step = step;
  SceneForce f;
  f.sweep = "tail";
  f.sweep_index = 0;
  f.spec.t = 5.0;
  f.spec.theta = 0.4;
  f.spec.vector = Vec3(1, 3, 0.5);  // oblique: its split changes as the part bends
  f.spec.components = kRotational | kRadial;
  f.spec.target = RotationTarget::chain;
  f.start = 0;
  f.end = 0.6;
  s.forces.push_back(f);
  return s;
}

TEST(FollowerLoads, HalvingTheStepQuartersTheError) {
  Rig rig;
  rig.sweeps.push_back(test::sweep_def(test::irregular_shape(7, 8)));
  rig.sweeps.back().name = "tail";
  const double h = 1.0 / 60;
#if defined(SWEEP_SANITIZED)
  // Under the sanitizers (16 s with the finer one) a reference 64x finer than h: its own error,
  // 1/256 of the 1/240 s step's, moves the ratios below by under 0.03.
  const Scene reference = oblique_push(h / 64);
#else
  const Scene reference = oblique_push(h / 256);
#endif
  double e[3];
  for (int k = 0; k < 3; ++k) e[k] = run_difference(rig, oblique_push(h / (1 << k)), reference);
  std::printf("step 1/60 s: %.3g, 1/120 s: %.3g, 1/240 s: %.3g of the length\n", e[0], e[1], e[2]);
  EXPECT_GT(e[2], 0.0);
  // Second order: each halving divides the error by 4 (a first-order split would give 2).
  EXPECT_NEAR(e[0] / e[1], 4.0, 0.5);
  EXPECT_NEAR(e[1] / e[2], 4.0, 0.5);
}

// Against a step 16 times finer than 1/480 s: within 1e-5 of the length at 1/480 s, and within the
// bar the default step is chosen by (Scene::kDefaultStep: 1e-4 of the length) at the default.
TEST(FollowerLoads, DiplodocusFig4WithinATenThousandthOfTheLengthAtTheDefaultStep) {
  const test::Diplodocus* dino = test::diplodocus();
  if (dino == nullptr) GTEST_SKIP() << "CGAL's diplodocus is absent (tools/setup-deps.sh)";
  Scene fine = read_scene(std::filesystem::path(SWEEP_SOURCE_DIR) / "rigs/diplodocus-fig4.scene.json", dino->rig);
  fine.substeps = 0;
  fine.step = 1.0 / (16 * 480);
  std::vector<Scene> runs(3, fine);
  runs[0].step = 1.0 / 480;
  runs[1].step = 1.0 / 240;
  runs[2].step = 1.0 / 120;
  const std::vector<double> e = run_differences(dino->rig, fine, runs);
  std::printf(
      "diplodocus Fig. 4 from a step of 1/7680 s: %.3g of the length at 1/480 s, %.3g at 1/240 s, %.3g at "
      "1/120 s\n",
      e[0], e[1], e[2]);
  EXPECT_GT(e[0], 0.0);
  EXPECT_LE(e[0], 1e-5);
  for (std::size_t r = 0; r < runs.size(); ++r) {
    if (runs[r].step == Scene::kDefaultStep) {
      EXPECT_LE(e[r], 1e-4) << "the default step";
    }
  }
}

}  // namespace
}  // namespace sweep::sim

namespace sweep::sim {
namespace {

// Material mode on the diplodocus, in the same run as the paper's mode: cost of stepping a frame
// (tail + neck, Fig. 4 forces, default step) — printed for BENCHMARKS.md — and a sane motion.
TEST(MaterialMode, DiplodocusFig4CostAgainstThePapersModeInTheSameRun) {
  const test::Diplodocus* dino = test::diplodocus();
  if (dino == nullptr) GTEST_SKIP() << "CGAL's diplodocus is absent (tools/setup-deps.sh)";
  Rig material_rig = dino->rig;
  for (SweepDef& d : material_rig.sweeps) {
    d.material = test::diplodocus_flesh();
    d.section_materials.assign(d.rest.section_count(), *d.material);
  }
  Scene scene = read_scene(std::filesystem::path(SWEEP_SOURCE_DIR) / "rigs/diplodocus-fig4.scene.json", dino->rig);
  scene.substeps = 0;
  for (SceneForce& f : scene.forces) f.spec.moment = MomentModel::physical;
  Scene with_gravity = scene;
  with_gravity.gravity = Vec3(0, -9.81, 0);
  double seconds[2] = {0, 0};
  for (int rep = 0; rep < 3; ++rep) {
    for (int mode = 0; mode < 2; ++mode) {
      Simulator sim(mode ? material_rig : dino->rig, mode ? with_gravity : scene, {.enabled = false});
      const auto t0 = std::chrono::steady_clock::now();
      for (int k = 1; k < scene.frame_count(); ++k) sim.advance_frame();
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      seconds[mode] = rep == 0 ? s : std::min(seconds[mode], s);
      for (int i = 0; i < sim.sweep_count(); ++i) ASSERT_TRUE(sim.sweep(i).is_finite());
    }
  }
  const int frames = scene.frame_count() - 1;
  std::printf("diplodocus Fig. 4 stepping, per frame: paper %.1f us, material %.1f us (%.2fx); K = %d, %d\n",
              1e6 * seconds[0] / frames, 1e6 * seconds[1] / frames, seconds[1] / seconds[0],
              dino->rig.sweeps[0].rest.section_count(), dino->rig.sweeps[1].rest.section_count());
}

}  // namespace
}  // namespace sweep::sim
