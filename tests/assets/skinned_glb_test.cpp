// The .glb bake of a skinned character's clip with --morph: the input asset whole (skeleton, skin,
// every clip, material, image, UV set, names and extras) plus the parts' motion as morph targets
// under the skin (assets/gltf_passthrough.h). On a copy of the committed creature meshes/skinned_tail.gltf given a
// textured material, two UV sets, normals and extras, the file is read back with tinygltf and
// skinned here, as an engine plays its new animation: morph weights first, then linear blend
// skinning with the animation's keys, against the .pc2 of the same run. Then what it refuses, and
// --under-skin's cache (the bake before skinning).
#include <iostream>
#include <numbers>

#include "assets/skinned_glb_support.h"

namespace sweep::test {
namespace {

using namespace skinned_glb;

// The walk baked once to .glb and .pc2 for the tests below (the asset, the bake's files).
struct WalkBake {
  Asset asset;
  fs::path glb, pc2;
  bool ok = false;
};
const WalkBake& walk_bake() {
  static const WalkBake bake = [] {
    WalkBake b{setup("walk"), here("walk.glb"), here("walk.pc2")};
    b.ok = run_sim(b.asset, kWalk, "-o '" + b.glb.string() + "' -o '" + b.pc2.string() + "'", "walk", "--morph") == 0;
    return b;
  }();
  return bake;
}

// The asset whole, and its new animation, played as an engine plays it (morph weights, then the
// skin), is the .pc2 at every frame; the skin alone is far from it.
TEST(SkinnedGlbMorph, KeepsTheAssetWholeAndPlaysTheBake) {
  const WalkBake& walk = walk_bake();
  ASSERT_TRUE(walk.ok) << io::read_file(here("walk.err"));
  const tinygltf::Model in = load(walk.asset.gltf), out = load(walk.glb);

  // The asset whole: nodes and their names, the skin's joints, every clip with its keys, the
  // material, texture, sampler and image (its bytes), both UV sets, the extras.
  ASSERT_EQ(out.nodes.size(), in.nodes.size());
  for (std::size_t n = 0; n < in.nodes.size(); ++n) EXPECT_EQ(out.nodes[n].name, in.nodes[n].name);
  ASSERT_EQ(out.skins.size(), 1u);
  EXPECT_EQ(out.skins[0].joints, in.skins[0].joints);
  EXPECT_EQ(numbers(out, out.skins[0].inverseBindMatrices), numbers(in, in.skins[0].inverseBindMatrices));
  ASSERT_EQ(out.animations.size(), in.animations.size() + 1);
  for (std::size_t a = 0; a < in.animations.size(); ++a) {
    const tinygltf::Animation &before = in.animations[a], &after = out.animations[a];
    EXPECT_EQ(after.name, before.name);
    ASSERT_EQ(after.channels.size(), before.channels.size());
    for (std::size_t c = 0; c < before.channels.size(); ++c) {
      EXPECT_EQ(after.channels[c].target_node, before.channels[c].target_node);
      EXPECT_EQ(after.channels[c].target_path, before.channels[c].target_path);
      const auto &sb = before.samplers[static_cast<std::size_t>(before.channels[c].sampler)],
                 &sa = after.samplers[static_cast<std::size_t>(after.channels[c].sampler)];
      EXPECT_EQ(sa.interpolation, sb.interpolation);
      EXPECT_EQ(numbers(out, sa.input), numbers(in, sb.input));
      EXPECT_EQ(numbers(out, sa.output), numbers(in, sb.output));
    }
  }
  ASSERT_EQ(out.materials.size(), 1u);
  EXPECT_EQ(out.materials[0].name, "Hide");
  EXPECT_EQ(out.materials[0].pbrMetallicRoughness.baseColorTexture.texCoord, 1);
  ASSERT_EQ(out.textures.size(), 1u);
  EXPECT_EQ(out.textures[0].name, "hide texture");
  ASSERT_EQ(out.images.size(), 1u);
  EXPECT_EQ(out.images[0].name, "hide");
  EXPECT_EQ(out.images[0].mimeType, "image/png");
  const tinygltf::BufferView& image = out.bufferViews[static_cast<std::size_t>(out.images[0].bufferView)];
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(out.buffers[0].data.data() + image.byteOffset), image.byteLength),
            tiny_png());
  const tinygltf::Primitive &pin = in.meshes[0].primitives[0], &pout = out.meshes[0].primitives[0];
  for (const char* uv : {"TEXCOORD_0", "TEXCOORD_1"}) {
    ASSERT_TRUE(pout.attributes.contains(uv)) << uv;
    EXPECT_EQ(numbers(out, pout.attributes.at(uv)), numbers(in, pin.attributes.at(uv))) << uv;
  }
  EXPECT_EQ(pout.material, 0);
  EXPECT_EQ(out.nodes[4].extras.Get("bone").Get<std::string>(), "tail tip");
  EXPECT_EQ(out.asset.extras.Get("author").Get<std::string>(), "test");

  const int bake = find_animation(out, "sweep bake");
  ASSERT_GE(bake, 0);
  const Pc2 cache(walk.pc2);
  const int frames = cache.frames;
  ASSERT_EQ(frames, 31);
  ASSERT_EQ(pout.targets.size(), 31u);
  const std::vector<double> times = numbers(out, out.animations[static_cast<std::size_t>(bake)].samplers[0].input);
  ASSERT_EQ(times.size(), 31u);
  for (int k = 0; k < frames; ++k) EXPECT_FLOAT_EQ(static_cast<float>(times[k]), static_cast<float>(k / 30.0));
  const double length = 1.0;  // the tail's
  const std::vector<double> indices = numbers(out, pout.indices);
  double worst = 0, unmorphed = 0, worst_normal = 0, turned = 0, clip_off_surface = 0;
  for (int k = 0; k < frames; ++k) {
    const Shown shown = played(out, bake, static_cast<std::size_t>(k));
    ASSERT_EQ(shown.positions.size(), static_cast<std::size_t>(cache.points));
    const Shown clip_only = played(out, bake, static_cast<std::size_t>(k), /*morph=*/false);
    for (std::size_t v = 0; v < shown.positions.size(); ++v) {
      worst = std::max(worst, (shown.positions[v] - cache.at(k, v)).norm());
      unmorphed = std::max(unmorphed, (clip_only.positions[v] - cache.at(k, v)).norm());
    }
    // The normals shown are the clip's (the file's, skinned) turned as the surface turns from the
    // clip's pose to the bake's: by the shortest rotation between the two surfaces' normals there
    // (area-weighted over the faces round a vertex), on the tube between its ends.
    auto surface = [&](const std::function<Vec3(std::size_t)>& at) {
      std::vector<Vec3> n(shown.positions.size(), Vec3::Zero());
      for (std::size_t f = 0; f + 2 < indices.size(); f += 3) {
        const auto a = static_cast<std::size_t>(indices[f]), b = static_cast<std::size_t>(indices[f + 1]),
                   c = static_cast<std::size_t>(indices[f + 2]);
        const Vec3 face = (at(b) - at(a)).cross(at(c) - at(a));
        for (const std::size_t v : {a, b, c}) n[v] += face;
      }
      for (Vec3& x : n) x.normalize();
      return n;
    };
    const std::vector<Vec3> baked = surface([&](std::size_t v) { return cache.at(k, v); });
    const std::vector<Vec3> keyed = surface([&](std::size_t v) { return clip_only.positions[v]; });
    auto degrees = [](const Vec3& a, const Vec3& b) {
      return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180 / std::numbers::pi;
    };
    for (std::size_t v = 2 * 24; v < 39 * 24; ++v) {
      const Vec3 want = Quat::FromTwoVectors(keyed[v], baked[v]) * clip_only.normals[v];
      worst_normal = std::max(worst_normal, degrees(shown.normals[v], want));
      turned = std::max(turned, degrees(keyed[v], baked[v]));
      clip_off_surface = std::max(clip_off_surface, degrees(clip_only.normals[v], keyed[v]));
    }
  }
  EXPECT_LT(worst, 1e-5 * length);
  EXPECT_GT(unmorphed, 1e-2 * length) << "the tail hardly left its skinned pose: the check above could not fail";
  EXPECT_LT(worst_normal, 0.5);
  EXPECT_GT(turned, 5.0) << "the bake hardly turned the surface: the check above could not fail";
  std::cout << "skinned .glb against the .pc2: " << worst << " of the tail's length (the skin alone: " << unmorphed
            << "); normals off the clip's turned with the surface " << worst_normal << " deg (the surface turns up to "
            << turned << " deg; the clip's own skinned normals are up to " << clip_off_surface
            << " deg off its skinned surface)\n";
}

TEST(SkinnedGlbMorph, PassesTheKhronosValidator) {
  const WalkBake& bake = walk_bake();
  ASSERT_TRUE(bake.ok) << io::read_file(here("walk.err"));
  int code = -1;
  const std::string report = validate(bake.glb, &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numErrors\": 0"), std::string::npos) << report;
}

// What the --morph .glb of a skinned clip cannot carry is refused with exit 3 (unsupported), saying
// what to do, and nothing is written: a skinned primitive with morph targets of its own, compressed
// geometry; --morph with --joints is a usage error.
TEST(SkinnedGlbMorph, RefusesWhatItCannotCarry) {
  auto refused = [](const Asset& s, const std::string& name, const std::string& extra, const char* says) {
    const fs::path glb = here(name + ".glb"), pc2 = here(name + ".pc2");
    fs::remove(glb);
    fs::remove(pc2);
    EXPECT_EQ(run_sim(s, kWalk, "-o '" + glb.string() + "' -o '" + pc2.string() + "'", name, extra), 3) << name;
    const std::string err = io::read_file(here(name + ".err"));
    EXPECT_NE(err.find(says), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(glb)) << name;
    EXPECT_FALSE(fs::exists(pc2)) << name;
  };
  const Asset targets = setup("targets", [](Json& d) {
    d["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", 0}}};  // the POSITION accessor: valid data
  });
  refused(targets, "targets", "--morph", "already has morph targets");
  refused(setup("meshopt", [](Json& d) { d["extensionsUsed"] = {"EXT_meshopt_compression"}; }), "meshopt", "--morph",
          "EXT_meshopt_compression");
  // --morph and --joints ask for two different .glb bakes: a usage error (exit 1), nothing written.
  const fs::path glb = here("both.glb");
  fs::remove(glb);
  EXPECT_EQ(run_sim(targets, kWalk, "-o '" + glb.string() + "'", "both", "--morph --joints 4"), 1);
  EXPECT_NE(io::read_file(here("both.err")).find("--morph and --joints"), std::string::npos);
  EXPECT_FALSE(fs::exists(glb));
}

// --under-skin: the .pc2 holds each vertex before skinning (bind space), so skinning it by the
// clip — here the .glb's own joints and weights, its morph targets left out — is the world .pc2;
// a vertex no part moves is its POSITION.
TEST(SkinnedGlbMorph, UnderSkinTheCacheIsTheBakeBeforeSkinning) {
  const WalkBake& walk = walk_bake();
  ASSERT_TRUE(walk.ok) << io::read_file(here("walk.err"));
  const Asset& s = walk.asset;
  const fs::path under = here("under.pc2");
  ASSERT_EQ(run_sim(s, kWalk, "-o '" + under.string() + "'", "under", "--under-skin"), 0)
      << io::read_file(here("under.err"));
  const tinygltf::Model out = load(walk.glb);
  const Pc2 w(walk.pc2), u(under);
  ASSERT_EQ(u.frames, w.frames);
  ASSERT_EQ(u.points, w.points);
  const int bake = find_animation(out, "sweep bake");
  ASSERT_GE(bake, 0);
  const std::vector<double> position = numbers(out, out.meshes[0].primitives[0].attributes.at("POSITION"));
  double worst = 0, off_position = 0;
  std::size_t at_position = 0;
  for (int k = 0; k < u.frames; ++k) {
    std::vector<double> base;
    for (int v = 0; v < u.points; ++v) {
      const Vec3 p = u.at(k, static_cast<std::size_t>(v));
      base.insert(base.end(), {p.x(), p.y(), p.z()});
      const Vec3 b(position[3 * v], position[3 * v + 1], position[3 * v + 2]);
      if (p == b) ++at_position;
      off_position = std::max(off_position, (p - b).norm());
    }
    const std::vector<Vec3> skinned = played(out, bake, static_cast<std::size_t>(k), /*morph=*/false, &base).positions;
    for (std::size_t v = 0; v < skinned.size(); ++v) worst = std::max(worst, (skinned[v] - w.at(k, v)).norm());
  }
  EXPECT_LT(worst, 1e-5 * 1.0) << "the tail's length is 1";
  EXPECT_GT(off_position, 1e-2) << "the tail hardly moved: the check above could not fail";
  // The body's 8 vertices and the tail's 25 root-cap vertices at least, every frame.
  EXPECT_GE(at_position, static_cast<std::size_t>(u.frames) * 8);
  std::cout << "under-skin .pc2 skinned against the world .pc2: " << worst << "\n";
  // Without a skinned clip there is nothing to write under: exit 1.
  EXPECT_EQ(run_sim(s, R"({"format": "sweep-scene", "version": 1, "duration": 0.1, "fps": 30, "forces": []})",
                    "-o '" + here("plain.pc2").string() + "'", "plain", "--under-skin"),
            1);
}

}  // namespace
}  // namespace sweep::test
