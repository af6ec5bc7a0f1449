// A skinned character's own clip drives the bake (assets/gltf_skin.h, assets/skinned_clip.h), on the
// committed generated creature meshes/skinned_tail.gltf (meshes/make_skinned_tail.py: a box body and
// a tail skinned to Hip -> Tail1 -> Tail2 -> Tail3, clip "Walk"). Every expectation is computed here
// a second way: the clip's keys restated from the generator, composed into joint matrices and
// skinned by this file's own code.
#include "sweep/assets/skinned_clip.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "bind/support.h"
#include "pc2_reader.h"
#include "sweep/assets/gltf_skin.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/bind/bind.h"
#include "sweep/core/error.h"
#include "sweep/core/springs.h"
#include "sweep/io/read_file.h"
#include "sweep/io/rig_json.h"

namespace sweep::test {
namespace {

using Json = nlohmann::json;
using Mat4 = Eigen::Matrix4d;
namespace fs = std::filesystem;

fs::path fixture() {
  return fs::path(SWEEP_SOURCE_DIR) / "meshes/skinned_tail.gltf";
}

fs::path clip_scratch_file(const std::string& name) {
  const fs::path dir = fs::path(SWEEP_BINARY_DIR) / "tests/assets/skinned_clip";
  fs::create_directories(dir);
  return dir / name;
}

Quat about(const Vec3& axis, double degrees) {
  return Quat(Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis));
}
Mat4 trs(const Vec3& t, const Quat& r) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = r.toRotationMatrix();
  m.topRightCorner<3, 1>() = t;
  return m;
}
// Piecewise linear through (times, values).
double lerp_keys(const std::vector<double>& times, const std::vector<double>& values, double t) {
  if (t <= times.front()) return values.front();
  for (std::size_t k = 0; k + 1 < times.size(); ++k) {
    if (t <= times[k + 1]) return values[k] + (t - times[k]) / (times[k + 1] - times[k]) * (values[k + 1] - values[k]);
  }
  return values.back();
}
// glTF's cubic Hermite spline of one component (tangents times the key interval dt).
double hermite(double v0, double b0, double v1, double a1, double s, double dt) {
  return (2 * s * s * s - 3 * s * s + 1) * v0 + (s * s * s - 2 * s * s + s) * dt * b0 +
         (-2 * s * s * s + 3 * s * s) * v1 + (s * s * s - s * s) * dt * a1;
}

// The clip "Walk", restated from meshes/make_skinned_tail.py.
const std::vector<double> kHipTimes{0, 0.25, 0.5, 0.75, 1};
Vec3 hip_translation(double t) {
  return Vec3(lerp_keys(kHipTimes, {0, 0.03, 0, -0.03, 0}, t), lerp_keys(kHipTimes, {0, 0.04, 0, 0.04, 0}, t), -0.3);
}
// Turns about one axis: slerp is the angle's lerp.
Quat hip_rotation(double t) {
  return about(Vec3::UnitY(), lerp_keys(kHipTimes, {0, 15, 0, -15, 0}, t));
}
Quat tail1_rotation(double t) {
  // Keys at 0, 0.5, 1 (-10, 10, -10 degrees about x); in/out tangents on the x component only.
  const Quat q[3] = {about(Vec3::UnitX(), -10), about(Vec3::UnitX(), 10), about(Vec3::UnitX(), -10)};
  const double in[3] = {0, -0.2, 0.4}, out[3] = {0.4, -0.2, 0};
  t = std::clamp(t, 0.0, 1.0);
  const int k = t < 0.5 ? 0 : 1;
  const double s = (t - 0.5 * k) / 0.5;
  const Eigen::Vector4d a = q[k].coeffs(), b = q[k + 1].coeffs();  // x, y, z, w
  Eigen::Vector4d v;
  for (int c = 0; c < 4; ++c) v[c] = hermite(a[c], c == 0 ? out[k] : 0, b[c], c == 0 ? in[k + 1] : 0, s, 0.5);
  v.normalize();
  return Quat(v[3], v[0], v[1], v[2]);
}
Quat tail2_rotation(double t) {
  return about(Vec3::UnitX(), t < 0.5 ? -15 : 15);
}
Quat tail3_rotation(double t) {
  return about(Vec3::UnitY(), lerp_keys({0, 0.5, 1}, {0, 20, 0}, t));
}

// Joint matrices J_k = World(k) · IBM_k of Hip, Tail1, Tail2, Tail3 at clip time t.
std::vector<Mat4> joints_at(double t) {
  const Mat4 hip = trs(hip_translation(t), hip_rotation(t));
  const Mat4 tail1 = hip * trs(Vec3(0, 0, 0.3), tail1_rotation(t));
  const Mat4 tail2 = tail1 * trs(Vec3(0, 0, 0.33), tail2_rotation(t));
  const Mat4 tail3 = tail2 * trs(Vec3(0, 0, 0.33), tail3_rotation(t));
  const double rest_z[4] = {-0.3, 0, 0.33, 0.66};
  std::vector<Mat4> out;
  for (int k = 0; const Mat4& world : {hip, tail1, tail2, tail3})
    out.push_back(world * trs(Vec3(0, 0, -rest_z[k++]), Quat::Identity()));
  return out;
}
// The generator's weights, by the bind position.
std::array<double, 4> weights_of(const Vec3& p) {
  const double z = p.z();
  if (z < -0.3) return {1, 0, 0, 0};
  if (z < 0) return {0.6, 0.4, 0, 0};
  const double w1 = z <= 0.1 ? 1 : std::max(0.0, (0.4 - z) / 0.3);
  const double w2 = z <= 0.1 ? 0 : z <= 0.4 ? (z - 0.1) / 0.3 : std::max(0.0, (0.75 - z) / 0.35);
  const double w3 = z <= 0.4 ? 0 : std::min(1.0, (z - 0.4) / 0.35);
  return {0, w1, w2, w3};
}
Vec3 skinned(const Vec3& p, const std::vector<Mat4>& joints) {
  const std::array<double, 4> w = weights_of(p);
  Eigen::Vector4d out = Eigen::Vector4d::Zero();
  for (int k = 0; k < 4; ++k) out += w[k] * (joints[k] * p.homogeneous());
  return out.head<3>();
}

// The creature's rig (the tail as the binding tests' hand-made straight sweep) and its binding.
struct Creature {
  fs::path rig, binding, gltf;
  Mesh mesh;
  Rig rig_data;
  bind::Binding bound;
};
Creature creature(const std::string& name, double spring_hz = 0) {
  Creature c;
  // Each creature in a folder of its own: ctest runs this file's tests as parallel processes, and a
  // fixture copied over the one another test is reading tears it.
  const fs::path dir = clip_scratch_file(name);
  fs::create_directories(dir);
  c.rig = dir / "rig.json";
  c.binding = dir / "rig.bind";
  c.gltf = dir / "skinned_tail.gltf";
  fs::copy_file(fixture(), c.gltf, fs::copy_options::overwrite_existing);
  c.rig_data = rig_of({straight_sweep("tail", false)}, "skinned_tail.gltf");
  if (spring_hz > 0) {  // every spring of every section this stiff, critically damped
    SweepDef& def = c.rig_data.sweeps[0];
    for (SpringSettings* k : {&def.default_springs.positional, &def.default_springs.bend, &def.default_springs.twist})
      *k = SpringSettings{1.0, spring_hz, 1.0};
    def.springs.assign(def.rest.frames.size(), def.default_springs);
  }
  io::write_rig(c.rig, c.rig_data);
  c.mesh = assets::read_mesh(c.gltf);
  EXPECT_EQ(std::system(
                (std::string(SWEEP_BIND_EXE) + " -q '" + c.rig.string() + "' -o '" + c.binding.string() + "'").c_str()),
            0);
  c.bound = bind::bind(c.rig_data, c.mesh).binding;
  return c;
}

int run_sim(const Creature& c, const std::string& scene_json, const fs::path& out, const std::string& name) {
  const fs::path scene = clip_scratch_file(name + ".scene.json");
  std::ofstream(scene) << scene_json;
  const std::string cmd = std::string(SWEEP_SIM_EXE) + " -q '" + c.rig.string() + "' --scene '" + scene.string() +
                          "' -b '" + c.binding.string() + "' -o '" + out.string() + "' 2> '" +
                          clip_scratch_file(name + ".err").string() + "'";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The committed creature is its generator's output, byte for byte.
TEST(SkinnedClip, TheFixtureIsItsGeneratorsOutput) {
  if (std::system("python3 --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "no python3";
  const fs::path out = clip_scratch_file("regenerated.gltf");
  ASSERT_EQ(std::system(("python3 '" + (fs::path(SWEEP_SOURCE_DIR) / "meshes/make_skinned_tail.py").string() + "' '" +
                         out.string() + "'")
                            .c_str()),
            0);
  EXPECT_EQ(io::read_file(out), io::read_file(fixture()));
}

TEST(SkinnedClip, ChannelsInterpolateAsGltfDefines) {
  const Mesh mesh = assets::read_mesh(fixture());
  const auto model = assets::read_gltf_skin(fixture(), mesh.positions, Eigen::Affine3d::Identity());
  ASSERT_TRUE(model);
  ASSERT_EQ(model->clips.size(), 2u);
  const assets::SkinClip& walk = model->clips[model->find_clip("Walk")];
  auto channel = [&](const std::string& node, assets::ChannelPath path) -> const assets::ClipChannel& {
    for (const assets::ClipChannel& c : walk.channels)
      if (model->nodes[c.node].name == node && c.path == path) return c;
    throw std::runtime_error("no channel");
  };
  auto as_quat = [](const Eigen::Vector4d& v) { return Quat(v[3], v[0], v[1], v[2]); };
  for (double t : {-0.5, 0.0, 0.1, 0.25, 0.3, 0.49, 0.5, 0.51, 0.8, 1.0, 1.7}) {
    const double u = std::clamp(t, 0.0, 1.0);  // held before the first key and after the last
    EXPECT_LT(
        (assets::channel_value(channel("Hip", assets::ChannelPath::translation), t).head<3>() - hip_translation(u))
            .norm(),
        1e-7)
        << t;
    EXPECT_LT(as_quat(assets::channel_value(channel("Hip", assets::ChannelPath::rotation), t))
                  .angularDistance(hip_rotation(u)),
              1e-6)
        << t;
    EXPECT_LT(as_quat(assets::channel_value(channel("Tail1", assets::ChannelPath::rotation), t))
                  .angularDistance(tail1_rotation(u)),
              1e-6)
        << t;
    EXPECT_LT(as_quat(assets::channel_value(channel("Tail2", assets::ChannelPath::rotation), t))
                  .angularDistance(tail2_rotation(u)),
              1e-6)
        << t;
    EXPECT_LT(as_quat(assets::channel_value(channel("Tail3", assets::ChannelPath::rotation), t))
                  .angularDistance(tail3_rotation(u)),
              1e-6)
        << t;
  }
  // The cubic's tangents are scaled by the key interval: at the middle of the first piece the
  // x component is (v0 + v1)/2 + dt·(b0 − a1)/8 before normalizing, not the tangents alone.
  const Eigen::Vector4d mid = assets::channel_value(channel("Tail1", assets::ChannelPath::rotation), 0.25);
  const double x = 0.5 * (about(Vec3::UnitX(), -10).x() + about(Vec3::UnitX(), 10).x()) + 0.5 * (0.4 - -0.2) / 8;
  const double w = 0.5 * (about(Vec3::UnitX(), -10).w() + about(Vec3::UnitX(), 10).w());
  EXPECT_NEAR(mid[0], x / std::hypot(x, w), 1e-6);
  // The whole pose: the model's skinning against this file's, every vertex, at several times.
  double worst = 0;
  for (double t : {0.0, 0.13, 0.5, 0.77}) {
    const auto joints = assets::joint_matrices(*model, assets::world_transforms(*model, model->find_clip("Walk"), t));
    const auto mine = joints_at(t);
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
      worst = std::max(worst, (assets::skin_vertex(*model, joints, v) - skinned(mesh.positions[v], mine)).norm());
  }
  EXPECT_LT(worst, 1e-6);
}

// sweep-sim plays the clip: outside the tail every vertex is the clip's skinning, the tail's root
// ring follows Tail1, and the tail itself is simulated (it leaves its keyed pose).
TEST(SkinnedClip, TheClipDrivesTheBodyAndThePartsRoot) {
  const Creature c = creature("drive");
  const fs::path pc2 = clip_scratch_file("drive.pc2");
  ASSERT_EQ(run_sim(c, R"({"format": "sweep-scene", "version": 1, "duration": 2, "fps": 30, "forces": [],
    "body": {"node": "Hip", "animation": "Walk", "loop": true}})",
                    pc2, "drive"),
            0)
      << io::read_file(clip_scratch_file("drive.err"));
  const Pc2 out(pc2);
  ASSERT_EQ(out.points, static_cast<int>(c.mesh.vertex_count()));
  ASSERT_EQ(out.frames, 61);
  std::vector<double> weight(c.mesh.vertex_count(), 0);
  for (std::size_t k = 0; k < c.bound.sweeps[0].size(); ++k)
    weight[c.bound.sweeps[0].vertices[k]] = c.bound.sweeps[0].weight[k];
  const double size = 1.7;  // the creature's bounding box diagonal, about
  double outside = 0, ring = 0, tip_off_keyed = 0;
  int ring_count = 0;
  for (int f = 0; f < out.frames; ++f) {
    const double t = std::fmod(f / 30.0, 1.0);
    const auto joints = joints_at(t);
    for (std::size_t v = 0; v < c.mesh.vertex_count(); ++v) {
      const Vec3& p = c.mesh.positions[v];
      if (weight[v] == 0) outside = std::max(outside, (out.at(f, v) - skinned(p, joints)).norm());
      if (p.z() == 0) {
        ring = std::max(ring, (out.at(f, v) - (joints[1] * p.homogeneous()).head<3>()).norm());
        ring_count += f == 0;
      }
      if (p.z() == 1) tip_off_keyed = std::max(tip_off_keyed, (out.at(f, v) - skinned(p, joints)).norm());
    }
  }
  EXPECT_LT(outside, 1e-5 * size);
  EXPECT_EQ(ring_count, 25);  // the root ring and its cap centre
  EXPECT_LT(ring, 1e-5 * size);
  EXPECT_GT(tip_off_keyed, 1e-2);  // the tail is simulated, not only keyed
  std::cout << "outside the part: " << outside << ", root ring: " << ring
            << ", tip off its keyed pose: " << tip_off_keyed << "\n";
}

// With very stiff springs the tail follows its own keyed pose (the clip's skinning of its
// vertices, the joints below its root swaying it) within 0.5 % of its length.
TEST(SkinnedClip, AStiffPartFollowsItsKeyedPose) {
  const Creature c = creature("stiff", 60);
  const fs::path pc2 = clip_scratch_file("stiff.pc2");
  ASSERT_EQ(run_sim(c, R"({"format": "sweep-scene", "version": 1, "duration": 2, "fps": 30, "forces": [],
    "body": {"node": "Tail2", "animation": "Walk", "loop": true}})",
                    pc2, "stiff"),
            0)
      << io::read_file(clip_scratch_file("stiff.err"));
  const Pc2 out(pc2);
  double worst = 0, keyed_sway = 0;
  for (int f = 0; f < out.frames; ++f) {
    const auto joints = joints_at(std::fmod(f / 30.0, 1.0));
    for (const std::uint32_t v : c.bound.sweeps[0].vertices) {
      const Vec3& p = c.mesh.positions[v];
      worst = std::max(worst, (out.at(f, v) - skinned(p, joints)).norm());
      keyed_sway = std::max(keyed_sway, (skinned(p, joints) - (joints[1] * p.homogeneous()).head<3>()).norm());
    }
  }
  EXPECT_LT(worst, 0.005 * 1.0) << "the tail's length is 1";
  EXPECT_GT(keyed_sway, 0.1);  // the keys bend the tail well away from its root joint's rigid pose
  std::cout << "stiff tail off its keyed pose: " << worst << " (the keys bend it " << keyed_sway << " off rigid)\n";
}

// A looping clip after a preroll: the bake's last frame (one clip length on) meets its first.
TEST(SkinnedClip, ALoopingBakeAfterAPrerollMeetsItsFirstFrame) {
  const Creature c = creature("loop");
  const fs::path pc2 = clip_scratch_file("loop.pc2");
  ASSERT_EQ(run_sim(c, R"({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 30, "forces": [],
    "body": {"node": "Creature", "animation": "Walk", "loop": true, "preroll": 6}})",
                    pc2, "loop"),
            0)
      << io::read_file(clip_scratch_file("loop.err"));
  // The same without the preroll: the tail starts at rest, so its first cycle does not close.
  const fs::path cold = clip_scratch_file("cold.pc2");
  ASSERT_EQ(run_sim(c, R"({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 30, "forces": [],
    "body": {"node": "Creature", "animation": "Walk", "loop": true}})",
                    cold, "cold"),
            0);
  auto seam_of = [&](const Pc2& out) {
    double seam = 0;
    for (std::size_t v = 0; v < c.mesh.vertex_count(); ++v)
      seam = std::max(seam, (out.at(30, v) - out.at(0, v)).norm());
    return seam;
  };
  const Pc2 out(pc2), out_cold(cold);
  ASSERT_EQ(out.frames, 31);
  const double seam = seam_of(out), cold_seam = seam_of(out_cold);
  EXPECT_LT(seam, 1e-3 * 1.0) << "the tail's length is 1";
  EXPECT_GT(cold_seam, 1e-3);
  std::cout << "loop seam: " << seam << " of the tail's length after the preroll, " << cold_seam << " without\n";
}

// What the file holds is listed when the scene asks for what it does not.
TEST(SkinnedClip, BadInputSaysWhatTheFileHolds) {
  const Creature c = creature("bad");
  const auto model = assets::read_gltf_skin(c.gltf, c.mesh.positions, Eigen::Affine3d::Identity());
  ASSERT_TRUE(model);
  auto make = [&](const std::string& node, const std::string& clip) {
    assets::SkinnedClip(fixture(), *model, Eigen::Affine3d::Identity(), c.rig_data, c.bound, node, clip, true, 0, 30);
  };
  expect_refused([&] { make("Nose", "Walk"); }, ErrorCategory::bad_input,
                 {"'Nose'", "not a node", "'Hip', 'Tail1', 'Tail2', 'Tail3'"});
  expect_refused([&] { make("Eye", "Walk"); }, ErrorCategory::bad_input,
                 {"neither the skinned mesh's node nor a joint", "'Creature'"});
  expect_refused([&] { make("Hip", "Run"); }, ErrorCategory::bad_input,
                 {"no animation is named 'Run'", "'Walk', 'Blink'"});
  expect_refused([&] { make("Hip", "Blink"); }, ErrorCategory::bad_input,
                 {"'Blink' moves none of the joints", "(it moves 'Eye')"});
  // The root joint found from the weights: Tail1 holds the whole root ring.
  const assets::SkinnedClip walk(fixture(), *model, Eigen::Affine3d::Identity(), c.rig_data, c.bound, "Hip", "Walk",
                                 true, 0, 30);
  EXPECT_EQ(model->nodes[walk.root_joint_node(0)].name, "Tail1");

  // Edited copies of the file.
  const Json doc = Json::parse(io::read_file(fixture()));
  auto refused_file = [&](const std::function<void(Json&)>& edit, std::initializer_list<const char*> fragments) {
    Json d = doc;
    edit(d);
    const fs::path path = clip_scratch_file("edited.gltf");
    std::ofstream(path) << d.dump();
    expect_refused([&] { assets::read_gltf_skin(path, c.mesh.positions, Eigen::Affine3d::Identity()); },
                   ErrorCategory::bad_input, fragments);
  };
  refused_file([](Json& d) { d["meshes"][0]["primitives"][0]["attributes"]["JOINTS_1"] = 1; },
               {"more than 4 joint influences"});
  refused_file(
      [](Json& d) {
        // All four inverse bind matrices zero: a second buffer of 256 zero bytes.
        d["buffers"].push_back(
            {{"byteLength", 256}, {"uri", "data:application/octet-stream;base64," + std::string(340, 'A') + "AA=="}});
        d["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 0}, {"byteLength", 256}});
        d["accessors"].push_back(
            {{"bufferView", d["bufferViews"].size() - 1}, {"componentType", 5126}, {"count", 4}, {"type", "MAT4"}});
        d["skins"][0]["inverseBindMatrices"] = d["accessors"].size() - 1;
      },
      {"inverse bind matrix of joint 'Hip'", "not an invertible affine transform"});
  // A scale channel on the tail's root joint.
  Json d = doc;
  d["animations"][0]["channels"].push_back({{"sampler", 0}, {"target", {{"node", 2}, {"path", "scale"}}}});
  // Sampler 0's VEC3 values are the hip's translations (z = -0.3): as a scale, a mirror and a squash.
  const fs::path scaled = clip_scratch_file("scaled.gltf");
  std::ofstream(scaled) << d.dump();
  const auto scaled_model = assets::read_gltf_skin(scaled, c.mesh.positions, Eigen::Affine3d::Identity());
  ASSERT_TRUE(scaled_model);
  const assets::SkinnedClip clip(scaled, *scaled_model, Eigen::Affine3d::Identity(), c.rig_data, c.bound, "Hip", "Walk",
                                 true, 0, 30);
  expect_refused([&] { (void)clip.sweep_path(0, 1.0); }, ErrorCategory::bad_input,
                 {"root joint 'Tail1'", "scaled or sheared"});
}

// sweep-sim refuses a clip the file does not hold (exit 2, listing those it does), before anything
// is written.
TEST(SkinnedClip, SweepSimRefusesAnUnknownClipWithWhatToDo) {
  const Creature c = creature("run");
  // An unknown clip: exit 2 (bad input), the file's clips listed, nothing written.
  const fs::path pc2 = clip_scratch_file("run.pc2");
  fs::remove(pc2);
  EXPECT_EQ(run_sim(c, R"({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 30, "forces": [],
    "body": {"node": "Creature", "animation": "Run"}})",
                    pc2, "run"),
            2);
  EXPECT_NE(io::read_file(clip_scratch_file("run.err")).find("'Walk', 'Blink'"), std::string::npos)
      << io::read_file(clip_scratch_file("run.err"));
  EXPECT_FALSE(fs::exists(pc2));
}

}  // namespace
}  // namespace sweep::test
