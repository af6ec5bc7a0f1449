// A material part whose fast modes are taken quasi-statically (ElasticSweep::set_moving_modes, the
// mode-acceleration method): with every mode moving it is the step it always was; truncated, it
// settles to the full modes' shape (the static correction K⁻¹ τ − Φ_m Ω_m⁻² Φ_mᵀ τ is exact for a
// settled part) and, under a walking body's bob and sway at the live step, stays closer to the full
// modes than the full modes at that step stay to a fine step.
#include <gtest/gtest.h>

#include <cmath>

#include "beam_tubes.h"
#include "sweep/core/elastic_sweep.h"

namespace sweep {
namespace {

// The 3.1 m tube of beam_tubes.h, K = 32, stiffened to 1 GPa: first sway 1.4 Hz (the diplodocus
// tail's is 2.2 Hz), 93 modes up to the twist's hundreds of Hz.
SweepDef stiff_truncation_tube(double damping_ratio) {
  SweepDef def = test::beam::tube(test::beam::kRadius, test::beam::kRadius, damping_ratio);
  test::beam::set_youngs_modulus(def, 1e9);
  return def;
}

// The largest distance between the two sweeps' section centres, and the largest angle between
// their sections' frames (radians).
double largest_centre_gap(const ElasticSweep& a, const ElasticSweep& b) {
  double gap = 0;
  for (std::size_t i = 0; i < a.deformed().frames.size(); ++i)
    gap = std::max(gap, (a.deformed().frames[i].center - b.deformed().frames[i].center).norm());
  return gap;
}
double largest_frame_angle(const ElasticSweep& a, const ElasticSweep& b) {
  double angle = 0;
  for (std::size_t i = 0; i < a.deformed().frames.size(); ++i)
    angle = std::max(angle, a.deformed().frames[i].rotation.angularDistance(b.deformed().frames[i].rotation));
  return angle;
}

// A held force at the middle of the tube, across it, following the surface (split anew each step).
ForceSpec held_side_push() {
  ForceSpec f;
  f.t = 0.5 * test::beam::kLengthUnits;
  f.vector = Vec3(40, 0, 0);
  f.components = kRotational;
  f.target = RotationTarget::chain;
  f.moment = MomentModel::physical;
  return f;
}

// A walking body at time t: a vertical bob of 4 cm at 2 Hz and a sway of 0.1 rad about the vertical
// at 1 Hz (the accelerations the part feels; mesh units of 0.1 m).
ElasticSweep::BodyMotion walking_bob(double t, const Vec3& gravity) {
  const double bob = 2 * test::beam::kPi * 2, sway = 2 * test::beam::kPi * 1;
  ElasticSweep::BodyMotion m;
  m.acceleration = Vec3(0, -0.4 * bob * bob * std::sin(bob * t), 0);
  m.angular_velocity = Vec3(0, 0.1 * sway * std::cos(sway * t), 0);
  m.angular_acceleration = Vec3(0, -0.1 * sway * sway * std::sin(sway * t), 0);
  m.gravity = gravity;
  return m;
}

TEST(TruncatedModes, AllModesMovingIsTheStepAsItWas) {
  const SweepDef def = stiff_truncation_tube(0.1);
  ElasticSweep untouched(def), restored(def);
  const int all = 3 * untouched.chain()->joints;
  EXPECT_EQ(untouched.moving_modes(), all);
  restored.set_moving_modes(4);
  EXPECT_EQ(restored.moving_modes(), 4);
  restored.set_moving_modes(all + 10);  // clamped to every mode
  EXPECT_EQ(restored.moving_modes(), all);
  const Vec3 g(0, -9.81, 0);
  for (ElasticSweep* s : {&untouched, &restored}) {
    s->set_dynamics(ElasticSweep::Dynamics::modal);
    s->set_gravity(g);
    s->add_force(held_side_push());
  }
  for (int k = 0; k < 60; ++k) {
    untouched.set_body_motion(walking_bob((k + 0.5) / 60, g));
    restored.set_body_motion(walking_bob((k + 0.5) / 60, g));
    untouched.step(1.0 / 60);
    restored.step(1.0 / 60);
  }
  int differ = 0;
  for (int i = 1; i < def.rest.section_count(); ++i)
    differ += untouched.rotation_vector(i) != restored.rotation_vector(i);
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(untouched.energy(), restored.energy());
  const double tip = (untouched.deformed().frames.back().center - def.rest.frames.back().center).norm();
  EXPECT_GT(tip, 1e-3 * def.rest.length());  // it did move
}

TEST(TruncatedModes, TheModesAStepResolvesAreThoseOfAtMostAPeriodAStep) {
  const ElasticSweep sweep(stiff_truncation_tube(0.1));
  const ChainModel& chain = *sweep.chain();
  const double step = 1.0 / 60, bound = ElasticSweep::kResolvedModeBound;
  const int kept = ElasticSweep::resolved_modes(chain, step, bound);
  ASSERT_GT(kept, 1);
  ASSERT_LT(kept, 3 * chain.joints);
  EXPECT_LE(std::sqrt(chain.omega2[kept - 1]) * step, bound);
  EXPECT_GT(std::sqrt(chain.omega2[kept]) * step, bound);
  // A step fine enough resolves them all; one too coarse for any still moves the slowest.
  EXPECT_EQ(ElasticSweep::resolved_modes(chain, 1e-6, bound), 3 * chain.joints);
  EXPECT_EQ(ElasticSweep::resolved_modes(chain, 100.0, bound), 1);
}

TEST(TruncatedModes, ASettledPartTakesTheFullModesShapeUnderGravityAndAHeldForce) {
  // Critically damped, starting unloaded: the part sags under its weight and a held push at its
  // middle that follows the surface, then settles (q = K⁻¹ τ(q), whatever the modes that move).
  const SweepDef def = stiff_truncation_tube(1.0);
  ElasticSweep full(def), resolved(def), slowest(def);
  resolved.set_moving_modes(ElasticSweep::resolved_modes(*full.chain(), 1.0 / 60, ElasticSweep::kResolvedModeBound));
  slowest.set_moving_modes(1);
  for (ElasticSweep* s : {&full, &resolved, &slowest}) {
    s->set_dynamics(ElasticSweep::Dynamics::modal);
    s->set_gravity(Vec3(0, -9.81, 0), false);
    s->add_force(held_side_push());
    for (int k = 0; k < 600; ++k) s->step(1.0 / 60);  // 10 s: 88 of the slowest mode's time constants
  }
  const double length = def.rest.length();
  const double sag = (full.deformed().frames.back().center - def.rest.frames.back().center).norm();
  EXPECT_GT(sag, 1e-3 * length);  // a settled shape far from the rest pose
  EXPECT_LT(full.max_speed(), 1e-12);
  for (const ElasticSweep* s : {&resolved, &slowest}) {
    EXPECT_LE(largest_centre_gap(*s, full), 1e-9 * length) << s->moving_modes() << " modes";
    EXPECT_LE(largest_frame_angle(*s, full), 1e-9) << s->moving_modes() << " modes";
    // The energy of the settled joints: the kept modes' ½ ω² η² and the dropped ones' static share.
    EXPECT_NEAR(s->energy(), full.energy(), 1e-9 * full.energy()) << s->moving_modes() << " modes";
  }
}

TEST(TruncatedModes, UnderAWalkingBodyTheResolvedModesStayCloserToTheFullModesThanTheStepToAFineOne) {
  // ζ = 0.1 as the diplodocus flesh, gravity pre-loaded, the body bobbing and swaying for 3 s.
  // At the live step (1/60 s) the full modes stray from a 16 times finer step by the step's own
  // error; the resolved modes (ω·h ≤ 2π, the faster ones quasi-static) must stray from the full
  // modes at that step by less: dropping what the step cannot resolve costs less than the step.
  const SweepDef def = stiff_truncation_tube(0.1);
  ElasticSweep full(def), resolved(def), fine(def);
  resolved.set_moving_modes(ElasticSweep::resolved_modes(*full.chain(), 1.0 / 60, ElasticSweep::kResolvedModeBound));
  const Vec3 g(0, -9.81, 0);
  for (ElasticSweep* s : {&full, &resolved, &fine}) {
    s->set_dynamics(ElasticSweep::Dynamics::modal);
    s->set_gravity(g);
  }
  constexpr int kFine = 16;
  double truncation = 0, step_error = 0, motion = 0;
  for (int k = 0; k < 180; ++k) {
    const double t = k / 60.0;
    for (ElasticSweep* s : {&full, &resolved}) {
      s->set_body_motion(walking_bob(t + 0.5 / 60, g));
      s->step(1.0 / 60);
    }
    for (int j = 0; j < kFine; ++j) {
      fine.set_body_motion(walking_bob(t + (j + 0.5) / (60.0 * kFine), g));
      fine.step(1.0 / (60 * kFine));
    }
    truncation = std::max(truncation, largest_centre_gap(resolved, full));
    step_error = std::max(step_error, largest_centre_gap(full, fine));
    motion = std::max(motion, (fine.deformed().frames.back().center - def.rest.frames.back().center).norm());
  }
  const double length = def.rest.length();
  EXPECT_GT(motion, 1e-2 * length);  // the tip swung
  EXPECT_LT(truncation, step_error) << "truncation " << truncation / length << " of the length, the step's error "
                                    << step_error / length;
  RecordProperty("truncation_over_length", std::to_string(truncation / length));
  RecordProperty("step_error_over_length", std::to_string(step_error / length));
}

}  // namespace
}  // namespace sweep
