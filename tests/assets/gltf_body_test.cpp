// The body driven by a glTF file's own animation of a node: the path read from the file
// against the closed form B(t) = P · L(t) · L0⁻¹ · P⁻¹, refusals that name what is wrong, and
// sweep-sim baking a scene whose body is {"node": ...}: the parts' root side follows the node.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "base64.h"
#include "bind/support.h"
#include "sweep/assets/gltf_motion.h"
#include "sweep/core/error.h"
#include "sweep/io/rig_json.h"

namespace sweep::test {
namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;

// A glTF document under construction: one buffer, accessors appended.
struct GltfBuilder {
  Json doc = {{"asset", {{"version", "2.0"}}},
              {"nodes", Json::array()},
              {"accessors", Json::array()},
              {"bufferViews", Json::array()}};
  std::string bytes;
  int add(const std::vector<float>& values, const char* type, int count) {
    const std::size_t offset = bytes.size();
    bytes.append(reinterpret_cast<const char*>(values.data()), values.size() * 4);
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * 4}});
    Json a = {{"bufferView", doc["bufferViews"].size() - 1}, {"componentType", 5126}, {"count", count}, {"type", type}};
    doc["accessors"].push_back(a);
    return static_cast<int>(doc["accessors"].size()) - 1;
  }
  int add_indices(const std::vector<std::uint32_t>& values) {
    const std::size_t offset = bytes.size();
    bytes.append(reinterpret_cast<const char*>(values.data()), values.size() * 4);
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * 4}});
    doc["accessors"].push_back({{"bufferView", doc["bufferViews"].size() - 1},
                                {"componentType", 5125},
                                {"count", values.size()},
                                {"type", "SCALAR"}});
    return static_cast<int>(doc["accessors"].size()) - 1;
  }
  void write(const fs::path& path) {
    doc["buffers"] =
        Json::array({{{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + base64(bytes)}}});
    std::ofstream(path) << doc.dump();
  }
};

std::vector<float> quat_xyzw(const Quat& q) {
  return {float(q.x()), float(q.y()), float(q.z()), float(q.w())};
}
Quat turn_y(double degrees) {
  return Quat(Eigen::AngleAxisd(degrees * std::numbers::pi / 180, Vec3::UnitY()));
}

// Root (translation P) → Body (rest translation T0, rotation R0 = 30° about y): translation keys
// at 0, 1, 2 s, rotation keys (turns about y on top of R0) at 0 and 1.5 s.
struct Scenario {
  Vec3 P{1, 0, 0}, T0{0, 0.5, 0};
  double turn_end = 40;  // degrees at 1.5 s
  std::vector<Vec3> T{{0, 0.5, 0}, {0.25, 0.5, 0}, {0.25, 0.5, 0.125}};
  Quat R0 = turn_y(30);
  bool zero_quaternion = false;  // the rotation key at 1.5 s written as [0, 0, 0, 0]

  // The closed form: B(x) = Ry(θ)(x − P − T0) + P + T(t), θ(t) linear to turn_end over [0, 1.5].
  sim::BodyState expected(double t) const {
    const double theta = turn_end * std::clamp(t / 1.5, 0.0, 1.0);
    const double u = std::clamp(t, 0.0, 2.0);
    const Vec3 Tt = u <= 1 ? T[0] + u * (T[1] - T[0]) : T[1] + (u - 1) * (T[2] - T[1]);
    sim::BodyState s;
    s.rotation = turn_y(theta);
    s.translation = P + Tt - s.rotation * (P + T0);
    return s;
  }

  void write(const fs::path& path, const std::string& interpolation = "LINEAR", bool scale_channel = false) const {
    GltfBuilder g;
    g.doc["nodes"] =
        Json::array({{{"name", "Root"}, {"translation", {P.x(), P.y(), P.z()}}, {"children", {1}}},
                     {{"name", "Body"}, {"translation", {T0.x(), T0.y(), T0.z()}}, {"rotation", quat_xyzw(R0)}}});
    const int tt = g.add({0, 1, 2}, "SCALAR", 3);
    std::vector<float> tv;
    for (const Vec3& v : T) tv.insert(tv.end(), {float(v.x()), float(v.y()), float(v.z())});
    const int tvals = g.add(tv, "VEC3", 3);
    const int rt = g.add({0, 1.5f}, "SCALAR", 2);
    std::vector<float> rv = quat_xyzw(R0);
    const std::vector<float> r1 = zero_quaternion ? std::vector<float>(4, 0.0f) : quat_xyzw(turn_y(turn_end) * R0);
    rv.insert(rv.end(), r1.begin(), r1.end());
    const int rvals = g.add(rv, "VEC4", 2);
    Json samplers = Json::array({{{"input", tt}, {"output", tvals}, {"interpolation", interpolation}},
                                 {{"input", rt}, {"output", rvals}, {"interpolation", "LINEAR"}}});
    Json channels = Json::array({{{"sampler", 0}, {"target", {{"node", 1}, {"path", "translation"}}}},
                                 {{"sampler", 1}, {"target", {{"node", 1}, {"path", "rotation"}}}}});
    if (scale_channel) {
      const int sv = g.add({1, 1, 1, 2, 2, 2}, "VEC3", 2);
      samplers.push_back({{"input", rt}, {"output", sv}});
      channels.push_back({{"sampler", 2}, {"target", {{"node", 1}, {"path", "scale"}}}});
    }
    g.doc["animations"] = Json::array({{{"name", "Walk"}, {"samplers", samplers}, {"channels", channels}}});
    g.write(path);
  }
};

fs::path body_scratch_file(const std::string& name) {
  const fs::path dir = fs::path(SWEEP_BINARY_DIR) / "tests/assets/gltf_body";
  fs::create_directories(dir);
  return dir / name;
}

TEST(GltfBody, TheNodesAnimationIsTheBodysMotionAwayFromItsRestPose) {
  const Scenario sc;
  const fs::path file = body_scratch_file("walk.gltf");
  sc.write(file);
  const sim::BodyPath path = assets::read_gltf_body_path(file, "Body");
  ASSERT_EQ(path.keys().size(), 4u);  // the union of 0, 1, 2 and 0, 1.5
  EXPECT_EQ(path.interpolation(), sim::BodyInterpolation::linear);
  double worst = 0;
  for (double t = -0.5; t <= 2.5; t += 1.0 / 64) {
    const sim::BodyState got = path.at(t), want = sc.expected(t);
    // The file holds float32: a few 1e-7 of the unit sizes here.
    worst = std::max({worst, (got.translation - want.translation).norm(), got.rotation.angularDistance(want.rotation)});
  }
  EXPECT_LT(worst, 2e-6);
  // The named animation is the same one; another name is refused with the names.
  EXPECT_EQ(assets::read_gltf_body_path(file, "Body", "Walk").keys().size(), 4u);
  expect_refused([&] { assets::read_gltf_body_path(file, "Body", "Run"); }, ErrorCategory::bad_input,
                 {"walk.gltf", "no animation named 'Run' moves node 'Body'"});
}

// About a pivot the mesh's origin swings: its velocity and acceleration (what the parts feel) are
// the derivatives of where it goes, checked by central differences inside each linear piece.
TEST(GltfBody, APivotedPathsOriginMovesAsItsDerivativesSay) {
  const Scenario sc;
  const fs::path file = body_scratch_file("pivot.gltf");
  sc.write(file);
  const sim::BodyPath path = assets::read_gltf_body_path(file, "Body");
  EXPECT_LT((path.pivot() - (sc.P + sc.T0)).norm(), 1e-7);  // the node's rest origin, world
  const double h = 1e-4;
  for (double t : {0.3, 0.7, 1.2, 1.7}) {
    const sim::BodyState s = path.at(t), before = path.at(t - h), after = path.at(t + h);
    const Vec3 v = (after.translation - before.translation) / (2 * h);
    const Vec3 a = s.rotation.conjugate() * ((after.translation - 2 * s.translation + before.translation) / (h * h));
    EXPECT_LT((s.velocity - v).norm(), 1e-6) << t;
    EXPECT_LT((s.acceleration - a).norm(), 1e-4) << t;
  }
  // Where the turn goes on (t < 1.5) the origin is accelerated towards the pivot: centripetal.
  EXPECT_GT(path.at(0.7).acceleration.norm(), 0.01);
  EXPECT_LT(path.at(1.7).acceleration.norm(), 1e-12);  // the turn is over: straight and steady
}

TEST(GltfBody, WhatCannotBeABodysMotionIsRefusedWithWhatToDo) {
  const Scenario sc;
  const fs::path file = body_scratch_file("refused.gltf");
  sc.write(file);
  expect_refused([&] { assets::read_gltf_body_path(file, "Tail"); }, ErrorCategory::bad_input,
                 {"refused.gltf", "no node is named 'Tail'"});
  // The parent is not animated: "Root" is moved by nothing.
  expect_refused([&] { assets::read_gltf_body_path(file, "Root"); }, ErrorCategory::bad_input,
                 {"no animation moves node 'Root'"});
  sc.write(file, "CUBICSPLINE");
  expect_refused([&] { assets::read_gltf_body_path(file, "Body"); }, ErrorCategory::bad_input,
                 {"CUBICSPLINE", "only LINEAR"});
  sc.write(file, "LINEAR", /*scale_channel=*/true);
  expect_refused([&] { assets::read_gltf_body_path(file, "Body"); }, ErrorCategory::bad_input, {"scales node 'Body'"});
  const fs::path obj = body_scratch_file("not-gltf.obj");
  std::ofstream(obj) << "v 0 0 0\n";
  expect_refused([&] { assets::read_gltf_body_path(obj, "Body"); }, ErrorCategory::bad_input, {"not a glTF file"});
}

// A key the file can hold but no body can follow: a translation past the limit of any length (a
// finite 1e35 used to stop the run halfway as "not finite", exit 5), a rotation of no length (used
// to be taken as no rotation). Refused before anything is simulated, naming the key.
TEST(GltfBody, AKeyPastTheLengthLimitOrOfNoRotationIsRefusedNamingIt) {
  Scenario far;
  far.T[1] = Vec3(1e35, 0.5, 0);
  const fs::path file = body_scratch_file("far.gltf");
  far.write(file);
  expect_refused([&] { assets::read_gltf_body_path(file, "Body"); }, ErrorCategory::bad_input,
                 {"far.gltf: animation 'Walk': translation key 1 of node 'Body' (at 1 s) is ",
                  " along x, past the limit of 1e9 mesh units"});
  Scenario zero;
  zero.zero_quaternion = true;
  const fs::path nothing = body_scratch_file("zero-quaternion.gltf");
  zero.write(nothing);
  expect_refused([&] { assets::read_gltf_body_path(nothing, "Body"); }, ErrorCategory::bad_input,
                 {"zero-quaternion.gltf: animation 'Walk': rotation key 1 of node 'Body' (at 1.5 s) is a quaternion of "
                  "length 0, not a rotation"});
}

// sweep-sim on a glTF tube whose node "Body" is animated: the scene says only {"node": "Body"}.
// The .pc2 holds world positions, so every vertex on the root side of the part (never bound)
// is exactly the node's motion applied to its rest position, frame by frame.
TEST(GltfBody, SweepSimBakesTheBodyFromTheMeshsOwnAnimation) {
  const Mesh tube = tube::make_tube(straight_tube_params());
  GltfBuilder g;
  std::vector<float> positions;
  for (const Vec3& p : tube.positions) positions.insert(positions.end(), {float(p.x()), float(p.y()), float(p.z())});
  const int pos = g.add(positions, "VEC3", static_cast<int>(tube.vertex_count()));
  const std::vector<std::uint32_t> tri = tube.triangles();
  const int idx = g.add_indices(tri);
  g.doc["accessors"][pos]["min"] = {-1, -1, -1};
  g.doc["accessors"][pos]["max"] = {1, 1, 2};
  g.doc["meshes"] = Json::array({{{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}}}});
  g.doc["nodes"] = Json::array({{{"name", "Body"}, {"mesh", 0}}});
  g.doc["scenes"] = Json::array({{{"nodes", {0}}}});
  g.doc["scene"] = 0;
  const int times = g.add({0, 0.5f, 1}, "SCALAR", 3);
  const int moves = g.add({0, 0, 0, 0.5f, 0, 0, 0.5f, 0.25f, 0}, "VEC3", 3);
  const std::vector<float> q0 = quat_xyzw(Quat::Identity()), q1 = quat_xyzw(turn_y(20)), q2 = quat_xyzw(turn_y(45));
  std::vector<float> turns = q0;
  turns.insert(turns.end(), q1.begin(), q1.end());
  turns.insert(turns.end(), q2.begin(), q2.end());
  const int turn = g.add(turns, "VEC4", 3);
  g.doc["animations"] =
      Json::array({{{"samplers", {{{"input", times}, {"output", moves}}, {{"input", times}, {"output", turn}}}},
                    {"channels",
                     {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}},
                      {{"sampler", 1}, {"target", {{"node", 0}, {"path", "rotation"}}}}}}}});
  const fs::path mesh = body_scratch_file("tube.gltf"), rig = body_scratch_file("tube.rig.json"),
                 bind = body_scratch_file("tube.bind"), scene = body_scratch_file("walk.scene.json"),
                 pc2 = body_scratch_file("tube.pc2");
  g.write(mesh);
  io::write_rig(rig, rig_of({straight_sweep("tube", false)}, "tube.gltf"));
  std::ofstream(scene) << R"({"format": "sweep-scene", "version": 1, "duration": 1.5, "fps": 10,
    "body": {"node": "Body"}, "forces": [{"sweep": "tube", "t": 1, "theta": 0, "vector": [0, 0, 1], "start": 0.2, "end": 0.4}]})";
  ASSERT_EQ(
      std::system((std::string(SWEEP_BIND_EXE) + " -q '" + rig.string() + "' -o '" + bind.string() + "'").c_str()), 0);
  ASSERT_EQ(std::system((std::string(SWEEP_SIM_EXE) + " -q '" + rig.string() + "' --scene '" + scene.string() +
                         "' -b '" + bind.string() + "' -o '" + pc2.string() + "'")
                            .c_str()),
            0);
  std::ifstream in(pc2, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::int32_t points = 0, samples = 0;
  std::memcpy(&points, bytes.data() + 16, 4);
  std::memcpy(&samples, bytes.data() + 28, 4);
  ASSERT_EQ(points, static_cast<std::int32_t>(tube.vertex_count()));
  ASSERT_EQ(samples, 16);
  const sim::BodyPath path = assets::read_gltf_body_path(mesh, "Body");
  // The closed form of the file's keys (lerp and slerp), checked on the path first.
  for (double t : {0.25, 0.75, 1.2}) {
    const Quat want_q = t <= 0.5 ? Quat::Identity().slerp(t / 0.5, turn_y(20))
                                 : turn_y(20).slerp(std::min(1.0, (t - 0.5) / 0.5), turn_y(45));
    EXPECT_LT(path.at(t).rotation.angularDistance(want_q), 1e-6) << t;
  }
  int root_side = 0;
  double worst = 0;
  for (std::size_t v = 0; v < tube.vertex_count(); ++v) {
    if (tube.positions[v].z() > 0) continue;  // the root cap: behind the root plane, never bound
    ++root_side;
    for (int k = 0; k < samples; ++k) {
      const sim::BodyState b = path.at(k / 10.0);
      const Vec3 want = b.rotation * tube.positions[v].cast<float>().cast<double>() + b.translation;
      float got[3];
      std::memcpy(got, bytes.data() + 32 + 12 * (static_cast<std::size_t>(k) * points + v), 12);
      worst = std::max(worst, (Vec3(got[0], got[1], got[2]) - want).norm());
    }
  }
  EXPECT_GT(root_side, 0);
  EXPECT_LT(worst, 1e-6);  // float32 output
  // And the body moved: the last frame is not the rest pose.
  EXPECT_GT((path.at(1.5).translation - Vec3::Zero()).norm(), 0.5);
}

}  // namespace
}  // namespace sweep::test
