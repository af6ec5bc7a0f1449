// Driven by the body: a keyframed root, the inertia the parts feel, teleports, and the
// files carrying the body's motion — against closed forms where there are any.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <string>

#include "bind/support.h"
#include "core/beam_tubes.h"
#include "core/sample_sweeps.h"
#include "pc2_reader.h"
#include "sim/sweep_pose.h"
#include "sweep/assets/bake_run.h"
#include "sweep/bind/bind.h"
#include "sweep/core/contact_rows_detail.h"
#include "sweep/sim/simulator.h"
#include "test_constants.h"

using sweep::assets::run_bake;

namespace sweep::sim {
namespace {

using test_pose::max_difference;
using test_pose::pose;

namespace fs = std::filesystem;
using test::read_pc2;
using Vec3f = Eigen::Vector3f;
using ::sweep::test::kPi;

// Root at the origin, one movable section at z = 1: positional spring of mass m, f0, ζ.
Rig one_section(double mass, double frequency_hz, double zeta) {
  Rig rig;
  SweepDef def = test::sweep_def(test::straight_shape(2, 6));
  def.name = "part";
  def.springs[1].positional = {mass, frequency_hz, zeta};
  rig.sweeps.push_back(def);
  return rig;
}

BodyKey key(double time, Vec3 translation, Quat rotation = Quat::Identity()) {
  return {time, translation, rotation};
}

Scene scene_of(BodyPath path, double duration, double fps = 30, double step = Scene::kDefaultStep) {
  Scene s;
  s.duration = duration;
  s.fps = fps;
  s.step = step;
  s.body = std::move(path);
  return s;
}

// The corner of a linear body path is an instant change of the body's velocity: the part, not
// yet pulled along by its root, stays where it was in the world, so each section's centre moves
// at −(Δv + Δω × c) relative to the body. Material mode takes the kick through its joints alone,
// the chain's full mass matrix. Measured on a straight tube kicked across its axis and turned
// about the body's: sections 2 on within 1.0 % and 0.1 % (mass-weighted RMS), the tip exact, the
// energy below the world's ½ Σ m v² as constraints' impulses must leave it. (Section 1 stays put:
// joint 1 turns the part about it, and only the stiff shear springs, which take no kick, move it.
// A kick along the axis is not taken at all: the joints cannot stretch the part.) Before, each
// stretch and shear spring, massed with all the sections beyond it, took the whole kick too and
// passed it on: section i moved at i times the jump (the tip at 32×, and 17× the world's energy).
TEST(Body, AKickLeavesThePartStillInTheWorld) {
  SweepDef def = test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.0);
  def.name = "tube";
  test::beam::set_youngs_modulus(def, 2e8);
  struct Case {
    Vec3 dv, dw;
  };
  for (const Case& kick : {Case{Vec3(0.5, 0, 0), Vec3::Zero()}, Case{Vec3::Zero(), Vec3(0, 2, 0)}}) {
    ElasticSweep part(def);
    part.apply_body_kick(kick.dv, kick.dw);
    const SweepShape& shape = part.deformed();
    const ChainModel& chain = *part.chain();
    ContactRow row;
    double error = 0, wanted = 0, world_energy = 0;
    Vec3 tip = Vec3::Zero(), tip_wanted = Vec3::Zero();
    for (int i = 1; i < shape.section_count(); ++i) {
      Vec3 v = Vec3::Zero();
      for (int c = 0; c < 3; ++c) {
        ContactRows::contact_row(part, shape.t[i], Vec3::Unit(c), row, false);
        v[c] = ContactRows::row_speed(part, row);
      }
      const Vec3 want = -(kick.dv + kick.dw.cross(shape.frames[i].center));
      const double m = chain.node_mass[static_cast<std::size_t>(i)];
      world_energy += 0.5 * m * std::pow(chain.metres_per_unit * want.norm(), 2);
      if (i == 1) {
        EXPECT_EQ(v, Vec3::Zero()) << "section 1: only the shear springs move it";
        continue;
      }
      error += m * (v - want).squaredNorm();
      wanted += m * want.squaredNorm();
      tip = v, tip_wanted = want;
    }
    const std::string which = "Δv " + std::to_string(kick.dv.x()) + ", Δω " + std::to_string(kick.dw.y());
    EXPECT_LT((tip - tip_wanted).norm(), 0.01 * tip_wanted.norm()) << which;
    EXPECT_LT(std::sqrt(error / wanted), 0.02) << which;
    EXPECT_LE(part.energy(), world_energy) << which;
  }
}

TEST(Body, MovingAtConstantVelocityDeformsNothing) {
  // Moving from the start (a key at t = 0: the parts begin at rest in a moving body), straight and
  // at one speed: no acceleration, no load, no motion — however fast.
  const Rig rig = test::bent_part();
  const std::vector<double> rest = pose(ElasticSweep(rig.sweeps[0]));
  const BodyPath path({key(0, Vec3(0, 0, 0)), key(10, Vec3(300, -40, 25))}, BodyInterpolation::linear);
  const Scene scene = scene_of(path, 3.0);  // (the simulator keeps a reference)
  Simulator sim(rig, scene);
  for (int k = 1; k < 91; ++k) {
    sim.advance_frame();
    ASSERT_LE(max_difference(pose(sim.sweep(0)), rest), 1e-9 * rig.sweeps[0].rest.length()) << "frame " << k;
  }
  EXPECT_NEAR(sim.body().translation.x(), 90.0, 1e-9);  // the body did move
}

TEST(Body, ConstantAccelerationGivesTheClosedFormOscillationAroundMaOverK) {
  // x(t) = −(m a / k)(1 − cos ω t) for an undamped spring starting at rest: the section lags behind
  // the accelerating body and swings about the static deflection m a / k = a / ω².
  const double f0 = 1.5, w = 2 * kPi * f0;
  const Rig rig = one_section(2.0, f0, 0.0);
  const Vec3 a(0.8, -0.3, 0.2);  // mesh units/s², body axes (no rotation)
  // p(t) = a t² / 2 through keys 0..5 s: cubic Hermite with Catmull-Rom tangents is exact for a
  // parabola except on the last piece (its end tangent is 0).
  std::vector<BodyKey> keys;
  for (int t = 0; t <= 5; ++t) keys.push_back(key(t, 0.5 * a * t * t));
  const Scene scene = scene_of(BodyPath(keys, BodyInterpolation::cubic), 4.0);
  Simulator sim(rig, scene);
  double largest = 0;
  for (int k = 1; k <= 120; ++k) {  // 4 s at 30 fps: within the exact pieces
    sim.advance_frame();
    const double t = k / 30.0;
    const Vec3 expected = -(a / (w * w)) * (1 - std::cos(w * t));
    ASSERT_LE((sim.sweep(0).section_offset(1) - expected).norm(), 1e-9 * a.norm() / (w * w)) << "t = " << t;
    largest = std::max(largest, sim.sweep(0).section_offset(1).norm());
  }
  EXPECT_NEAR(largest, 2 * a.norm() / (w * w), 1e-3 * a.norm() / (w * w));  // the swing's amplitude
}

TEST(Body, TurningAtConstantRateStretchesByTheCentrifugalClosedForm) {
  // The section at c = (0, 0, 1) on a body turning at ω about y is flung outward: in equilibrium
  // k x = m ω² (1 + x), so x = m ω² / (k − m ω²). Critically damped: it settles there.
  const double mass = 1.0, f0 = 2.0, omega = 3.0;
  const double k = mass * std::pow(2 * kPi * f0, 2);
  const Rig rig = one_section(mass, f0, 1.0);
  std::vector<BodyKey> keys;  // a linear turn about y at ω (pieces under half a turn each)
  for (int i = 0; i <= 40; ++i)
    keys.push_back(key(0.5 * i, Vec3::Zero(), Quat(Eigen::AngleAxisd(omega * 0.5 * i, Vec3::UnitY()))));
  const Scene scene = scene_of(BodyPath(keys, BodyInterpolation::linear), 12.0);
  Simulator sim(rig, scene);
  // While the section moves out (+z), the Coriolis force −2m ω × v pushes it against the turn: −x.
  double low = 0, high = 0;
  for (int f = 0; f < 360; ++f) {
    sim.advance_frame();
    low = std::min(low, sim.sweep(0).section_offset(1).x());
    high = std::max(high, sim.sweep(0).section_offset(1).x());
  }
  const double expected = mass * omega * omega / (k - mass * omega * omega);
  EXPECT_LT(low, -1e-3 * expected);
  EXPECT_GT(-low, 10 * high);
  const Vec3 x = sim.sweep(0).section_offset(1);
  EXPECT_NEAR(x.z(), expected, 1e-9 * expected);
  EXPECT_NEAR(x.x(), 0.0, 1e-9 * expected);  // the Coriolis push sideways died with the motion
  EXPECT_NEAR(x.y(), 0.0, 1e-12);
}

// Undamped, on a body turning at a constant rate, over 2 s at step h: the largest change of the
// Jacobi integral — the springs' energy less the centrifugal potential ½ m |ω × p|² — and |J|.
std::pair<double, double> jacobi_drift(double h) {
  const double mass = 1.0;
  Rig rig = one_section(mass, 1.5, 0.0);
  ElasticSweep sweep(rig.sweeps[0]);
  ElasticSweep::BodyMotion motion;
  motion.angular_velocity = Vec3(0, 2.0, 0);
  sweep.set_body_motion(motion);
  sweep.set_section_pose(1, Vec3(0.05, 0.02, -0.03), Vec3::Zero());
  auto jacobi = [&] {
    const Vec3 p = sweep.deformed().frames[1].center;
    return sweep.energy() - 0.5 * mass * motion.angular_velocity.cross(p).squaredNorm();
  };
  const double j0 = jacobi();
  double drift = 0;
  for (int s = 0; s < static_cast<int>(std::lround(2 / h)); ++s) {
    sweep.step(h);
    drift = std::max(drift, std::abs(jacobi() - j0));
  }
  return {drift, std::abs(j0)};
}

TEST(Body, CoriolisDoesNoWorkTheRotatingFramesEnergyIsKept) {
  // The Jacobi integral is kept by the motion; the Coriolis force, at right angles to it, adds
  // nothing. What the steps change is their own error: it falls as h² (a Coriolis force applied at
  // the wrong place or speed would pump energy at any step).
  const auto [coarse, j] = jacobi_drift(1.0 / 480);
  const auto [fine, j_fine] = jacobi_drift(1.0 / 960);
  EXPECT_LE(coarse, 1e-5 * j);
  EXPECT_NEAR(coarse / fine, 4.0, 0.5);
  EXPECT_EQ(j, j_fine);
}

TEST(Body, ATeleportPutsThePartsToRestInsteadOfWhipping) {
  // Walking, then a cut: the body is elsewhere 1/100 s later. With teleports (the default) the
  // parts are at rest in the new place; without, the jump whips them.
  const Rig rig = test::bent_part();
  const BodyPath path({key(0, Vec3::Zero()), key(0.5, Vec3(0.1, 0, 0)), key(1.0, Vec3(0.6, 0, 0)),
                       key(1.01, Vec3(40, 0, 0)), key(3.0, Vec3(41, 0, 0))},
                      BodyInterpolation::linear);
  auto speeds = [&](bool teleport, std::vector<int>* teleports) {
    Scene scene = scene_of(path, 2.0);
    scene.teleport_enabled = teleport;
    Simulator sim(rig, scene);
    std::vector<double> out;  // largest change of the section poses per frame
    std::vector<double> before = pose(sim.sweep(0));
    for (int k = 1; k <= 60; ++k) {
      sim.advance_frame();
      const std::vector<double> now = pose(sim.sweep(0));
      out.push_back(max_difference(now, before));
      before = now;
    }
    if (teleports) *teleports = sim.teleports();
    return out;
  };
  std::vector<int> teleports;
  const std::vector<double> with = speeds(true, &teleports);
  const std::vector<double> without = speeds(false, nullptr);
  ASSERT_EQ(teleports, std::vector<int>{31});  // the frame that contains t = 1.0 .. 1.01
  EXPECT_GT(with[29], 0.0);                    // moving before (the kick at 0.5 s still rings)
  EXPECT_LE(with[31], with[29]);               // no spike in the frame after it
  EXPECT_EQ(with[31], 0.0);                    // at rest in the new place
  EXPECT_GT(without[31], 10 * with[29]);       // what it spares: the whip
}

// Poses at every frame, keyed by the frame's time in units of 1/720 s.
std::map<long long, std::vector<double>> bake_poses(const Rig& rig, const Scene& scene) {
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

TEST(Body, AnyFrameRateGivesTheSameMotionWithTheBodyMoving) {
  // Kicks at corners between frame times (0.4321 s, 1.2345 s), turning pieces and a cubic path
  // alike: the frame rate changes nothing.
  const Rig rig = test::bent_part();
  const Quat turn(Eigen::AngleAxisd(0.7, Vec3(0.2, 1, 0.1).normalized()));
  for (const BodyInterpolation interpolation : {BodyInterpolation::linear, BodyInterpolation::cubic}) {
    const BodyPath path({key(0.4321, Vec3::Zero()), key(0.9, Vec3(2, 0.3, 0), turn),
                         key(1.2345, Vec3(2.5, 0.3, 0.4), turn), key(1.6, Vec3(2.6, 0.3, 0.4))},
                        interpolation);
    const double step = 1.0 / 700;
    const Scene reference = scene_of(path, 2.0, 144, step);
    const auto ref = bake_poses(rig, reference);
    double moved = 0;
    for (double fps : {24.0, 30.0, 60.0}) {
      const Scene scene = scene_of(path, 2.0, fps, step);
      for (const auto& [time, p] : bake_poses(rig, scene)) {
        const auto it = ref.find(time);
        if (it == ref.end()) continue;
        moved = std::max(moved, max_difference(p, ref.at(0)));
        ASSERT_LE(max_difference(p, it->second), 1e-9 * rig.sweeps[0].rest.length())
            << fps << " fps, t = " << time / 720.0;
      }
    }
    EXPECT_GT(moved, 1e-3);
  }
}

TEST(Body, GustyWindIsTheSameEveryRunAndAtAnyFrameRateAndFollowsItsSeed) {
  Rig rig = test::bent_part();
  Material m;
  m.youngs_modulus = 2e5;
  m.metres_per_unit = 0.1;
  rig.sweeps[0].material = m;
  rig.sweeps[0].section_materials.assign(rig.sweeps[0].rest.section_count(), m);
  auto windy = [](double fps, std::uint64_t seed) {
    Scene s = scene_of(BodyPath(), 2.0, fps, 1.0 / 700);
    WindSettings w;
    w.enabled = true;
    w.velocity = Vec3(6, 0, 2);
    w.gust = 0.5;
    w.gust_period = 1.5;
    w.turbulence = 0.3;
    w.seed = seed;
    s.wind = Wind(w);
    return s;
  };
  const Scene a = windy(30, 7), again = windy(30, 7), faster = windy(60, 7), other = windy(30, 8);
  const auto pa = bake_poses(rig, a), pagain = bake_poses(rig, again), pfast = bake_poses(rig, faster),
             pother = bake_poses(rig, other);
  double moved = 0, seeds_differ = 0;
  for (const auto& [time, p] : pa) {
    ASSERT_EQ(p, pagain.at(time));  // bit for bit
    ASSERT_LE(max_difference(p, pfast.at(time)), 1e-9 * rig.sweeps[0].rest.length()) << time / 720.0;
    moved = std::max(moved, max_difference(p, pa.at(0)));
    seeds_differ = std::max(seeds_differ, max_difference(p, pother.at(time)));
  }
  EXPECT_GT(moved, 1e-3);
  EXPECT_GT(seeds_differ, 1e-2 * moved);
  // Gusts only strengthen the mean wind; turbulence wanders about it.
  for (double t = 0; t < 10; t += 0.01) {
    const Vec3 v = a.wind.at(t);
    EXPECT_GE(v.dot(Vec3(6, 0, 2).normalized()), (1 - 0.3 * std::sqrt(3.0)) * Vec3(6, 0, 2).norm() - 1e-9);
  }
}

TEST(Body, AStillBodyWakesNothing) {
  // A path whose keys all agree is a body at rest: no part is driven or stepped.
  const Rig rig = test::bent_part();
  const Scene scene = scene_of(BodyPath({key(0, Vec3(1, 2, 3)), key(1, Vec3(1, 2, 3))}, BodyInterpolation::cubic), 1.0);
  Simulator sim(rig, scene);
  for (int k = 0; k < 30; ++k) sim.advance_frame();
  EXPECT_FALSE(sim.is_driven(0));
  EXPECT_EQ(sim.steps_taken(0), 0);
}

TEST(Body, FilesCarryTheBodyPcTwoInTheWorldGlbAsTheNodesAnimation) {
  const Mesh mesh = tube::make_tube(test::straight_tube_params());
  const Rig rig = test::rig_of({test::straight_sweep()});
  const bind::Binding binding = bind::bind_rig(rig, mesh);
  const Quat turn(Eigen::AngleAxisd(1.2, Vec3::UnitY()));
  Scene scene =
      scene_of(BodyPath({key(0, Vec3::Zero()), key(1, Vec3(0.5, 0, 0.2), turn)}, BodyInterpolation::cubic), 1.5);
  const fs::path dir = fs::temp_directory_path() / ("sweep_body_files_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  sweep::assets::BakeOptions o;
  o.outputs = {dir / "out.pc2", dir / "out.glb"};
  run_bake(mesh, rig, binding, scene, o);
  const auto pc2 = read_pc2(dir / "out.pc2");
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, (dir / "out.glb").string())) << err;
  fs::remove_all(dir);
  // The node's translation and rotation channels, keyed at the frames.
  const tinygltf::Animation& anim = model.animations.at(0);
  std::map<std::string, const float*> channel;
  for (const tinygltf::AnimationChannel& c : anim.channels) {
    const tinygltf::Accessor& acc = model.accessors.at(anim.samplers.at(c.sampler).output);
    if (c.target_path == "weights") continue;
    EXPECT_EQ(anim.samplers.at(c.sampler).interpolation, "LINEAR");
    EXPECT_EQ(acc.count, pc2.size());
    const tinygltf::BufferView& bv = model.bufferViews.at(acc.bufferView);
    channel[c.target_path] =
        reinterpret_cast<const float*>(model.buffers.at(0).data.data() + bv.byteOffset + acc.byteOffset);
  }
  ASSERT_EQ(channel.size(), 2u);
  // A vertex no sweep moves (the far cap's centre is bound; the first ring sits at the root): its
  // world position in the .pc2 is the body's pose applied to its rest position.
  const std::size_t v = 0;
  for (std::size_t k = 0; k < pc2.size(); ++k) {
    const BodyState b = scene.body.at(k / scene.fps);
    const float* t = channel["translation"] + 3 * k;
    const float* r = channel["rotation"] + 4 * k;
    const Quat q(r[3], r[0], r[1], r[2]);
    EXPECT_NEAR((Vec3(t[0], t[1], t[2]) - b.translation).norm(), 0.0, 1e-6) << k;
    EXPECT_NEAR(q.angularDistance(b.rotation), 0.0, 1e-6) << k;
    const Vec3 world = b.rotation * mesh.positions[v] + b.translation;
    EXPECT_NEAR((pc2[k][v].cast<double>() - world).norm(), 0.0, 1e-6) << k;
  }
  EXPECT_GT((pc2.back()[v] - pc2.front()[v]).norm(), 0.4f);  // the body moved the whole mesh
}

}  // namespace
}  // namespace sweep::sim
