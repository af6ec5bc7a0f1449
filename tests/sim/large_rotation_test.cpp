// Large rotations of a material part, through the simulator's own path (ElasticSweep in material
// mode, the geometrically exact chain): a 2 m tube of K = 32 sections, 5 cm in radius, ρ = 1100
// kg/m³ (its own weight β = q L³ / EI = 1.38e8 Pa / E: 138 at E = 1e6). Measured against what
// physics allows, never against the integrator's own bookkeeping: kinetic energies from the
// section centres' motion (central differences of the poses), gravity's work from their heights.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>

#include "core/beam_tubes.h"
#include "sweep/core/elastic_sweep.h"
#include "sweep/sim/simulator.h"
#include "test_constants.h"

namespace sweep::sim {
namespace {

using ::sweep::test::kG;  // m/s²
using ::sweep::test::kPi;
constexpr double kLengthUnits = 20;  // 2 m at the tubes' 0.1 m per unit

// The 2 m tube along z, straight or bent at rest into a quarter circle in the x–z plane.
SweepDef two_metre_tube(double youngs, double zeta, bool bent = false) {
  SweepDef def = test::beam::tube(test::beam::kRadius, test::beam::kRadius, zeta);
  test::beam::set_youngs_modulus(def, youngs);
  const int k = def.rest.section_count();
  const double radius = kLengthUnits / (kPi / 2);
  for (int i = 0; i < k; ++i) {
    const double s = kLengthUnits * i / (k - 1);
    def.rest.t[i] = s;
    if (bent) {
      const double a = s / radius;
      def.rest.frames[i].center = Vec3(radius * (1 - std::cos(a)), 0, radius * std::sin(a));
      def.rest.frames[i].rotation = Quat(Eigen::AngleAxisd(a, Vec3::UnitY()));
    } else {
      def.rest.frames[i].center = Vec3(0, 0, s);
    }
  }
  def.name = "tube";
  return def;
}

double length_m(const ElasticSweep& s) {
  return s.chain()->metres_per_unit * s.rest().length();
}

double total_mass(const ElasticSweep& s) {
  double m = 0;
  for (double x : s.chain()->node_mass) m += x;
  return m;
}

// Released level under gravity (not pre-loaded): the kinetic energy of the sections is at most
// what gravity's work gave them, and by symmetry the tube never leaves its vertical plane. Both
// measured on the joints' pose (exact_chain_state: the sections where the joints put them; the
// stiff stretch and shear springs ride on it as independent springs and are not part of this).
// The rest-pose modal step (set_exact_chain(false)), its joints measured the same way, breaks
// both: run alongside, it shows the test can fail.
TEST(LargeRotation, ASoftTubeReleasedLevelNeverOutrunsGravitysWorkAndStaysInItsPlane) {
  for (const bool exact : {true, false}) {
    ElasticSweep tube(two_metre_tube(1e6, 0.05));  // β = 138, the default damping
    tube.set_exact_chain(exact);
    tube.set_gravity(Vec3(0, -kG, 0), false);
    const double h = 1.0 / 480, l = length_m(tube), mgl = total_mass(tube) * kG * l;
    const std::vector<double>& mass = tube.chain()->node_mass;
    const std::vector<Vec3> start = tube.exact_chain_state()->centres();
    std::vector<Vec3> before = start, now = start;
    double worst = -1, off_plane = 0, lowest = 0;
    for (int s = 0; s < 480; ++s) {
      tube.step(h);
      const std::vector<Vec3> after = tube.exact_chain_state()->centres();
      if (s > 0) {
        double work = 0, kinetic = 0;
        for (std::size_t i = 1; i < now.size(); ++i) {
          work += mass[i] * kG * (start[i].y() - now[i].y());
          kinetic += 0.5 * mass[i] * ((after[i] - before[i]) / (2 * h)).squaredNorm();
        }
        worst = std::max(worst, (kinetic - work) / mgl);
      }
      for (const Vec3& c : after) off_plane = std::max(off_plane, std::abs(c.x()) / l);
      lowest = std::min(lowest, after.back().y() / l);
      before = now;
      now = after;
    }
    std::printf("released soft tube (%s): tip down to %.3f L, largest (KE - W)/(m g L) %.3g, off its plane %.3g L\n",
                exact ? "exact chain" : "rest-pose modes", lowest, worst, off_plane);
    if (exact) {
      EXPECT_LE(worst, 1e-4);  // the differences' own error is O(h²): far below
      EXPECT_LE(off_plane, 1e-9);
      EXPECT_LT(lowest, -0.5);  // it did fall
    } else {
      EXPECT_GT(worst, 0.1);  // the rest-pose modes gain energy
    }
  }
}

// The stability matrix: Young's modulus from a limp rope (1e4 Pa, β = 13800) to steel (1e11) ×
// internal steps from 1e-4 s to a frame (1/24 s), the exact chain through ElasticSweep. The body
// turns 90° about the vertical in 0.3 s (θ = 90° (3u² − 2u³)) with the tube level on it under
// gravity (not pre-loaded: it falls as it turns), then holds still. At every step: finite; relative to
// the body, the part's energy (kinetic, elastic, gravity's) never above the work the body's turn
// did on it (the centrifugal and Euler forces' work along each section centre's displacement, by
// the midpoint rule; the sections' own spin left out: their rotary inertia is 1e-3 of m ℓ² at
// 5 cm over 6.5 cm spans), with a margin of 1 % of the energies in play, m g L plus the work so
// far, for that quadrature's second-order error (measured: 0.56 % for the rope at 1/24 s, 1.3e-4
// at 1/120 s); and once the body is still, that energy never rises (the damping only takes).
TEST(LargeRotation, StabilityMatrixFromARopeToSteelAtStepsFromATenthOfAMillisecondToAFrame) {
  struct Run {
    double h, seconds;
  };
  for (const double youngs : {1e4, 1e6, 1e8, 1e11}) {
    for (const Run run : {Run{1e-4, 0.02}, Run{1.0 / 480, 0.6}, Run{1.0 / 120, 1.0}, Run{1.0 / 24, 1.0}}) {
      ElasticSweep tube(two_metre_tube(youngs, 0.05));
      tube.set_exact_chain(true);
      const double h = run.h, turn = 0.3, angle = kPi / 2;
      const double mgl = total_mass(tube) * kG * length_m(tube);
      const std::vector<double>& mass = tube.chain()->node_mass;
      const auto energy = [&] {
        const ChainDynamics& chain = *tube.exact_chain_state();
        return chain.kinetic_energy() + chain.elastic_energy() + chain.gravity_potential(Vec3(0, -kG, 0));
      };
      const double e0 = energy();
      std::vector<Vec3> now = tube.exact_chain_state()->centres();
      double work = 0, largest_work = 0, over = -1e300, rise = 0;
      const int steps = static_cast<int>(std::lround(run.seconds / h));
      double previous = e0;
      for (int k = 0; k < steps; ++k) {
        const double tm = (k + 0.5) * h;  // the body's state at mid-step
        double rate = 0, accel = 0;
        if (tm < turn) {
          const double u = tm / turn;
          rate = angle * (6 * u - 6 * u * u) / turn;
          accel = angle * (6 - 12 * u) / (turn * turn);
        }
        ElasticSweep::BodyMotion body;
        body.gravity = Vec3(0, -kG, 0);
        body.angular_velocity = Vec3(0, rate, 0);
        body.angular_acceleration = Vec3(0, accel, 0);
        tube.set_body_motion(body);
        tube.step(h);
        ASSERT_TRUE(tube.is_finite()) << "E " << youngs << ", step " << h << ", at " << k;
        const std::vector<Vec3> after = tube.exact_chain_state()->centres();
        // The work of this step: the fictitious forces −m (α × c + ω × (ω × c)) at the body's
        // mid-step rates (held over the step, as the step holds them), at the midpoint of each
        // centre's displacement.
        for (std::size_t i = 1; i < now.size(); ++i) {
          const Vec3 mid = 0.5 * (now[i] + after[i]);
          const Vec3 w(0, rate, 0), a(0, accel, 0);
          work -= mass[i] * (after[i] - now[i]).dot(a.cross(mid) + w.cross(w.cross(mid)));
        }
        const double e = energy();
        largest_work = std::max(largest_work, std::abs(work));
        over = std::max(over, (e - e0 - work) / (mgl + largest_work));
        if (tm > turn + h) rise = std::max(rise, (e - previous) / mgl);
        previous = e;
        now = after;
      }
      std::printf(
          "E %.0e, step %.3g s: largest (energy - work)/(m g L + work) %.3g, work up to %.3g m g L, rise once still "
          "%.3g, tip %.3g L down\n",
          youngs, h, over, largest_work / mgl, rise, -tube.exact_chain_state()->centres().back().y() / length_m(tube));
      EXPECT_LE(over, 0.01) << "E " << youngs << ", step " << h;
      EXPECT_LE(rise, 1e-9) << "E " << youngs << ", step " << h;
    }
  }
}

// Steps beyond a frame, up to the schema's longest (1 s), Young's modulus from a limp rope to steel,
// the tube released level under gravity (not pre-loaded) at the default damping (ζ = 0.05) for 2 s:
// every step's Newton iteration settles (a step that does not is halved, down to 2⁻¹⁶ of it), the
// state stays finite, and the chain's energy (kinetic, elastic, gravity's) never rises above what
// it started with: the damping only takes. Halved at most 8 times, the rope's 0.37 s and 1 s steps
// were taken unsettled 1 to 283 times; undamped, such steps gained energy 200-fold.
TEST(LargeRotation, StepsUpToASecondSettleAndNeverGainEnergy_long) {
  for (const double youngs : {1e4, 1e6, 1e8, 1e11}) {
    for (const double h : {0.1, 0.37, 1.0}) {
      ElasticSweep tube(two_metre_tube(youngs, 0.05));
      tube.set_exact_chain(true);
      tube.set_gravity(Vec3(0, -kG, 0), false);
      const double mgl = total_mass(tube) * kG * length_m(tube);
      const auto energy = [&] {
        const ChainDynamics& chain = *tube.exact_chain_state();
        return chain.kinetic_energy() + chain.elastic_energy() + chain.gravity_potential(Vec3(0, -kG, 0));
      };
      const double e0 = energy();
      double over = -1e300;
      const int steps = static_cast<int>(std::ceil(2.0 / h));
      for (int k = 0; k < steps; ++k) {
        tube.step(h);
        ASSERT_TRUE(tube.is_finite()) << "E " << youngs << ", step " << h << ", at " << k;
        over = std::max(over, (energy() - e0) / mgl);
      }
      const ChainDynamics& chain = *tube.exact_chain_state();
      std::printf("E %.0e, step %.3g s: largest energy gain %.3g m g L, unsettled steps %lld, %lld iterations\n",
                  youngs, h, over, chain.unsettled(), chain.iterations());
      EXPECT_EQ(chain.unsettled(), 0) << "E " << youngs << ", step " << h;
      EXPECT_LE(over, 1e-9) << "E " << youngs << ", step " << h;
      // The soft ones droop far under their weight (β ≥ 138): the steps did move them.
      if (youngs <= 1e6) {
        EXPECT_LT(chain.centres().back().y(), -0.1 * length_m(tube)) << "it did fall";
      }
    }
  }
}

}  // namespace
}  // namespace sweep::sim

// The default dynamics (a scene without "dynamics": automatic), through the simulator: the rest-pose
// modes while the motion is small, the exact chain from the internal step where a section has turned
// past ElasticSweep::kSwitchAngle. Each case runs the modes alone beside it: they break what it
// asserts, so each assertion can fail.

namespace sweep::sim {
namespace {

using Dynamics = ElasticSweep::Dynamics;

Rig rig_with(const SweepDef& def) {
  Rig rig;
  rig.sweeps.push_back(def);
  return rig;
}

// The scene's default dynamics (none given), or the rest-pose modes; frames on the internal grid
// (480 fps) so that every frame is one step of the body.
Scene scene_with(double seconds, bool modal) {
  Scene scene;
  scene.duration = seconds;
  scene.fps = 480;
  if (modal) scene.dynamics = Dynamics::modal;
  return scene;
}

// The soft tube released level (as LargeRotation.ASoftTubeReleasedLevel…, β = 138): the sections'
// kinetic energy never above gravity's work, in its plane but for what the modes' own out-of-plane
// growth from rounding reached before the switch, and it falls.
TEST(LargeRotation, ByDefaultASoftTubeReleasedLevelNeverOutrunsGravitysWorkAndStaysInItsPlane) {
  for (const bool modal : {false, true}) {
    const Rig rig = rig_with(two_metre_tube(1e6, 0.05));
    Scene scene = scene_with(1.0, modal);
    scene.gravity = Vec3(0, -kG, 0);
    scene.gravity_start = Scene::GravityStart::unloaded;
    Simulator sim(rig, scene);
    const double h = 1.0 / scene.fps;
    const double l = length_m(sim.sweep(0)), mgl = total_mass(sim.sweep(0)) * kG * l;
    const std::vector<double>& mass = sim.sweep(0).chain()->node_mass;
    const std::vector<Vec3> start = sim.sweep(0).exact_chain_state()->centres();
    std::vector<Vec3> before = start, now = start;
    double worst = -1, off_plane = 0, lowest = 0;
    for (int s = 0; s < 480; ++s) {
      sim.advance_frame();
      const std::vector<Vec3> after = sim.sweep(0).exact_chain_state()->centres();
      if (s > 0) {
        double work = 0, kinetic = 0;
        for (std::size_t i = 1; i < now.size(); ++i) {
          work += mass[i] * kG * (start[i].y() - now[i].y());
          kinetic += 0.5 * mass[i] * ((after[i] - before[i]) / (2 * h)).squaredNorm();
        }
        worst = std::max(worst, (kinetic - work) / mgl);
      }
      for (const Vec3& c : after) off_plane = std::max(off_plane, std::abs(c.x()) / l);
      lowest = std::min(lowest, after.back().y() / l);
      before = now;
      now = after;
    }
    const Simulator::ChainSwitch& to_exact = sim.chain_switch(0);
    std::printf(
        "released soft tube (%s): exact chain from %.4g s (%.3g rad), largest (KE - W)/(m g L) %.3g, off its "
        "plane %.3g L\n",
        modal ? "modal" : "default", to_exact.time, to_exact.angle, worst, off_plane);
    if (modal) {
      EXPECT_GT(worst, 0.1);
      EXPECT_GT(off_plane, 0.1);
      EXPECT_LT(to_exact.time, 0);
      continue;
    }
    EXPECT_GT(to_exact.time, 0);
    EXPECT_GT(to_exact.angle, ElasticSweep::kSwitchAngle);
    EXPECT_LE(worst, 1e-4);  // the differences' own error is O(h²): far below
    EXPECT_LE(off_plane, 1e-6);
    EXPECT_LT(lowest, -0.5);  // it did fall
  }
}

// A soft tube (E = 1e5 Pa) whipped by 20 N·s across its tip, undisturbed otherwise: the chain's
// energy (kinetic and elastic) never rises above what the kick gave it (measured at the rest pose,
// where both dynamics agree). The modes alone reach several times it.
TEST(LargeRotation, ByDefaultATipImpulseOnASoftTubeNeverRaisesItsEnergyAboveTheKicks) {
  for (const bool modal : {false, true}) {
    const SweepDef def = two_metre_tube(1e5, 0.05);
    const Rig rig = rig_with(def);
    Scene scene = scene_with(1.0, modal);
    SceneForce kick;
    kick.sweep = "tube";
    kick.sweep_index = 0;
    kick.spec.t = def.rest.length();
    kick.spec.vector = Vec3(20, 0, 0);
    kick.spec.components = kRotational;
    kick.spec.target = RotationTarget::chain;
    kick.spec.moment = MomentModel::physical;
    scene.forces.push_back(kick);
    Simulator sim(rig, scene);
    ElasticSweep kicked(def);
    kicked.apply_impulse(kick.spec);
    const double given = kicked.exact_chain_state()->kinetic_energy();
    double most = 0;
    for (int s = 0; s < 480; ++s) {
      sim.advance_frame();
      const ChainDynamics& chain = *sim.sweep(0).exact_chain_state();
      most = std::max(most, (chain.kinetic_energy() + chain.elastic_energy()) / given);
    }
    std::printf("whipped soft tube (%s): exact chain from %.4g s (%.3g rad), energy up to %.4g of the kick's\n",
                modal ? "modal" : "default", sim.chain_switch(0).time, sim.chain_switch(0).angle, most);
    if (modal) {
      EXPECT_GT(most, 1.5);
    } else {
      EXPECT_GE(sim.chain_switch(0).time, 0);
      EXPECT_LE(most, 1.0);
    }
  }
}

// A soft tube (E = 1e6 Pa, β = 138; as-modelled under gravity) level on a body that turns a quarter
// turn about the vertical in 0.3 s (from rest to rest), straight or bent into a quarter circle at
// rest, through the turn and a little after (0.4 s): the bake does not abort and stays finite. The
// modes alone run away within 0.02 s (the simulator's runaway guard: bad input, exit 2).
void turn_a_soft_tube(bool bent) {
  for (const bool modal : {false, true}) {
    const Rig rig = rig_with(two_metre_tube(1e6, 0.05, bent));
    Scene scene = scene_with(0.4, modal);
    scene.fps = 30;
    scene.gravity = Vec3(0, -kG, 0);
    scene.gravity_start = Scene::GravityStart::as_modelled;  // (it cannot hold it: by default it starts unloaded)
    const Quat turned(Eigen::AngleAxisd(kPi / 2, Vec3::UnitY()));
    scene.body = BodyPath({BodyKey{.time = 0}, BodyKey{.time = 0.3, .rotation = turned}}, BodyInterpolation::cubic);
    Simulator sim(rig, scene);
    std::string error;
    try {
      for (int f = 0; f < 12; ++f) sim.advance_frame();
    } catch (const std::exception& e) {
      error = e.what();
    }
    std::printf("turned %s tube (%s): exact chain from %.4g s (%.3g rad)%s%s\n", bent ? "bent" : "straight",
                modal ? "modal" : "default", sim.chain_switch(0).time, sim.chain_switch(0).angle,
                error.empty() ? "" : ", ", error.c_str());
    if (modal) {
      EXPECT_NE(error.find("moved more than"), std::string::npos);
      continue;
    }
    EXPECT_EQ(error, "");
    EXPECT_TRUE(sim.sweep(0).is_finite());
    EXPECT_GE(sim.chain_switch(0).time, 0);
  }
}
TEST(LargeRotation, ByDefaultAStraightSoftPartOnABodyTurningAQuarterTurnInAThirdOfASecondDoesNotAbort) {
  turn_a_soft_tube(false);
}
TEST(LargeRotation, ByDefaultABentSoftPartOnABodyTurningAQuarterTurnInAThirdOfASecondDoesNotAbort) {
  turn_a_soft_tube(true);
}

// The switch falls on the internal clock: the released tube baked at 24, 30, 60 and 144 fps turns
// to the exact chain at the same time, to the bit, and its pose at the frames they share (0.5 s)
// is the same to 1e-9 of its length.
TEST(LargeRotation, ByDefaultTheSwitchIsAtTheSameTimeWhateverTheFrameRate) {
  const Rig rig = rig_with(two_metre_tube(1e6, 0.05));
  double reference_time = 0;
  std::vector<Frame> reference;
  for (const double fps : {144.0, 24.0, 30.0, 60.0}) {
    Scene scene = scene_with(0.5, false);
    scene.fps = fps;
    scene.gravity = Vec3(0, -kG, 0);
    scene.gravity_start = Scene::GravityStart::unloaded;
    Simulator sim(rig, scene);
    const int frames = static_cast<int>(std::lround(0.5 * fps));
    for (int f = 0; f < frames; ++f) sim.advance_frame();
    ASSERT_EQ(sim.time(), 0.5);
    const std::vector<Frame>& pose = sim.sweep(0).deformed().frames;
    if (reference.empty()) {
      reference_time = sim.chain_switch(0).time;
      reference = pose;
      EXPECT_GT(reference_time, 0);
      continue;
    }
    EXPECT_EQ(sim.chain_switch(0).time, reference_time) << fps << " fps";
    double apart = 0;
    for (std::size_t i = 0; i < pose.size(); ++i)
      apart = std::max(apart, (pose[i].center - reference[i].center).norm() / rig.sweeps[0].rest.length());
    EXPECT_LE(apart, 1e-9) << fps << " fps";
  }
}

}  // namespace
}  // namespace sweep::sim
