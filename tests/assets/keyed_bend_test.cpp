// A skinned part lags and overshoots its keyed pose like a driven oscillator (assets/skinned_clip.h,
// sim/keyed_bend.h): its deviation q from the keyed pose obeys q'' + 2ζω0 q' + ω0² q = −a, a the
// acceleration its keys give it, whether they move its root joint (the base) or the joints that bend
// it below its root. On the committed creature meshes/skinned_tail.gltf (Hip -> Tail1 -> Tail2 ->
// Tail3, the tail from z = 0 to 1) with its clips replaced here by a sway of one joint, and the tail
// a part of one spring section (the paper's springs: the tip's positional spring alone carries it).
// The closed form is computed here, from the springs' settings and the keys.
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

#include "bind/support.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/core/springs.h"
#include "sweep/io/read_file.h"
#include "sweep/io/rig_json.h"

namespace sweep::test {
namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

// The part's springs: f0 = 2 Hz, ζ = 0.15; the sway keyed every kKeyStep s over a 1 s loop.
constexpr double kF0 = 2.0, kZeta = 0.15;
constexpr double kAmplitude = 0.05;  // of the keyed sway, 5 % of the tail's length
constexpr int kKeys = 60;            // keys a second (the clip is 1 s long)
constexpr int kFps = 30;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(SWEEP_BINARY_DIR) / "tests/assets/keyed_bend" / name;
  fs::create_directories(dir);
  return dir;
}

std::string base64(const std::string& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k) v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? digits[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
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
  const fs::path dir = scratch(name);
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

}  // namespace
}  // namespace sweep::test
