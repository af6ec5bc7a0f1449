#pragma once
// A small textured glTF asset written by the tests themselves: a creature whose tail is
// a tube sweep-fit can fit, with UVs, vertex colours, normals and tangents, a textured material on
// the tube's side and a plain one on its caps, a node tree Creature → Tail (Tail: translation,
// rotation and a non-uniform scale), a head node with no mesh, a second mesh Ground with its own
// material and an animation of its own ("Idle"). The JSON is `creature.gltf`; the buffer and the
// texture are files beside it (`creature.bin`, `skin.png`), so a bake must embed them.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "tool_runner.h"

namespace sweep::test {

// A 2 × 2 RGB PNG (red, green / blue, yellow).
inline std::string tiny_png() {
  static const char bytes[] =
      "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x02\x00\x00\x00\x02"
      "\x08\x02\x00\x00\x00\xfd\xd4\x9a\x73\x00\x00\x00\x14\x49\x44\x41\x54\x78\x9c\x63\xf8\xcf\xc0\xc0"
      "\x00\xc2\x0c\xff\xff\xff\x67\x00\x00\x1e\xef\x04\xfc\xa3\xc8\xb4\xf7\x00\x00\x00\x00\x49\x45\x4e"
      "\x44\xae\x42\x60\x82";
  return std::string(bytes, sizeof bytes - 1);
}

// A .glb of a glTF document whose one buffer is `bin` (the document's buffers[0] without a uri): the
// JSON chunk padded with spaces, the BIN chunk with zeros, as the container asks.
inline std::string glb_bytes(const nlohmann::json& doc, const std::string& bin) {
  std::string text = doc.dump();
  text.append((4 - text.size() % 4) % 4, ' ');
  std::string padded = bin;
  padded.append((4 - padded.size() % 4) % 4, '\0');
  std::string glb = "glTF";
  auto u32 = [&](std::uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
  u32(2);
  u32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + padded.size()));
  u32(static_cast<std::uint32_t>(text.size()));
  glb += "JSON" + text;
  u32(static_cast<std::uint32_t>(padded.size()));
  glb += std::string("BIN\0", 4) + padded;
  return glb;
}

// Whether Blender is installed (it writes the FBX files; tests that need it skip without).
inline bool have_blender() {
  return std::system("command -v blender > /dev/null 2>&1") == 0;
}

// Blender converts `obj` (+ its .mtl and textures) to `fbx` with tests/blender/obj_to_fbx.py: the
// OBJ's coordinates, the texture embedded; `unit_args` as that script takes them ("" = metres).
inline ToolRun obj_to_fbx(const fs::path& obj, const fs::path& fbx, const fs::path& io,
                          const std::string& unit_args = "") {
  const fs::path script = fs::path(SWEEP_SOURCE_DIR) / "tests/blender/obj_to_fbx.py";
  return run_tool("blender",
                  "-b --factory-startup --python-exit-code 1 --python " + quoted(script) + " -- " + quoted(obj) + " " +
                      quoted(fbx) + unit_args,
                  io);
}

struct TexturedAsset {
  static constexpr int kRings = 33, kSegments = 24;
  static constexpr double kLength = 1.0, kRadius = 0.1;
  // The Tail node's world transform (Creature · Tail), for seeds and checks.
  static Eigen::Affine3d creature() {
    Eigen::Affine3d a = Eigen::Affine3d::Identity();
    a.translate(Eigen::Vector3d(0.3, 0.2, -0.1));
    a.rotate(Eigen::AngleAxisd(std::numbers::pi / 6, Eigen::Vector3d::UnitY()));
    return a;
  }
  static Eigen::Affine3d tail_local() {
    Eigen::Affine3d a = Eigen::Affine3d::Identity();
    a.translate(Eigen::Vector3d(0, 0.1, 0.05));
    a.rotate(Eigen::AngleAxisd(-std::numbers::pi / 9, Eigen::Vector3d::UnitX()));
    a.scale(Eigen::Vector3d(1.2, 1.2, 1.5));
    return a;
  }
  static Eigen::Affine3d tail_world() { return creature() * tail_local(); }
  // Side primitive: ring i, segment j = 0 .. kSegments (the last repeats the first's position:
  // the UV seam) at vertex i * (kSegments + 1) + j.
  static int side_vertices() { return kRings * (kSegments + 1); }
  static int cap_vertices() { return 2 * kSegments + 2; }
};

// Writes creature.gltf, creature.bin and skin.png into `dir`; returns the document.
inline nlohmann::json write_textured_asset(const fs::path& dir) {
  using Doc = nlohmann::json;
  using A = TexturedAsset;
  std::string bin;
  Doc views = Doc::array(), accessors = Doc::array();
  auto add = [&](const void* data, std::size_t bytes, int component, const char* type, std::size_t count, int target) {
    bin.append((4 - bin.size() % 4) % 4, '\0');
    Doc view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
    if (target) view["target"] = target;
    bin.append(static_cast<const char*>(data), bytes);
    views.push_back(view);
    accessors.push_back(
        {{"bufferView", views.size() - 1}, {"componentType", component}, {"count", count}, {"type", type}});
    return accessors.size() - 1;
  };
  auto floats = [&](const std::vector<float>& v, const char* type, int width, bool bounds = false) {
    const std::size_t a = add(v.data(), 4 * v.size(), 5126, type, v.size() / width, 34962);
    if (bounds) {
      Doc lo = Doc::array(), hi = Doc::array();
      for (int c = 0; c < width; ++c) {
        float l = v[c], h = v[c];
        for (std::size_t k = c; k < v.size(); k += width) l = std::min(l, v[k]), h = std::max(h, v[k]);
        lo.push_back(l);
        hi.push_back(h);
      }
      accessors[a]["min"] = lo;
      accessors[a]["max"] = hi;
    }
    return a;
  };
  auto indices = [&](const std::vector<std::uint32_t>& v) {
    return add(v.data(), 4 * v.size(), 5125, "SCALAR", v.size(), 34963);
  };

  // The tail's side: positions, normals, tangents, UVs, colours.
  std::vector<float> pos, nrm, tan, uv, col;
  for (int i = 0; i < A::kRings; ++i) {
    const double z = A::kLength * i / (A::kRings - 1);
    for (int j = 0; j <= A::kSegments; ++j) {
      const double th = 2 * std::numbers::pi * (j % A::kSegments) / A::kSegments;
      const float c = static_cast<float>(std::cos(th)), s = static_cast<float>(std::sin(th));
      pos.insert(pos.end(),
                 {static_cast<float>(A::kRadius) * c, static_cast<float>(A::kRadius) * s, static_cast<float>(z)});
      nrm.insert(nrm.end(), {c, s, 0});
      tan.insert(tan.end(), {-s, c, 0, 1});
      uv.insert(uv.end(), {static_cast<float>(j) / A::kSegments, static_cast<float>(i) / (A::kRings - 1)});
      col.insert(col.end(), {static_cast<float>(i) / (A::kRings - 1), static_cast<float>(j) / A::kSegments, 0.5f, 1});
    }
  }
  std::vector<std::uint32_t> side;
  for (int i = 0; i + 1 < A::kRings; ++i) {
    for (int j = 0; j < A::kSegments; ++j) {
      const std::uint32_t a = i * (A::kSegments + 1) + j, b = a + 1, c2 = b + A::kSegments + 1,
                          d = a + A::kSegments + 1;
      side.insert(side.end(), {a, b, c2, a, c2, d});
    }
  }
  // The caps: ring 0 then its centre, the last ring then its centre.
  std::vector<float> cpos, cnrm;
  std::vector<std::uint32_t> caps;
  for (int end = 0; end < 2; ++end) {
    const std::uint32_t first = static_cast<std::uint32_t>(cpos.size() / 3);
    const int ring = end ? A::kRings - 1 : 0;
    for (int j = 0; j < A::kSegments; ++j) {
      const std::size_t v = 3 * (ring * (A::kSegments + 1) + j);
      cpos.insert(cpos.end(), {pos[v], pos[v + 1], pos[v + 2]});
      cnrm.insert(cnrm.end(), {0, 0, end ? 1.0f : -1.0f});
    }
    cpos.insert(cpos.end(), {0, 0, static_cast<float>(end ? A::kLength : 0)});
    cnrm.insert(cnrm.end(), {0, 0, end ? 1.0f : -1.0f});
    const std::uint32_t centre = first + A::kSegments;
    for (int j = 0; j < A::kSegments; ++j) {
      const std::uint32_t a = first + j, b = first + (j + 1) % A::kSegments;
      if (end)
        caps.insert(caps.end(), {centre, a, b});
      else
        caps.insert(caps.end(), {centre, b, a});
    }
  }
  const std::vector<float> gpos = {-2, 0, -2, 2, 0, -2, 2, 0, 2, -2, 0, 2}, gnrm = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0},
                           guv = {0, 0, 1, 0, 1, 1, 0, 1};
  const std::vector<std::uint32_t> ground = {0, 2, 1, 0, 3, 2};

  Doc side_prim = {{"attributes",
                    {{"POSITION", floats(pos, "VEC3", 3, true)},
                     {"NORMAL", floats(nrm, "VEC3", 3)},
                     {"TANGENT", floats(tan, "VEC4", 4)},
                     {"TEXCOORD_0", floats(uv, "VEC2", 2)},
                     {"COLOR_0", floats(col, "VEC4", 4)}}},
                   {"indices", indices(side)},
                   {"material", 0}};
  Doc cap_prim = {{"attributes", {{"POSITION", floats(cpos, "VEC3", 3, true)}, {"NORMAL", floats(cnrm, "VEC3", 3)}}},
                  {"indices", indices(caps)},
                  {"material", 1}};
  Doc ground_prim = {{"attributes",
                      {{"POSITION", floats(gpos, "VEC3", 3, true)},
                       {"NORMAL", floats(gnrm, "VEC3", 3)},
                       {"TEXCOORD_0", floats(guv, "VEC2", 2)}}},
                     {"indices", indices(ground)},
                     {"material", 2}};
  const std::vector<float> idle_times = {0, 1, 2}, idle_moves = {0, -1, 0, 0, -0.9f, 0, 0, -1, 0};
  const std::size_t idle_in = add(idle_times.data(), 12, 5126, "SCALAR", 3, 0);
  accessors[idle_in]["min"] = Doc::array({0.0});
  accessors[idle_in]["max"] = Doc::array({2.0});
  const std::size_t idle_out = add(idle_moves.data(), 36, 5126, "VEC3", 3, 0);

  auto trs = [](const Eigen::Affine3d& a, const Eigen::Vector3d& scale) {
    const Eigen::Quaterniond q(a.linear() * scale.cwiseInverse().asDiagonal());
    return Doc{{"translation", {a.translation().x(), a.translation().y(), a.translation().z()}},
               {"rotation", {q.x(), q.y(), q.z(), q.w()}}};
  };
  Doc creature = trs(TexturedAsset::creature(), Eigen::Vector3d::Ones());
  creature["name"] = "Creature";
  creature["children"] = {1, 2};
  Doc tail = trs(TexturedAsset::tail_local(), Eigen::Vector3d(1.2, 1.2, 1.5));
  tail["name"] = "Tail";
  tail["scale"] = {1.2, 1.2, 1.5};
  tail["mesh"] = 0;
  tail["extras"] = {{"wag", true}};

  Doc doc = {{"asset", {{"version", "2.0"}, {"generator", "sweep tests: textured asset"}}},
             {"scene", 0},
             {"scenes", {{{"name", "World"}, {"nodes", {0, 3}}}}},
             {"nodes",
              {creature,
               tail,
               {{"name", "Head"}, {"translation", {0, 0.3, -0.4}}},
               {{"name", "Ground"}, {"mesh", 1}, {"translation", {0, -1, 0}}}}},
             {"meshes",
              {{{"name", "Tail"}, {"primitives", {side_prim, cap_prim}}},
               {{"name", "Ground"}, {"primitives", {ground_prim}}}}},
             {"materials",
              {{{"name", "Skin"},
                {"pbrMetallicRoughness",
                 {{"baseColorTexture", {{"index", 0}}}, {"baseColorFactor", {1, 0.9, 0.8, 1}}, {"metallicFactor", 0}}},
                {"doubleSided", true}},
               {{"name", "Bone"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.9, 0.85, 1}}}}},
               {{"name", "Grass"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.6, 0.1, 1}}}}}}},
             {"textures", {{{"sampler", 0}, {"source", 0}}}},
             {"samplers", {{{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", 33071}, {"wrapT", 10497}}}},
             {"images", {{{"name", "skin"}, {"uri", "skin.png"}}}},
             {"animations",
              {{{"name", "Idle"},
                {"samplers", {{{"input", idle_in}, {"output", idle_out}, {"interpolation", "LINEAR"}}}},
                {"channels", {{{"sampler", 0}, {"target", {{"node", 3}, {"path", "translation"}}}}}}}}},
             {"accessors", accessors},
             {"bufferViews", views},
             {"buffers", {{{"uri", "creature.bin"}, {"byteLength", bin.size()}}}}};
  spit(dir / "creature.bin", bin);
  spit(dir / "skin.png", tiny_png());
  spit(dir / "creature.gltf", doc.dump(1));
  return doc;
}

}  // namespace sweep::test
