// The runtime's per-frame work allocates nothing after the first frame: a game's loop — the body's
// pose given live (set_body_pose), advance_to, the fast deformation of the bound vertices — runs
// over many frames without one call of operator new or malloc, on any thread. Its own executable
// (test_sim_allocation): the counting allocator (tests/allocation_counter.cpp) replaces the global
// one for the whole process.
//
// Adding a force (add_force) may allocate — the scene's force list and each sweep's list of the
// forces acting on it grow — so the forces are given before the counted frames; the frames that
// then play them (a held one, an impulse switched on between internal steps) are counted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <vector>

#include "allocation_counter.h"
#include "bind/support.h"
#include "sweep/bind/fast_deform.h"
#include "sweep/sim/simulator.h"

namespace sweep::sim {
namespace {

struct Part {
  Mesh mesh;
  Rig rig;
  bind::Binding binding;
  std::vector<bind::Vec3f> rest;
};

// The generated straight tube (41 rings of 24 vertices, capped) bound to its hand-made sweep; in
// material mode, a soft rubber one hanging from a body that moves.
Part tube_part(bool material) {
  Part p;
  p.mesh = tube::make_tube(test::straight_tube_params());
  SweepDef sweep = test::straight_sweep();
  if (material) {
    Material m;
    m.youngs_modulus = 2e5;
    m.metres_per_unit = 0.1;
    sweep.material = m;
    sweep.section_materials.assign(sweep.rest.section_count(), m);
  }
  p.rig = test::rig_of({sweep});
  p.binding = bind::bind_rig(p.rig, p.mesh, {.blend = 0.05});
  p.rest.resize(p.mesh.vertex_count());
  for (std::size_t v = 0; v < p.rest.size(); ++v) p.rest[v] = p.mesh.positions[v].cast<float>();
  return p;
}

SceneForce force_at_tip(const Rig& rig, double start, double end, const Vec3& v) {
  SceneForce f;
  f.sweep = rig.sweeps[0].name;
  f.sweep_index = 0;
  f.spec.t = 0.9 * rig.sweeps[0].rest.length();
  f.spec.vector = v;
  f.spec.components = kRotational | kRadial | kPositional;
  f.spec.target = RotationTarget::chain;
  f.start = start;
  f.end = end;
  return f;
}

// The end of frame k ≥ 1: frames of 1/60, 1/144 and 1/30 s in turn, as a game's frame times vary.
double frame_end(int k) {
  const double slices[] = {1.0 / 60, 1.0 / 144, 1.0 / 30};
  double t = 0;
  for (int j = 0; j < k; ++j) t += slices[j % 3];
  return t;
}

// The body at time t: swaying about y and walking along a circle.
BodyState body_at(double t) {
  BodyState b;
  b.rotation = Quat(Eigen::AngleAxisd(0.6 * std::sin(std::numbers::pi * t), Vec3::UnitY()));
  b.translation = Vec3(0.3 * std::sin(2 * std::numbers::pi * t), 0.1 * t, 0.3 * std::cos(2 * std::numbers::pi * t));
  return b;
}

struct LoopResult {
  test::AllocationCounts counts;
  int counted_frames = 0;
  int moved_frames = 0;     // frames in which the part's shape changed (it was re-deformed)
  double largest_bend = 0;  // largest distance of a vertex from its rest position (mesh space)
};

// A game's loop on `part`: a held force and an impulse given before frame 1 (the warm-up frame),
// then `frames` frames counted, each giving the body's pose (and, with `gravity`, the gravity —
// a ship turning — every frame), advancing, and deforming what moved.
LoopResult run_loop(const Part& part, bool gravity, int frames) {
  Simulator sim(part.rig, Scene{});
  bind::FastDeformer fast(part.rig.sweeps[0].rest, part.binding.sweeps[0], part.rest);
  std::vector<bind::Vec3f> positions = part.rest;
  std::vector<bind::DeformJob> jobs;
  jobs.reserve(1);
  const double length = part.rig.sweeps[0].rest.length();
  sim.add_force(force_at_tip(part.rig, 0, 100, Vec3(0.2, 0.1, 0.05)));
  sim.add_force(force_at_tip(part.rig, 0.3 + 1.0 / 1000, 0.3 + 1.0 / 1000, Vec3(0, 0.3, 0.1)));
  const auto frame = [&](int k) {
    const double t = frame_end(k);
    const BodyState b = body_at(t);
    sim.set_body_pose(b.rotation, b.translation);
    if (gravity) sim.set_gravity(Vec3(0.5 * std::sin(t), -9.81, 0));
    sim.advance_to(t);
    jobs.clear();
    if (sim.moved_last_frame(0)) jobs.push_back({&fast, &sim.sweep(0).deformed()});
    bind::deform_sweeps(jobs, positions);
  };
  frame(1);  // the warm-up frame: it may allocate (first use of scratch, the threads' team)
  LoopResult r;
  test::open_allocation_window();
  for (int k = 2; k < 2 + frames; ++k) {
    frame(k);
    ++r.counted_frames;
    r.moved_frames += jobs.size() == 1;
    for (std::size_t v = 0; v < positions.size(); ++v)
      r.largest_bend = std::max(r.largest_bend, double((positions[v] - part.rest[v]).norm()) / length);
  }
  r.counts = test::close_allocation_window();
  return r;
}

constexpr const char* kSanitizerSkip =
    "AddressSanitizer replaces operator new and malloc: allocations are not counted in this build";

TEST(Allocation, PaperSpringsLoopAllocatesNothingAfterTheFirstFrame) {
  if (!test::kCounts) GTEST_SKIP() << kSanitizerSkip;
  const LoopResult r = run_loop(tube_part(false), false, 300);
  EXPECT_EQ(r.counts.news, 0);
  EXPECT_EQ(r.counts.mallocs, 0);
  // What was counted is real work: the part moved and was deformed in every frame, visibly.
  EXPECT_EQ(r.moved_frames, r.counted_frames);
  EXPECT_GT(r.largest_bend, 0.01);
}

TEST(Allocation, MaterialModeLoopWithGravityAllocatesNothingAfterTheFirstFrame) {
  if (!test::kCounts) GTEST_SKIP() << kSanitizerSkip;
  const LoopResult r = run_loop(tube_part(true), true, 300);
  EXPECT_EQ(r.counts.news, 0);
  EXPECT_EQ(r.counts.mallocs, 0);
  EXPECT_EQ(r.moved_frames, r.counted_frames);
  EXPECT_GT(r.largest_bend, 0.01);
}

// The geometrically exact chain's steps (ElasticSweep::set_exact_chain): Newton iterations, its
// factorizations, the halved steps of a fast turn, impulses (the articulated-body solve) and the
// body's kicks — none allocates after the first step.
TEST(Allocation, TheExactChainsStepsAndKicksAllocateNothingAfterTheFirstStep) {
  if (!test::kCounts) GTEST_SKIP() << kSanitizerSkip;
  SweepDef def = test::straight_sweep();
  Material m;
  m.youngs_modulus = 2e5;
  m.metres_per_unit = 0.1;
  def.material = m;
  def.section_materials.assign(def.rest.section_count(), m);
  ElasticSweep sweep(def);
  sweep.set_exact_chain(true);
  sweep.set_gravity(Vec3(0, -9.81, 0), false);
  ForceSpec f;
  f.t = 0.9 * sweep.rest().length();
  f.vector = Vec3(0.2, 0.1, 0.05);
  f.components = kRotational | kRadial | kPositional;
  f.target = RotationTarget::chain;
  sweep.add_force(f);
  ForceSpec kick = f;
  kick.vector = Vec3(0, 0.05, 0.02);
  ElasticSweep::BodyMotion body;
  body.gravity = Vec3(0, -9.81, 0);
  sweep.set_body_motion(body);
  sweep.step(1.0 / 480);  // the warm-up step
  ASSERT_TRUE(sweep.exact_chain());
  test::open_allocation_window();
  for (int k = 0; k < 240; ++k) {
    body.angular_velocity = Vec3(0, 6 * std::sin(0.05 * k), 0);
    body.angular_acceleration = Vec3(0, 144 * std::cos(0.05 * k), 0);  // d/dt of the above at 480 steps/s
    sweep.set_body_motion(body);
    if (k == 100) sweep.apply_impulse(kick);
    if (k == 150) sweep.apply_body_kick(Vec3(0.1, 0, 0), Vec3(0, 0.5, 0));
    sweep.step(k % 3 ? 1.0 / 480 : 1.0 / 120);
  }
  const test::AllocationCounts counts = test::close_allocation_window();
  EXPECT_EQ(counts.news, 0);
  EXPECT_EQ(counts.mallocs, 0);
  EXPECT_TRUE(sweep.is_finite());
  EXPECT_GT(sweep.exact_chain_state()->iterations(), 240);  // it did step
}

// The counter counts: an allocation inside the window is seen, one outside it is not.
TEST(Allocation, TheCounterSeesAnAllocation) {
  if (!test::kCounts) GTEST_SKIP() << kSanitizerSkip;
  auto* before = new std::vector<double>(100);
  test::open_allocation_window();
  auto* inside = new std::vector<double>(100);              // the vector and its buffer: two news
  void* block = std::malloc(64);                            // and one malloc
  asm volatile("" : : "g"(inside), "g"(block) : "memory");  // kept: the compiler may not elide them
  const test::AllocationCounts counts = test::close_allocation_window();
  auto* after = new std::vector<double>(100);
  EXPECT_EQ(counts.news, 2);
  EXPECT_EQ(counts.mallocs, 1);
  std::free(block);
  delete before;
  delete inside;
  delete after;
}

}  // namespace
}  // namespace sweep::sim
