// Colliders' friction (issue 16) against Coulomb's law: a straight stiff tube sags onto the ground
// under its weight, its tip alone resting there, while the body carries its root sideways at a
// constant speed; once the tip slides steadily it is dragged back by μN, N the tip's support, and
// lags by μN L³/3EI (closed forms below; tests/core/beam_test.cpp checks the chain against
// FL³/3EI and wL⁴/8EI within 1% at K = 32).
//
// Red before the position-level stick (contact_stick.cpp): the velocity-level friction held a
// stiff part only for the step it kicked it. Measured then (default step 1/480 s): μ = 0.05 lagged
// 2.484 mm against the closed form's 2.507 mm (−0.9%), but every μ ≥ 0.1 lagged 3.050 mm, the drag
// m_eff·v/dt rather than μN, and step-dependent (μ = 0.2: 0.73 mm at 1/120 s, 6.67 mm at 1/960 s).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/beam_tubes.h"
#include "sim/simulator.h"

namespace sweep::sim {
namespace {

using test::beam::kRadius;
using test::beam::kScale;

constexpr double kG = 9.81;          // m/s²
constexpr double kStiff = 2e9;      // Pa: lags of at most ~1.5% of the length at μ = 0.4 (small deflection)
constexpr double kSpeed = 0.5;       // the body's speed along +x, mesh units/s (5 cm/s)
constexpr double kSettled = 2.0;     // s: the first bending mode (~12 rad/s, ζ = 0.5) has decayed to e^-12
constexpr double kDuration = 2.5;    // s: the steady lag is the mean over [kSettled, kDuration]

SweepDef stiff_tube() {
  SweepDef def = test::beam::tube(kRadius, kRadius, 0.5);
  def.name = "tube";
  for (Material& m : def.section_materials) m.youngs_modulus = kStiff;
  def.material->youngs_modulus = kStiff;
  return def;
}

struct Drag {
  double steady = 0;  // the tip's mean lag behind its rest place (−x), metres, once sliding steadily
  double spread = 0;  // its largest departure from that mean over the same frames, metres
};

// The floor, kDrop below the tube's rest surface: the tube sags under its weight onto it, its tip
// alone resting there (a cantilever propped at its tip, whose lowest point the tip stays while
// the prop takes less than wL/3: here 3wL/16).
double drop_m(const SweepDef& def);
Collider ground(const SweepDef& def) {
  return Collider::plane(Vec3(0, -kRadius - drop_m(def) / kScale, 0), Vec3(0, 1, 0));
}

// The tube lies on a floor touching its rest surface (its weight held by the floor, not by its
// bending: gravity unloaded, so the floor takes it from the first step), the body glides along +x.
Drag drag(const Rig& rig, double mu, double fps, double step = 0) {
  Scene scene;
  scene.duration = kDuration;
  scene.fps = fps;
  scene.step = step;
  scene.gravity = Vec3(0, -kG, 0);
  scene.gravity_preloaded = false;
  scene.body = BodyPath({{0, Vec3::Zero(), Quat::Identity()}, {100, Vec3(100 * kSpeed, 0, 0), Quat::Identity()}},
                        BodyInterpolation::linear);
  Collider floor = ground(rig.sweeps[0]);
  floor.friction = mu;
  scene.colliders = {floor};
  Simulator sim(rig, scene);
  std::vector<double> lags;
  for (int k = 1; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    if (k / fps >= kSettled) lags.push_back(-kScale * sim.sweep(0).deformed().frames.back().center.x());
  }
  Drag out;
  for (const double l : lags) out.steady += l / static_cast<double>(lags.size());
  for (const double l : lags) out.spread = std::max(out.spread, std::abs(l - out.steady));
  return out;
}

// The tip's free sag under its weight, w L⁴ / 8EI (w = ρ A g; the 32-gon's A and I, as the chain
// has them), metres; the floor is half of it below the rest surface.
double free_sag(const SweepDef& def) {
  const SectionProperties p = test::beam::props_of(def);
  return def.material->density * p.area * kG * std::pow(test::beam::length_m(def), 4) / (8 * kStiff * p.i_xx);
}
double drop_m(const SweepDef& def) { return 0.5 * free_sag(def); }

// The floor holds the tip up by (sag − drop), so it presses it with N = 3EI/L³ (sag − drop); sliding,
// the tip is dragged back by μN, and a tip load F moves the tip by FL³/3EI: it lags μ (sag − drop).
double coulomb_lag(const SweepDef& def, double mu) { return mu * (free_sag(def) - drop_m(def)); }

TEST(ContactFriction, ASlidingPartLagsByItsKineticDragMuTimesItsWeight) {
  Rig rig;
  rig.sweeps.push_back(stiff_tube());
  const SweepDef& def = rig.sweeps[0];
  EXPECT_LT(drag(rig, 0, 24).steady, 1e-9) << "no friction, no drag";
  const double mus[] = {0.05, 0.1, 0.2, 0.4};
  double lag[4];
  for (int i = 0; i < 4; ++i) {
    const Drag d = drag(rig, mus[i], 24);
    lag[i] = d.steady;
    const double expected = coulomb_lag(def, mus[i]);
    std::printf("mu %.2f: steady lag %.6g m (spread %.2g), closed form %.6g m (%+.2f%%)\n", mus[i], d.steady, d.spread,
                expected, 100 * (d.steady / expected - 1));
    // Steady: the lag is still (the frames after kSettled within 1% of it).
    EXPECT_LT(d.spread, 0.01 * d.steady) << "mu " << mus[i];
    // The closed form within 3%: it is the difference of two deflections the chain gets within 1%
    // each (wL⁴/8EI and FL³/3EI at K = 32), the sag of 3% of the length adds its geometric
    // nonlinearity (~(δ/L)² ≈ 0.1%), and the tip's contact station sits a radius above its support.
    EXPECT_NEAR(d.steady / expected, 1.0, 0.03) << "mu " << mus[i];
  }
  // Coulomb: linear in μ (the ratios within 1%, tighter than either's distance to the closed form).
  for (int i = 1; i < 4; ++i) {
    EXPECT_NEAR((lag[i] / lag[0]) / (mus[i] / mus[0]), 1.0, 0.01) << "mu " << mus[i] << " against " << mus[0];
  }
}

TEST(ContactFriction, TheDragIsTheSameAtEveryFrameRateAndStep) {
  Rig rig;
  rig.sweeps.push_back(stiff_tube());
  const double mu = 0.2;
  const double at24 = drag(rig, mu, 24).steady;
  // Frames are partial steps from the internal clock: the steady lag read at 144 fps is the same
  // state sampled more often (the mean over more frames of a still pose).
  EXPECT_NEAR(drag(rig, mu, 144).steady / at24, 1.0, 1e-3);
  // The internal step itself: the drag per step is μ N dt with N dt the step's normal impulse, so
  // a step 4× longer or 2× shorter gives the same force (within 1%).
  for (const double step : {1.0 / 120, 1.0 / 960}) {
    const double lag = drag(rig, mu, 24, step).steady;
    std::printf("step %.5g s: steady lag %.6g m (default step %.6g m)\n", step, lag, at24);
    EXPECT_NEAR(lag / at24, 1.0, 0.01) << "step " << step;
  }
}

// Static friction, Coulomb's other half: the tip resting on the floor (settled for 1 s, the body
// still), the body then moves 5 mm along +x in 0.1 s and stops. Sliding would take a lag of
// μN L³/3EI (19.9 mm at μ = 0.4, the test above), so the springs' force at 5 mm stays inside the
// cone: the tip does not move on the floor at all, its lag grows by exactly the body's travel and
// stays so (no creep), at every step.
TEST(ContactFriction, AStuckTipStaysWhereItRestsWhileTheBodyMovesLessThanItsSlide) {
  Rig rig;
  rig.sweeps.push_back(stiff_tube());
  constexpr double kTravel = 0.05;  // mesh units: 5 mm
  for (const double step : {0.0, 1.0 / 120, 1.0 / 960}) {
    Scene scene;
    scene.duration = 3;
    scene.fps = 24;
    scene.step = step;
    scene.gravity = Vec3(0, -kG, 0);
    scene.gravity_preloaded = false;
    scene.body = BodyPath({{0, Vec3::Zero(), Quat::Identity()},
                           {1.0, Vec3::Zero(), Quat::Identity()},
                           {1.1, Vec3(kTravel, 0, 0), Quat::Identity()},
                           {100, Vec3(kTravel, 0, 0), Quat::Identity()}},
                          BodyInterpolation::linear);
    Collider floor = ground(rig.sweeps[0]);
    floor.friction = 0.4;
    scene.colliders = {floor};
    Simulator sim(rig, scene);
    double rest = 0, worst = 0;
    for (int k = 1; k < scene.frame_count(); ++k) {
      sim.advance_frame();
      const double tip = sim.sweep(0).deformed().frames.back().center.x();  // mesh units, body frame
      if (k == 24) rest = tip;                                                // t = 1 s, body at 0
      if (k >= 30) worst = std::max(worst, std::abs((tip + kTravel) - rest));  // world x against t = 1 s
    }
    std::printf("step %.5g s: tip %.3g units off where it rested (travel %.3g)\n", step, worst, kTravel);
    // Held on positions, a station ends each step on its anchor to the linear model's error (the
    // solver's rows re-measured next step, never accumulated): within 1% of the travel.
    EXPECT_LT(worst, 0.01 * kTravel) << "step " << step;
  }
}

// The stick anchors carry from step to step; the frame view's partial step (25 fps on a 1/480 s
// step grid: 19.2 steps a frame) must not move them. A tube the body drags over the floor, sliding
// and sticking, is in the same state at t = 1 s (frame 24 at 24 fps, frame 25 at 25 fps, on the
// grid for both) to the bit.
TEST(ContactFriction, TheOutputFrameRateDoesNotChangeTheMotion) {
  Rig rig;
  rig.sweeps.push_back(stiff_tube());
  const auto state_at_one_second = [&](double fps) {
    Scene scene;
    scene.duration = 1.2;
    scene.fps = fps;
    scene.step = 1.0 / 480;
    scene.gravity = Vec3(0, -kG, 0);
    scene.gravity_preloaded = false;
    const std::vector<BodyKey> keys = {{0, Vec3::Zero(), Quat::Identity()},
                                 {0.3, Vec3::Zero(), Quat::Identity()},
                                 {0.6, Vec3(0.3, 0, 0), Quat::Identity()},
                                 {0.8, Vec3(0.32, 0, 0.05), Quat::Identity()},
                                 {100, Vec3(0.32, 0, 0.05), Quat::Identity()}};
    scene.body = BodyPath(keys, BodyInterpolation::linear);
    Collider floor = ground(rig.sweeps[0]);
    floor.friction = 0.3;
    scene.colliders = {floor};
    Simulator sim(rig, scene);
    const int frames = static_cast<int>(std::lround(fps));
    for (int k = 1; k <= frames; ++k) sim.advance_frame();
    std::vector<double> out;
    for (const Frame& f : sim.sweep(0).deformed().frames) out.insert(out.end(), f.center.data(), f.center.data() + 3);
    return out;
  };
  const std::vector<double> a = state_at_one_second(24), b = state_at_one_second(25);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k], b[k]) << "coordinate " << k;
}

}  // namespace
}  // namespace sweep::sim

namespace sweep::sim {
namespace {

// Not a check: BENCHMARKS.md's lag-against-μ table, in Contact.FrictionDragsAPartTheBodyPullsOverTheGround's
// scene (the largest lag of the tip over 2 s, mesh units, and the lags at 1 s and 2 s: a tip
// stuck to the floor lags 1 unit more at 2 s, the body's travel in between).
TEST(ContactFriction, DISABLED_LagAgainstMuTable) {
  Rig rig;
  rig.sweeps.push_back(test::beam::tube(kRadius, kRadius, 0.2, 12));
  rig.sweeps[0].name = "tube";
  for (Material& m : rig.sweeps[0].section_materials) m.youngs_modulus = 2e8;
  rig.sweeps[0].material->youngs_modulus = 2e8;
  for (const double mu : {0.0, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0, 4.0}) {
    Scene scene;
    scene.duration = 2;
    scene.fps = 30;
    scene.gravity = Vec3(0, -kG, 0);
    scene.gravity_preloaded = false;
    scene.body = BodyPath({{0, Vec3::Zero(), Quat::Identity()}, {10, Vec3(10, 0, 0), Quat::Identity()}},
                          BodyInterpolation::linear);
    Collider floor = Collider::plane(Vec3(0, -kRadius - 0.3, 0), Vec3(0, 1, 0));
    floor.friction = mu;
    scene.colliders = {floor};
    Simulator sim(rig, scene);
    double most = 0, last = 0, at_one = 0;
    for (int k = 1; k < scene.frame_count(); ++k) {
      sim.advance_frame();
      last = -sim.sweep(0).deformed().frames.back().center.x();
      most = std::max(most, last);
      if (k == 30) at_one = last;
    }
    std::printf("mu %g: largest lag %.4f, at 1 s %.4f, at 2 s %.4f\n", mu, most, at_one, last);
  }
}

}  // namespace
}  // namespace sweep::sim
