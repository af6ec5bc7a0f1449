// The default .glb bake of a skinned character's clip: the input asset whole with the parts' joints
// added to ITS skeleton (assets/character_joints.h, gltf_character_joints.h). On the creature of
// skinned_glb_support.h given a third clip, "Wag" (Tail1 swung about y, Hip bobbing: LINEAR keys,
// so that the test can sample it at any time), the file is read back with tinygltf and skinned here
// by linear blend skinning: "sweep bake" at every frame against the .pc2, and "Wag" at the new
// joints' key times against the input file's own skinning.
#include <iostream>

#include "assets/skinned_glb_support.h"
#include "sweep/io/binding_file.h"

namespace sweep::test {
namespace {

using namespace skinned_glb;

// The creature with "Wag": Tail1 and Tail2 (nodes 2, 3) turned by the keys of Walk's Tail3 channel
// (about y: 0, 20, 0 degrees over a second), so that the tail bends, and Hip (node 1) moved by
// Walk's translation keys.
void add_wag(Json& doc) {
  Json wag = {{"name", "Wag"}, {"samplers", Json::array()}, {"channels", Json::array()}};
  const Json& walk = doc["animations"][0];
  for (const Json& c : walk["channels"]) {
    const int node = c["target"]["node"];
    const std::string path = c["target"]["path"];
    const Json& sampler = walk["samplers"][c["sampler"].get<std::size_t>()];
    const bool tail3_turn = node == 4 && path == "rotation", hip_bob = node == 1 && path == "translation";
    if (!tail3_turn && !hip_bob) continue;
    wag["samplers"].push_back(sampler);
    for (const int target : tail3_turn ? std::vector<int>{2, 3} : std::vector<int>{1})
      wag["channels"].push_back(
          {{"sampler", wag["samplers"].size() - 1}, {"target", {{"node", target}, {"path", path}}}});
  }
  doc["animations"].push_back(std::move(wag));
}

struct JointsBake {
  Asset asset;
  fs::path glb, pc2, report;
  bool ok = false;
};
const JointsBake& joints_bake() {
  static const JointsBake bake = [] {
    JointsBake b{setup("joints", add_wag), here("joints.glb"), here("joints.pc2"), here("joints.report.json")};
    b.ok = run_sim(b.asset, kWalk, "-o '" + b.glb.string() + "' -o '" + b.pc2.string() + "'", "joints",
                   "--report '" + b.report.string() + "'") == 0;
    return b;
  }();
  return bake;
}

// A channel's value at time t (LINEAR: lerp, rotations by slerp; STEP), held outside its keys.
Eigen::Vector4d sample(const tinygltf::Model& m, const tinygltf::AnimationSampler& s, int width, double t) {
  const std::vector<double> times = numbers(m, s.input), values = numbers(m, s.output);
  EXPECT_NE(s.interpolation, "CUBICSPLINE");
  auto key = [&](std::size_t k) {
    Eigen::Vector4d v = Eigen::Vector4d::Zero();
    for (int c = 0; c < width; ++c) v[c] = values[k * width + c];
    return v;
  };
  if (t <= times.front()) return key(0);
  if (t >= times.back()) return key(times.size() - 1);
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  if (s.interpolation == "STEP") return key(k);
  const double u = (t - times[k]) / (times[k + 1] - times[k]);
  if (width == 4) {
    const Quat a(key(k)[3], key(k)[0], key(k)[1], key(k)[2]),
        b(key(k + 1)[3], key(k + 1)[0], key(k + 1)[1], key(k + 1)[2]);
    const Quat q = a.slerp(u, b);
    return Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
  }
  return (1 - u) * key(k) + u * key(k + 1);
}

// The mesh as clip `animation` shows it at time t: every node's transform sampled, then linear
// blend skinning with the file's skin, inverse bind matrices, joints and weights.
std::vector<Vec3> skinned_at(const tinygltf::Model& m, int animation, double t) {
  NodePoses pose = rest_poses(m);
  std::vector<Vec3>&tr = pose.t, &sc = pose.s;
  std::vector<Quat>& r = pose.r;
  const tinygltf::Animation& a = m.animations[static_cast<std::size_t>(animation)];
  for (const tinygltf::AnimationChannel& ch : a.channels) {
    const auto n = static_cast<std::size_t>(ch.target_node);
    const auto& s = a.samplers[static_cast<std::size_t>(ch.sampler)];
    if (ch.target_path == "rotation") {
      const Eigen::Vector4d q = sample(m, s, 4, t);
      r[n] = Quat(q[3], q[0], q[1], q[2]);
    } else {
      const Eigen::Vector4d v = sample(m, s, 3, t);
      (ch.target_path == "scale" ? sc[n] : tr[n]) = v.head<3>();
    }
  }
  const std::vector<Mat4> joint = skin_joint_matrices(m, pose);
  const tinygltf::Primitive& p = m.meshes[0].primitives[0];
  const std::vector<double> position = numbers(m, p.attributes.at("POSITION"));
  const std::vector<double> joints = numbers(m, p.attributes.at("JOINTS_0")),
                            weight = numbers(m, p.attributes.at("WEIGHTS_0"));
  std::vector<Vec3> out;
  for (std::size_t v = 0; v < position.size() / 3; ++v) {
    Mat4 skinning = Mat4::Zero();
    for (int e = 0; e < 4; ++e) skinning += weight[4 * v + e] * joint[static_cast<std::size_t>(joints[4 * v + e])];
    out.push_back((skinning * Vec3(position[3 * v], position[3 * v + 1], position[3 * v + 2]).homogeneous()).head<3>());
  }
  return out;
}

// The asset whole (nodes and names, the skin's joints and matrices, every clip's own channels,
// material, image, UV sets, extras), the parts' joints added under the tail's root joint, and
// weights that are weights: at most 4, non-negative, summing to 1; outside the tail the input's.
TEST(SkinnedJoints, KeepsTheAssetWholeAndAddsThePartsJointsToItsSkeleton) {
  const JointsBake& bake = joints_bake();
  ASSERT_TRUE(bake.ok) << io::read_file(here("joints.err"));
  const tinygltf::Model in = load(bake.asset.gltf), out = load(bake.glb);
  ASSERT_GT(out.nodes.size(), in.nodes.size());
  for (std::size_t n = 0; n < in.nodes.size(); ++n) EXPECT_EQ(out.nodes[n].name, in.nodes[n].name);
  ASSERT_EQ(out.skins.size(), 1u);
  const std::size_t added = out.nodes.size() - in.nodes.size();
  ASSERT_EQ(out.skins[0].joints.size(), in.skins[0].joints.size() + added);
  for (std::size_t j = 0; j < in.skins[0].joints.size(); ++j) EXPECT_EQ(out.skins[0].joints[j], in.skins[0].joints[j]);
  const std::vector<double> ibm_in = numbers(in, in.skins[0].inverseBindMatrices),
                            ibm_out = numbers(out, out.skins[0].inverseBindMatrices);
  EXPECT_EQ(std::vector<double>(ibm_out.begin(), ibm_out.begin() + static_cast<long>(ibm_in.size())), ibm_in);
  // The new joints: stations "tail.00" … under Tail1 (node 2, the tail's root joint), ring joints
  // "tail.03.r05" … under their station.
  std::vector<int> parent(out.nodes.size(), -1);
  for (std::size_t n = 0; n < out.nodes.size(); ++n)
    for (int c : out.nodes[n].children) parent[static_cast<std::size_t>(c)] = static_cast<int>(n);
  std::size_t stations = 0;
  for (std::size_t n = in.nodes.size(); n < out.nodes.size(); ++n) {
    const std::string& name = out.nodes[n].name;
    EXPECT_EQ(name.rfind("tail.", 0), 0u) << name;
    EXPECT_EQ(out.skins[0].joints[in.skins[0].joints.size() + (n - in.nodes.size())], static_cast<int>(n));
    if (name.find(".r") == std::string::npos) {
      ++stations;
      EXPECT_EQ(parent[n], 2) << name;
    } else {
      ASSERT_GE(parent[n], static_cast<int>(in.nodes.size())) << name;
      EXPECT_EQ(name.rfind(out.nodes[static_cast<std::size_t>(parent[n])].name + ".r", 0), 0u) << name;
    }
  }
  EXPECT_GE(stations, 2u);
  // Every clip of the input, its own channels first and unchanged; "sweep bake" added.
  ASSERT_EQ(out.animations.size(), in.animations.size() + 1);
  ASSERT_EQ(in.animations.size(), 3u);
  for (std::size_t a = 0; a < in.animations.size(); ++a) {
    const tinygltf::Animation &before = in.animations[a], &after = out.animations[a];
    EXPECT_EQ(after.name, before.name);
    ASSERT_GT(after.channels.size(), before.channels.size()) << before.name << ": the new joints are keyed in it";
    for (std::size_t c = 0; c < before.channels.size(); ++c) {
      EXPECT_EQ(after.channels[c].target_node, before.channels[c].target_node);
      EXPECT_EQ(after.channels[c].target_path, before.channels[c].target_path);
      const auto &sb = before.samplers[static_cast<std::size_t>(before.channels[c].sampler)],
                 &sa = after.samplers[static_cast<std::size_t>(after.channels[c].sampler)];
      EXPECT_EQ(sa.interpolation, sb.interpolation);
      EXPECT_EQ(numbers(out, sa.input), numbers(in, sb.input));
      EXPECT_EQ(numbers(out, sa.output), numbers(in, sb.output));
    }
    for (std::size_t c = before.channels.size(); c < after.channels.size(); ++c)
      EXPECT_GE(after.channels[c].target_node, static_cast<int>(in.nodes.size())) << "only the new joints are added";
  }
  EXPECT_EQ(out.animations.back().name, "sweep bake");
  ASSERT_EQ(out.materials.size(), 1u);
  EXPECT_EQ(out.materials[0].name, "Hide");
  ASSERT_EQ(out.images.size(), 1u);
  EXPECT_EQ(out.images[0].name, "hide");
  const tinygltf::BufferView& image = out.bufferViews[static_cast<std::size_t>(out.images[0].bufferView)];
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(out.buffers[0].data.data() + image.byteOffset), image.byteLength),
            tiny_png());
  const tinygltf::Primitive &pin = in.meshes[0].primitives[0], &pout = out.meshes[0].primitives[0];
  for (const char* attribute : {"POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1"}) {
    ASSERT_TRUE(pout.attributes.contains(attribute)) << attribute;
    EXPECT_EQ(numbers(out, pout.attributes.at(attribute)), numbers(in, pin.attributes.at(attribute))) << attribute;
  }
  EXPECT_TRUE(pout.targets.empty());
  EXPECT_EQ(out.nodes[4].extras.Get("bone").Get<std::string>(), "tail tip");
  EXPECT_EQ(out.asset.extras.Get("author").Get<std::string>(), "test");

  // Weights.
  const std::vector<char> part = part_vertices(bake.asset);
  const std::vector<double> jin = numbers(in, pin.attributes.at("JOINTS_0")),
                            win = numbers(in, pin.attributes.at("WEIGHTS_0"));
  const std::vector<double> jout = numbers(out, pout.attributes.at("JOINTS_0")),
                            wout = numbers(out, pout.attributes.at("WEIGHTS_0"));
  ASSERT_EQ(wout.size(), 4 * part.size());
  std::size_t on_new = 0;
  for (std::size_t v = 0; v < part.size(); ++v) {
    float sum = 0;
    for (std::size_t e = 0; e < 4; ++e) {
      EXPECT_GE(wout[4 * v + e], 0.0) << v;
      sum += static_cast<float>(wout[4 * v + e]);
      if (wout[4 * v + e] > 0 && jout[4 * v + e] >= static_cast<double>(in.skins[0].joints.size())) ++on_new;
    }
    EXPECT_NEAR(sum, 1.0, 1e-6) << v;
    if (part[v]) continue;
    for (std::size_t e = 0; e < 4; ++e) {
      EXPECT_EQ(jout[4 * v + e], jin[4 * v + e]) << v;
      EXPECT_EQ(wout[4 * v + e], win[4 * v + e]) << v;
    }
  }
  EXPECT_GT(on_new, 500u) << "the tail's vertices are weighted to its new joints";
}

TEST(SkinnedJoints, PassesTheKhronosValidator) {
  const JointsBake& bake = joints_bake();
  ASSERT_TRUE(bake.ok) << io::read_file(here("joints.err"));
  int code = -1;
  const std::string report = validate(bake.glb, &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numErrors\": 0"), std::string::npos) << report;
}

// "sweep bake" skinned here at every frame is the .pc2: the tail within the skinned-export error
// the bake reports (and under 1 % of its length), every other vertex as the clip skins it.
TEST(SkinnedJoints, TheBakedClipSkinnedIsTheBake) {
  const JointsBake& bake = joints_bake();
  ASSERT_TRUE(bake.ok) << io::read_file(here("joints.err"));
  const tinygltf::Model out = load(bake.glb);
  const int baked = find_animation(out, "sweep bake");
  ASSERT_GE(baked, 0);
  const Pc2 cache(bake.pc2);
  ASSERT_EQ(cache.frames, 31);
  const std::vector<char> part = part_vertices(bake.asset);
  const double length = 1.0;  // the tail's; the box is 1.2 long
  double worst = 0, sum_squares = 0, worst_outside = 0, moved = 0;
  std::size_t samples = 0;
  for (int k = 0; k < cache.frames; ++k) {
    const std::vector<Vec3> shown = played(out, baked, static_cast<std::size_t>(k), /*morph=*/false).positions;
    ASSERT_EQ(shown.size(), part.size());
    for (std::size_t v = 0; v < shown.size(); ++v) {
      const double e = (shown[v] - cache.at(k, v)).norm();
      if (part[v]) {
        worst = std::max(worst, e);
        sum_squares += e * e;
        ++samples;
        moved = std::max(moved, (cache.at(k, v) - cache.at(0, v)).norm());
      } else {
        worst_outside = std::max(worst_outside, e);
      }
    }
  }
  const Json report = Json::parse(io::read_file(bake.report));
  EXPECT_TRUE(report.value("skin_joints_in_character", false));
  const double reported = report.at("skin_error_max_relative").get<double>();
  EXPECT_LE(worst / length, reported * (1 + 1e-3) + 1e-6) << "the error the bake reports is the file's";
  EXPECT_LT(worst, 0.01 * length);
  EXPECT_LT(worst_outside, 1e-5 * length);
  EXPECT_GT(moved, 0.1 * length) << "the tail hardly moved: the checks above could not fail";
  std::cout << "skinned-export error of the joints .glb against the .pc2: max " << worst / length << ", RMS "
            << std::sqrt(sum_squares / static_cast<double>(samples)) / length << " of the tail's length (reported max "
            << reported << "); outside the tail " << worst_outside << "\n";
}

// "Wag", another clip of the file, plays the tail's original skinned motion: at the new joints'
// key times, the output skinned by it is the input skinned by it — the tail within the same kind
// of bound, every other vertex to float precision.
TEST(SkinnedJoints, AnotherClipPlaysThePartsOriginalMotion) {
  const JointsBake& bake = joints_bake();
  ASSERT_TRUE(bake.ok) << io::read_file(here("joints.err"));
  const tinygltf::Model in = load(bake.asset.gltf), out = load(bake.glb);
  const int wag = find_animation(out, "Wag");
  ASSERT_EQ(wag, 2);
  const tinygltf::Animation& a = out.animations[2];
  const std::vector<double> times = numbers(out, a.samplers[static_cast<std::size_t>(a.channels.back().sampler)].input);
  ASSERT_EQ(times.size(), 31u) << "keys every 1/30 s over the clip's second";
  const std::vector<char> part = part_vertices(bake.asset);
  double worst = 0, worst_outside = 0, swing = 0;
  for (const double t : times) {
    const std::vector<Vec3> original = skinned_at(in, 2, t), played = skinned_at(out, 2, t),
                            rest = skinned_at(in, 2, 0);
    for (std::size_t v = 0; v < part.size(); ++v) {
      const double e = (played[v] - original[v]).norm();
      (part[v] ? worst : worst_outside) = std::max(part[v] ? worst : worst_outside, e);
      if (part[v]) swing = std::max(swing, (original[v] - rest[v]).norm());
    }
  }
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(worst_outside, 1e-5);
  EXPECT_GT(swing, 0.1) << "Wag hardly moved the tail: the check above could not fail";
  std::cout << "Wag: the tail against its original skinning, max " << worst << " of its length (it swings " << swing
            << "); outside it " << worst_outside << "\n";
}

}  // namespace
}  // namespace sweep::test
