// A skinned part lags and overshoots its keyed pose like a driven oscillator (assets/skinned_clip.h,
// sim/keyed_bend.h): its deviation q from the keyed pose obeys q'' + 2ζω0 q' + ω0² q = −a, a the
// acceleration its keys give it, whether they move its root joint (the base) or the joints that bend
// it below its root. On the committed creature meshes/skinned_tail.gltf (Hip -> Tail1 -> Tail2 ->
// Tail3, the tail from z = 0 to 1) with its clips replaced here by a sway of one joint, and the tail
// a part of one spring section (the paper's springs: the tip's positional spring alone carries it).
// The closed form is computed here, from the springs' settings and the keys.
#include "sweep/sim/keyed_bend.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "base64.h"
#include "bind/support.h"
#include "sweep/assets/gltf_skin.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/assets/skinned_clip.h"
#include "sweep/bind/bind.h"
#include "sweep/core/springs.h"
#include "sweep/io/read_file.h"
#include "sweep/io/rig_json.h"
#include "test_constants.h"

namespace sweep::test {
namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;
using ::sweep::test::kPi;

// The part's springs: f0 = 2 Hz, ζ = 0.15; the sway keyed every kKeyStep s over a 1 s loop.
constexpr double kF0 = 2.0, kZeta = 0.15;
constexpr double kAmplitude = 0.05;  // of the keyed sway, 5 % of the tail's length
constexpr int kKeys = 60;            // keys a second (the clip is 1 s long)
constexpr int kFps = 30;

fs::path keyed_bend_dir(const std::string& name) {
  const fs::path dir = fs::path(SWEEP_BINARY_DIR) / "tests/assets/keyed_bend" / name;
  fs::create_directories(dir);
  return dir;
}

// The creature with one clip, "Sway": node `node` (glTF index) translated by A sin(2π hz τ) along x
// from its own place `rest`, LINEAR keys at k / kKeys s over one second.
void write_sway(const fs::path& out, int node, const std::vector<float>& rest, int hz) {
  Json d = Json::parse(io::read_file(fs::path(SWEEP_SOURCE_DIR) / "meshes/skinned_tail.gltf"));
  std::string bytes;
  auto put = [&](float f) { bytes.append(reinterpret_cast<const char*>(&f), 4); };
  for (int k = 0; k <= kKeys; ++k) put(static_cast<float>(static_cast<double>(k) / kKeys));
  for (int k = 0; k <= kKeys; ++k) {
    put(rest[0] + static_cast<float>(kAmplitude * std::sin(2 * kPi * hz * k / kKeys)));
    put(rest[1]);
    put(rest[2]);
  }
  const std::size_t times = 4 * (kKeys + 1);
  d["buffers"].push_back(
      {{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + base64(bytes)}});
  const std::size_t buffer = d["buffers"].size() - 1;
  d["bufferViews"].push_back({{"buffer", buffer}, {"byteOffset", 0}, {"byteLength", times}});
  d["bufferViews"].push_back({{"buffer", buffer}, {"byteOffset", times}, {"byteLength", bytes.size() - times}});
  const std::size_t views = d["bufferViews"].size();
  d["accessors"].push_back({{"bufferView", views - 2},
                            {"componentType", 5126},
                            {"count", kKeys + 1},
                            {"type", "SCALAR"},
                            {"min", {0}},
                            {"max", {1}}});
  d["accessors"].push_back(
      {{"bufferView", views - 1}, {"componentType", 5126}, {"count", kKeys + 1}, {"type", "VEC3"}});
  const std::size_t accessors = d["accessors"].size();
  d["animations"] =
      Json::array({{{"name", "Sway"},
                    {"samplers", {{{"input", accessors - 2}, {"output", accessors - 1}}}},
                    {"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", "translation"}}}}}}}});
  std::ofstream(out) << d.dump();
}

// The tail as a part of one spring section: root at z = 0, tip at z = 1.
SweepDef one_section_tail(double stiffness_hz) {
  SweepShape s;
  s.radial_count = 8;
  for (int i = 0; i < 2; ++i) {
    s.t.push_back(i);
    s.frames.push_back({Quat::Identity(), Vec3(0, 0, i)});
    for (int j = 0; j < 8; ++j) s.radii.push_back(0.1);
  }
  SweepDef def = make_sweep("tail", std::move(s));
  for (SpringSettings* k : {&def.default_springs.positional, &def.default_springs.bend, &def.default_springs.twist})
    *k = SpringSettings{1.0, stiffness_hz, kZeta};
  def.springs.assign(def.rest.frames.size(), def.default_springs);
  return def;
}

struct Sway {
  std::vector<Vec3> deviation;  // the tip's from its keyed place, per frame
};

// Bakes the swaying creature (node, its rest translation, the sway's frequency) after a 4 s preroll
// and returns the tip's deviation from its keyed place over one second (frames 0..29).
Sway bake(const std::string& name, int node, const std::vector<float>& rest, int hz) {
  const fs::path dir = keyed_bend_dir(name);
  write_sway(dir / "creature.gltf", node, rest, hz);
  io::write_rig(dir / "rig.json", rig_of({one_section_tail(kF0)}, "creature.gltf"));
  const std::string rig = "'" + (dir / "rig.json").string() + "'", bound = "'" + (dir / "rig.bind").string() + "'";
  EXPECT_EQ(std::system((std::string(SWEEP_BIND_EXE) + " -q " + rig + " -o " + bound).c_str()), 0);
  std::ofstream(dir / "scene.json") << R"({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 30,
    "forces": [], "body": {"node": "Creature", "animation": "Sway", "loop": true, "preroll": 4}})";
  const fs::path pc2 = dir / "out.pc2";
  EXPECT_EQ(std::system((std::string(SWEEP_SIM_EXE) + " -q " + rig + " --scene '" + (dir / "scene.json").string() +
                         "' -b " + bound + " -o '" + pc2.string() + "'")
                            .c_str()),
            0);
  const Mesh mesh = assets::read_mesh(dir / "creature.gltf");
  const std::string bytes = io::read_file(pc2);
  int points = 0;
  std::memcpy(&points, bytes.data() + 16, 4);
  EXPECT_EQ(points, static_cast<int>(mesh.vertex_count()));
  Sway out;
  for (int f = 0; f < kFps; ++f) {
    // The tip: the ring and cap centre at z = 1, which the keys carry by the sway alone.
    Vec3 tip = Vec3::Zero();
    int count = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
      if (mesh.positions[v].z() != 1) continue;
      float p[3];
      std::memcpy(p, bytes.data() + 32 + 12 * (static_cast<std::size_t>(f) * points + v), 12);
      tip += Vec3(p[0], p[1], p[2]) - mesh.positions[v].cast<double>();
      ++count;
    }
    const double keyed = kAmplitude * std::sin(2 * kPi * hz * f / kFps);
    out.deviation.push_back(tip / count - Vec3(keyed, 0, 0));
  }
  return out;
}

// The steady response to the keyed sway y = A sin ωt: x'' + 2ζω0 x' + ω0² x = −y'' with y'' that of
// the LINEAR keys, whose motion at ω is A ω² κ, κ = sinc²(ω δ / 2) (δ the keys' spacing: each key a
// change of velocity, the second difference of the keys over δ). Returns the deviation's complex
// amplitude X (x = Im(X e^{iωt})) relative to A.
std::complex<double> closed_form(int hz) {
  const double w = 2 * kPi * hz, w0 = 2 * kPi * kF0, half = w / (2.0 * kKeys);
  const double kappa = std::pow(std::sin(half) / half, 2);
  return w * w * kappa / std::complex<double>(w0 * w0 - w * w, 2 * kZeta * w0 * w);
}

// The deviation's component at the sway's frequency over whole periods (frames 0..29 of a 1 s loop):
// x ≈ Im(X e^{iωt}), X relative to A.
std::complex<double> measured(const Sway& s, int hz, double& off_axis) {
  double sine = 0, cosine = 0;
  off_axis = 0;
  for (int f = 0; f < kFps; ++f) {
    const double phase = 2 * kPi * hz * f / kFps;
    sine += 2.0 / kFps * s.deviation[f].x() * std::sin(phase);
    cosine += 2.0 / kFps * s.deviation[f].x() * std::cos(phase);
    off_axis = std::max(off_axis, s.deviation[f].tail<2>().norm());
  }
  return std::complex<double>(sine, cosine) / kAmplitude;  // x = sine·sin + cosine·cos = Im((sine + i·cosine) e^{iωt})
}

void expect_driven_oscillator(const std::string& name, int node, const std::vector<float>& rest) {
  for (const int hz : {1, 3}) {  // below and above the part's own 2 Hz
    const Sway s = bake(name + std::to_string(hz), node, rest, hz);
    double off_axis = 0;
    const std::complex<double> got = measured(s, hz, off_axis), want = closed_form(hz);
    EXPECT_NEAR(std::abs(got) / std::abs(want), 1.0, 0.02) << hz << " Hz";
    EXPECT_NEAR(std::arg(got), std::arg(want), 0.02 * kPi) << hz << " Hz";
    EXPECT_LT(off_axis, 1e-3 * kAmplitude) << hz << " Hz: the sway is along x";
    std::cout << name << " at " << hz << " Hz: amplitude " << std::abs(got) << " of the sway's (closed form "
              << std::abs(want) << "), phase " << std::arg(got) / kPi * 180 << "° (" << std::arg(want) / kPi * 180
              << "°)\n";
  }
}

// The root joint (Tail1, which holds the tail's root ring) keyed to sway: the base-driven oscillator.
TEST(KeyedBend, ARootSwayedByItsKeysDrivesThePartAsABase) {
  expect_driven_oscillator("root", 2, {0, 0, 0.3f});
}

// The root still, the joint below it (Tail2, carrying Tail3 and the tip) keyed to sway: the tip's
// keyed acceleration drives it the same way.
TEST(KeyedBend, AJointBelowTheRootSwayedByItsKeysDrivesThePart) {
  expect_driven_oscillator("bend", 3, {0, 0, 0.33f});
}

// What a keyed bend holds is bounded by the clip, not the bake: the committed creature's "Walk"
// (1 s; LINEAR, CUBICSPLINE and STEP channels on the tail's joints) on the binding tests' straight
// tail of six sections, at the default internal step.
struct WalkingTail {
  Mesh mesh = assets::read_mesh(fs::path(SWEEP_SOURCE_DIR) / "meshes/skinned_tail.gltf");
  Rig rig = rig_of({straight_sweep("tail", false)}, "skinned_tail.gltf");
  bind::Binding bound = bind::bind(rig, mesh).binding;
  assets::SkinnedClip clip(bool loop, double preroll) const {
    const fs::path file = fs::path(SWEEP_SOURCE_DIR) / "meshes/skinned_tail.gltf";
    const auto model = assets::read_gltf_skin(file, mesh.positions, Eigen::Affine3d::Identity());
    return assets::SkinnedClip(file, *model, Eigen::Affine3d::Identity(), rig, bound, "Creature", "Walk", loop, preroll,
                               kFps);
  }
};
constexpr double kStep = 1.0 / 480;  // the simulator's default internal step at 30 fps
constexpr double kWalkLength = 1.0;  // the fixture's "Walk", 0 to 1 s

double largest(const sim::KeyedBend& bend, double from, double to, double dt) {
  std::vector<Vec3> a(static_cast<std::size_t>(bend.sections()));
  double most = 0;
  for (double t = from; t <= to; t += dt) {
    bend.at(t, a);
    for (const Vec3& v : a) most = std::max(most, v.cwiseAbs().maxCoeff());
  }
  return most;
}

// A looping clip's bend is one period: as many samples for a 1 s bake as for a 20 s one (the
// clip's length over the step), and the same accelerations one period apart, loads included.
TEST(KeyedBend, ALoopingClipHoldsOnePeriodWhateverTheBakesLength) {
  const WalkingTail w;
  const double preroll = 0.5;
  const assets::SkinnedClip clip = w.clip(true, preroll);
  const sim::KeyedBend brief = clip.keyed_bend(0, 1.0 + preroll, kStep);
  const sim::KeyedBend lasting = clip.keyed_bend(0, 20.0 + preroll, kStep);
  EXPECT_EQ(brief.samples(), std::llround(kWalkLength / kStep));
  EXPECT_EQ(lasting.samples(), brief.samples());
  EXPECT_DOUBLE_EQ(lasting.period(), kWalkLength);
  const double scale = largest(lasting, 0, kWalkLength, kStep / 3);
  ASSERT_GT(scale, 1.0) << "the walk bends the tail";
  std::vector<Vec3> a(6), b(6), c(6), d(6);
  for (double t = 0.0123; t < 1.5; t += 0.0371) {  // between samples, and across the period's seam
    lasting.at(t, a);
    lasting.at(t + kWalkLength, b);
    lasting.at(t + 17 * kWalkLength, c);
    brief.at(t + 17 * kWalkLength, d);
    for (int i = 0; i < 6; ++i) {
      // Equal but for the rounding of t + k L (ulps of 18 s, over a sample's 2 ms).
      EXPECT_NEAR((b[i] - a[i]).norm(), 0, 1e-9 * scale) << t << " s, section " << i;
      EXPECT_NEAR((c[i] - a[i]).norm(), 0, 1e-9 * scale) << t << " s, section " << i;
      EXPECT_EQ(d[i], c[i]) << t << " s, section " << i;
    }
    EXPECT_EQ(lasting.loads_between(t, t + kStep),
              lasting.loads_between(t + 9 * kWalkLength, t + 9 * kWalkLength + kStep));
  }
}

// A clip that does not loop holds its first pose before it and its last after it: its bend is zero
// outside the clip (scene time 0 is the simulator's `preroll`), and holds samples over the clip's
// span alone, whatever the bake's length.
TEST(KeyedBend, AHeldClipIsZeroAfterItsEnd) {
  const WalkingTail w;
  const double preroll = 0.5;
  const assets::SkinnedClip clip = w.clip(false, preroll);
  const sim::KeyedBend brief = clip.keyed_bend(0, 3.0, kStep);
  const sim::KeyedBend lasting = clip.keyed_bend(0, 20.0, kStep);
  EXPECT_EQ(lasting.samples(), brief.samples());
  EXPECT_LE(lasting.samples(), std::llround(kWalkLength / kStep) + 7);  // the span, a sample each side and margins
  EXPECT_EQ(lasting.period(), 0);
  const double end = preroll + kWalkLength;
  EXPECT_GT(largest(lasting, preroll, end, kStep / 3), 1.0) << "the walk bends the tail";
  EXPECT_EQ(largest(lasting, end + 2 * kStep, 20.0, kStep / 2), 0);
  EXPECT_EQ(largest(lasting, 0, preroll - 2 * kStep, kStep / 2), 0);
  EXPECT_FALSE(lasting.loads_between(end + 2 * kStep, 20.0));
  EXPECT_FALSE(lasting.loads_between(0, preroll - 2 * kStep));
  EXPECT_TRUE(lasting.loads_between(0, 20.0));
}

// A repeating bend wraps around its period: one section's four samples over a 1 s period (phase 0
// at 0.25 s), only the last (phase 0.75 s) non-zero: halfway from it to the first it is half its
// value, at any period before or after, and it loads just the pieces beside it.
TEST(KeyedBend, ARepeatingBendWrapsAroundItsPeriod) {
  const Eigen::Vector3f peak(4, -2, 1);
  const sim::KeyedBend bend = sim::KeyedBend::repeating(
      1.0, 0.25, 1, {Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero(), peak});
  EXPECT_EQ(bend.samples(), 4);
  EXPECT_DOUBLE_EQ(bend.spacing(), 0.25);
  std::vector<Vec3> a(1);
  for (const double t : {0.125, 1.125, -2.875, 7.125}) {  // phase 0.875
    bend.at(t, a);
    EXPECT_NEAR((a[0] - 0.5 * peak.cast<double>()).norm(), 0, 1e-12) << t;
  }
  bend.at(0.25 + 0.5 + 3, a);  // phase 0.5: between two zeros
  EXPECT_EQ(a[0], Vec3::Zero());
  bend.at(0.25 + 0.625 + 3, a);  // phase 0.625: halfway from sample 2 (zero) to the peak
  EXPECT_NEAR((a[0] - 0.5 * peak.cast<double>()).norm(), 0, 1e-12);
  EXPECT_FALSE(bend.loads_between(3.25 + 0.05, 3.25 + 0.2));  // phase 0.05 .. 0.2: samples 0 and 1
  EXPECT_TRUE(bend.loads_between(3.25 + 0.9, 3.25 + 1.05));   // phase 0.9 .. 1.05: across the seam
  EXPECT_TRUE(bend.loads_between(3.25 + 0.55, 3.25 + 0.6));   // the piece rising to the peak
  EXPECT_TRUE(bend.loads_between(0, 5));                      // longer than the period
}

}  // namespace
}  // namespace sweep::test
