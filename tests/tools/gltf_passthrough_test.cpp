// A glTF asset baked to .glb comes back whole — the input document plus the bake.
// The textured creature of textured_asset.h is fitted, bound and baked by the tools; the .glb must
// hold the input's nodes, materials, textures, samplers, images (bytes), UVs and colours unchanged,
// targets only on the Tail mesh, whose rest + delta at weight 1 is the .pc2's frame (the mesh's own
// space: the rig names the Tail), whose morph normals match normals recomputed from those positions, and the
// Khronos validator must pass it. Then the refusals: what the .glb cannot carry is named, exit 3,
// and nothing is written.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <sstream>

#include "glb_file.h"
#include "pipeline.h"
#include "sweep/assets/mesh_io.h"
#include "textured_asset.h"

namespace sweep::test {
namespace {

using Json = nlohmann::json;
using Vec3 = Eigen::Vector3d;

// A push across the tail near its tip, strong enough to bend it well (normals turn by tens of degrees).
const char* const kTexturedScene =
    R"({"format": "sweep-scene", "version": 1, "duration": 0.5, "fps": 10,
  "forces": [{"sweep": "tube", "t": 1, "theta": 0, "vector": [0, 40, 0], "start": 0, "end": 0.2}]}
)";

// The asset fitted and bound once per build of the tools: creature.gltf (+ .bin, .png), rig.json,
// rig.bind, scene.json.
fs::path textured_pipeline() {
  return cached_dir("textured-gltf", [](const fs::path& dir, const fs::path& io) {
    write_textured_asset(dir);
    const Eigen::Affine3d w = TexturedAsset::tail_world();
    const Vec3 root = w * Vec3(0, 0, 0.02), tip = w * Vec3(0, 0, 1);
    auto csv = [](const Vec3& p) {
      return std::to_string(p.x()) + "," + std::to_string(p.y()) + "," + std::to_string(p.z());
    };
    // The paper's springs (--springs): kTexturedScene pushes as hard as they need.
    const ToolRun fit = run_tool(SWEEP_FIT_EXE,
                                 quoted(dir / "creature.gltf") + " -o " + quoted(dir / "rig.json") +
                                     " --name tube --root " + csv(root) + " --tip " + csv(tip) + " -k 6 -n 8 --springs",
                                 io);
    ASSERT_EQ(fit.code, 0) << fit.err;
    const ToolRun bind = run_tool(SWEEP_BIND_EXE, quoted(dir / "rig.json") + " -q", io);
    ASSERT_EQ(bind.code, 0) << bind.err;
    spit(dir / "scene.json", kScene);
  });
}

struct TexturedWorkspace {
  fs::path work, io;
  explicit TexturedWorkspace(const std::string& name) {
    const fs::path top = scratch_dir(name);
    work = top / "work";
    io = top / "io";
    fs::create_directories(io);
    fs::copy(textured_pipeline(), work, fs::copy_options::recursive);
    spit(work / "scene.json", kTexturedScene);
  }
  fs::path operator/(const std::string& name) const { return work / name; }
  ToolRun bake(const std::string& outputs) const {
    return run_tool(SWEEP_SIM_EXE,
                    quoted(work / "rig.json") + " --scene " + quoted(work / "scene.json") + " -q " + outputs, io);
  }
};

// Area-weighted normals of `positions` (3 a vertex) over `triangles`, welded by position.
std::vector<Vec3> welded_normals(const std::vector<float>& positions, const std::vector<std::uint32_t>& triangles,
                                 const std::vector<float>& rest) {
  std::map<std::array<float, 3>, std::uint32_t> first;
  std::vector<std::uint32_t> rep(positions.size() / 3);
  for (std::uint32_t v = 0; v < rep.size(); ++v)
    rep[v] = first.try_emplace({rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]}, v).first->second;
  std::vector<Vec3> sum(rep.size(), Vec3::Zero());
  auto p = [&](std::uint32_t v) { return Vec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]); };
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const std::uint32_t a = rep[triangles[t]], b = rep[triangles[t + 1]], c = rep[triangles[t + 2]];
    const Vec3 f = (p(b) - p(a)).cross(p(c) - p(a));
    sum[a] += f;
    sum[b] += f;
    sum[c] += f;
  }
  std::vector<Vec3> out(rep.size());
  for (std::size_t v = 0; v < rep.size(); ++v) out[v] = sum[rep[v]].normalized();
  return out;
}

TEST(GltfPassthrough, TheBakedGlbIsTheInputPlusTheBake) {
  const TexturedWorkspace ws("gltf-passthrough");
  const ToolRun r = ws.bake("-o " + quoted(ws / "out.glb") + " -o " + quoted(ws / "out.pc2"));
  ASSERT_EQ(r.code, 0) << r.err;
  const Json in = Json::parse(slurp(ws / "creature.gltf"));
  const std::string in_bin = slurp(ws / "creature.bin");
  const Glb out = read_glb(ws / "out.glb");
  ASSERT_TRUE(out.json.is_object());

  // Kept as they were.
  for (const char* key : {"nodes", "scenes", "scene", "materials", "textures", "samplers", "asset"}) {
    EXPECT_EQ(out.json[key], in[key]) << key;
  }
  ASSERT_EQ(out.json["images"].size(), 1u);
  EXPECT_EQ(out.json["images"][0]["name"], "skin");
  EXPECT_EQ(out.json["images"][0]["mimeType"], "image/png");
  EXPECT_FALSE(out.json["images"][0].contains("uri"));
  EXPECT_EQ(view_bytes(out.json, out.bin, out.json["images"][0]["bufferView"]), tiny_png());
  ASSERT_EQ(out.json["buffers"].size(), 1u);
  EXPECT_FALSE(out.json["buffers"][0].contains("uri"));
  EXPECT_EQ(out.json["meshes"][1], in["meshes"][1]) << "Ground gained something";
  ASSERT_EQ(out.json["animations"].size(), 2u);
  EXPECT_EQ(out.json["animations"][0], in["animations"][0]);
  // Every attribute of every primitive reads back the same, byte for byte.
  for (std::size_t m = 0; m < 2; ++m) {
    for (std::size_t p = 0; p < in["meshes"][m]["primitives"].size(); ++p) {
      const Json& pi = in["meshes"][m]["primitives"][p];
      const Json& po = out.json["meshes"][m]["primitives"][p];
      EXPECT_EQ(po["attributes"], pi["attributes"]);
      EXPECT_EQ(po["material"], pi["material"]);
      for (const auto& [name, accessor] : pi["attributes"].items()) {
        const int width = in["accessors"][accessor.get<std::size_t>()]["type"] == "VEC2"   ? 2
                          : in["accessors"][accessor.get<std::size_t>()]["type"] == "VEC3" ? 3
                                                                                           : 4;
        EXPECT_EQ(floats(out.json, out.bin, accessor, width), floats(in, in_bin, accessor, width))
            << m << " " << p << " " << name;
      }
      EXPECT_EQ(uints(out.json, out.bin, po["indices"]), uints(in, in_bin, pi["indices"]));
    }
  }

  // The bake: targets on the Tail mesh's two primitives only, and a new animation on node Tail.
  const std::string pc2 = slurp(ws / "out.pc2");
  std::int32_t frames = 0;
  std::memcpy(&frames, pc2.data() + 28, 4);
  ASSERT_EQ(frames, 6);
  const Json& tail = out.json["meshes"][0];
  ASSERT_EQ(tail["weights"].size(), 6u);
  EXPECT_FALSE(out.json["meshes"][1]["primitives"][0].contains("targets"));
  const Json& bake = out.json["animations"][1];
  EXPECT_EQ(bake["name"], "sweep bake");
  ASSERT_EQ(bake["channels"].size(), 1u);
  EXPECT_EQ(bake["channels"][0]["target"], (Json{{"node", 1}, {"path", "weights"}}));

  const Eigen::Affine3d w = TexturedAsset::tail_world();
  const Eigen::Matrix3d to_local = w.linear().inverse();
  double worst_position = 0, worst_normal = 0, turned = 0, worst_tangent = 0, moved = 0, scale = 0;
  std::uint32_t base = 0;
  for (std::size_t p = 0; p < 2; ++p) {
    const Json& prim = tail["primitives"][p];
    ASSERT_EQ(prim["targets"].size(), 6u);
    const std::vector<float> rest = floats(out.json, out.bin, prim["attributes"]["POSITION"], 3);
    const std::vector<float> normals = floats(out.json, out.bin, prim["attributes"]["NORMAL"], 3);
    const std::vector<std::uint32_t> triangles = uints(out.json, out.bin, prim["indices"]);
    for (int k = 0; k < frames; ++k) {
      const Json& target = prim["targets"][k];
      const std::vector<float> d = floats(out.json, out.bin, target["POSITION"], 3);
      const std::vector<float> dn = floats(out.json, out.bin, target["NORMAL"], 3);
      int points = 0;
      // The rig names the Tail (the file's largest mesh): the .pc2 holds its vertices in its own space.
      const std::vector<float> local = pc2_frame(pc2, k, &points);
      std::vector<float> deformed(rest.size());
      for (std::size_t v = 0; v < rest.size() / 3; ++v) {
        const Vec3 want(local[3 * (base + v)], local[3 * (base + v) + 1], local[3 * (base + v) + 2]);
        const Vec3 got(rest[3 * v] + d[3 * v], rest[3 * v + 1] + d[3 * v + 1], rest[3 * v + 2] + d[3 * v + 2]);
        worst_position = std::max(worst_position, (got - want).norm());
        moved = std::max(moved, Vec3(d[3 * v], d[3 * v + 1], d[3 * v + 2]).norm());
        scale = std::max(scale, want.norm());
        for (int c = 0; c < 3; ++c) deformed[3 * v + c] = static_cast<float>(got[c]);
      }
      if (p != 0) continue;  // normals on the side: the smooth part (the caps meet it at an edge)
      const std::vector<Vec3> recomputed = welded_normals(deformed, triangles, rest);
      const std::vector<float> dt = floats(out.json, out.bin, target["TANGENT"], 3);
      const std::vector<float> tangents = floats(out.json, out.bin, prim["attributes"]["TANGENT"], 4);
      for (std::size_t v = 0; v < rest.size() / 3; ++v) {
        const int ring = static_cast<int>(v) / (TexturedAsset::kSegments + 1);
        if (ring == 0 || ring == TexturedAsset::kRings - 1) continue;  // next to the caps' edge
        const Vec3 n0(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
        const Vec3 n = n0 + Vec3(dn[3 * v], dn[3 * v + 1], dn[3 * v + 2]);
        const double angle =
            std::acos(std::clamp(n.normalized().dot(recomputed[v]), -1.0, 1.0)) * 180 / std::numbers::pi;
        worst_normal = std::max(worst_normal, angle);
        turned = std::max(
            turned, std::acos(std::clamp(n.normalized().dot(n0.normalized()), -1.0, 1.0)) * 180 / std::numbers::pi);
        const Vec3 t = Vec3(tangents[4 * v], tangents[4 * v + 1], tangents[4 * v + 2]) +
                       Vec3(dt[3 * v], dt[3 * v + 1], dt[3 * v + 2]);
        // Tangents live in the mesh's space as positions do: perpendicular to the normal there
        // only up to the node's non-uniform scale, so compare in world space.
        const Vec3 tw = (w.linear() * t).normalized(), nw = (to_local.transpose() * n).normalized();
        worst_tangent = std::max(worst_tangent,
                                 std::abs(90 - std::acos(std::clamp(tw.dot(nw), -1.0, 1.0)) * 180 / std::numbers::pi));
      }
    }
    base += static_cast<std::uint32_t>(rest.size() / 3);
  }
  EXPECT_EQ(base, static_cast<std::uint32_t>(TexturedAsset::side_vertices() + TexturedAsset::cap_vertices()));
  std::cout << "passthrough: largest move " << moved << ", position error " << worst_position
            << ", morph normal vs recomputed " << worst_normal << " deg (normals turned up to " << turned
            << " deg), tangent off the normal's plane " << worst_tangent << " deg\n";
  EXPECT_GT(moved, 0.02) << "the bake hardly moved: the checks below could not fail";
  EXPECT_LT(worst_position, 4e-7 * scale);
  EXPECT_GT(turned, 5.0);
  EXPECT_LT(worst_normal, 2.0);
  EXPECT_LT(worst_tangent, 2.0);

  int code = -1;
  const std::string report = validate(ws / "out.glb", &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numErrors\": 0"), std::string::npos) << report;
  EXPECT_NE(report.find("\"numWarnings\": 0"), std::string::npos) << report;
}

// ---- Several meshes in one file ----

std::string csv(const Vec3& p) {
  return std::to_string(p.x()) + "," + std::to_string(p.y()) + "," + std::to_string(p.z());
}

// The creature's tail seeds, in world space (Creature · Tail applied).
std::string tail_seeds() {
  const Eigen::Affine3d w = TexturedAsset::tail_world();
  return " --root " + csv(w * Vec3(0, 0, 0.02)) + " --tip " + csv(w * Vec3(0, 0, 1)) + " -k 6 -n 8";
}

struct SceneMeshesDir {
  fs::path work, io;
  Json in;
  std::string in_bin;
  explicit SceneMeshesDir(const std::string& name) {
    const fs::path top = scratch_dir(name);
    work = top / "work";
    io = top / "io";
    fs::create_directories(work);
    fs::create_directories(io);
    in = write_textured_asset(work);
    in_bin = slurp(work / "creature.bin");
    spit(work / "scene.json", kTexturedScene);
  }
  fs::path operator/(const std::string& name) const { return work / name; }
  // The paper's springs (--springs): kTexturedScene pushes as hard as they need.
  ToolRun fit(const std::string& args) const {
    return run_tool(
        SWEEP_FIT_EXE,
        quoted(work / "creature.gltf") + " -o " + quoted(work / "rig.json") + " --name tube --springs" + args, io);
  }
  ToolRun bind() const { return run_tool(SWEEP_BIND_EXE, quoted(work / "rig.json") + " -q", io); }
  // rig.json as a rig from before mesh names (version 1, no mesh_name): of the whole file.
  void make_rig_of_the_whole_file() const {
    Json rig = Json::parse(slurp(work / "rig.json"));
    rig.erase("mesh_name");
    rig["version"] = 1;
    spit(work / "rig.json", rig.dump(2));
  }
  ToolRun bake(const std::string& outputs) const {
    return run_tool(SWEEP_SIM_EXE,
                    quoted(work / "rig.json") + " --scene " + quoted(work / "scene.json") + " -q " + outputs, io);
  }
  // The Tail mesh's POSITION values as stored (its side, then its caps): its local space.
  std::vector<float> tail_local() const {
    std::vector<float> out;
    for (const Json& prim : in["meshes"][0]["primitives"]) {
      const std::vector<float> p = floats(in, in_bin, prim["attributes"]["POSITION"], 3);
      out.insert(out.end(), p.begin(), p.end());
    }
    return out;
  }
};

std::vector<float> obj_vertices(const fs::path& obj) {
  std::istringstream in(slurp(obj));
  std::vector<float> out;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream words(line.substr(2));
    float x = 0, y = 0, z = 0;
    words >> x >> y >> z;
    out.insert(out.end(), {x, y, z});
  }
  return out;
}

// `--mesh Tail`: the rig names it; the .pc2 and the .obj sequence hold the Tail's vertices only, in
// the Tail's own space (frame 0: the file's POSITION values; each frame the .glb's rest + delta);
// the .glb deforms the Tail's primitives and leaves the Ground (mesh and node) as it was.
TEST(SceneMeshes, TheNamedMeshIsBakedAloneInItsOwnSpace) {
  const SceneMeshesDir d("scene-meshes-named");
  ToolRun r = d.fit(" --mesh Tail" + tail_seeds());
  ASSERT_EQ(r.code, 0) << r.err;
  const Json rig = Json::parse(slurp(d / "rig.json"));
  EXPECT_EQ(rig["mesh_name"], "Tail");
  EXPECT_EQ(rig["version"], 3);
  ASSERT_EQ((r = d.bind()).code, 0) << r.err;
  ASSERT_EQ(
      (r = d.bake("-o " + quoted(d / "out.glb") + " -o " + quoted(d / "out.pc2") + " -o " + quoted(d / "out.obj")))
          .code,
      0)
      << r.err;

  const std::vector<float> local = d.tail_local();
  const std::size_t n = local.size() / 3;
  EXPECT_EQ(n, static_cast<std::size_t>(TexturedAsset::side_vertices() + TexturedAsset::cap_vertices()));
  const std::string pc2 = slurp(d / "out.pc2");
  int points = 0;
  const std::vector<float> frame0 = pc2_frame(pc2, 0, &points);
  ASSERT_EQ(static_cast<std::size_t>(points), n) << "the .pc2 must hold the Tail's vertices only";
  double worst0 = 0, scale = 0;
  for (std::size_t k = 0; k < 3 * n; ++k) {
    worst0 = std::max(worst0, double(std::abs(frame0[k] - local[k])));
    scale = std::max(scale, double(std::abs(local[k])));
  }
  std::cout << "--mesh Tail: .pc2 frame 0 against the Tail's stored positions: largest difference " << worst0
            << " (coordinates up to " << scale << ")\n";
  EXPECT_LE(worst0, 2 * std::numeric_limits<float>::epsilon() * scale);

  // Every frame: the .pc2 is the .glb's rest + delta of the Tail's primitives (both local).
  const Glb out = read_glb(d / "out.glb");
  double worst = 0, moved = 0;
  for (int k = 0; k < 6; ++k) {
    const std::vector<float> frame = pc2_frame(pc2, k, &points);
    std::size_t base = 0;
    for (std::size_t p = 0; p < 2; ++p) {
      const Json& prim = out.json["meshes"][0]["primitives"][p];
      const std::vector<float> rest = floats(out.json, out.bin, prim["attributes"]["POSITION"], 3);
      const std::vector<float> delta = floats(out.json, out.bin, prim["targets"][k]["POSITION"], 3);
      for (std::size_t c = 0; c < rest.size(); ++c) {
        worst = std::max(worst, double(std::abs(rest[c] + delta[c] - frame[base + c])));
        moved = std::max(moved, double(std::abs(frame[base + c] - local[base + c])));
      }
      base += rest.size();
    }
    const std::vector<float> obj = obj_vertices(d / ("out_000" + std::to_string(k) + ".obj"));
    EXPECT_EQ(obj, frame) << "the .obj frame " << k << " must hold the .pc2's numbers";
  }
  std::cout << "--mesh Tail: the .glb's rest + delta against the .pc2: largest difference " << worst
            << " (the tail moves up to " << moved << ")\n";
  EXPECT_GT(moved, 0.02);
  EXPECT_LE(worst, 4 * std::numeric_limits<float>::epsilon() * scale);
  EXPECT_EQ(out.json["meshes"][1], d.in["meshes"][1]) << "the Ground gained something";
  EXPECT_EQ(out.json["nodes"], d.in["nodes"]);
  ASSERT_EQ(out.json["animations"].size(), 2u);
  ASSERT_EQ(out.json["animations"][1]["channels"].size(), 1u);
  EXPECT_EQ(out.json["animations"][1]["channels"][0]["target"]["node"], 1);
}

// A name the file does not have: exit 2, the file and its meshes named, no rig. A name for a
// format of one nameless mesh: exit 2. Another mesh for a rig of one: exit 1.
TEST(SceneMeshes, AnUnknownNameIsRefusedNamingTheFileAndItsMeshes) {
  const SceneMeshesDir d("scene-meshes-unknown");
  ToolRun r = d.fit(" --mesh Nope" + tail_seeds());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.err_lines().size(), 1u) << r.err;
  EXPECT_NE(r.err.find("error: " + (d / "creature.gltf").string() +
                       ": no mesh is named 'Nope'; its meshes: 'Tail' 875 vertices, 'Ground' 4 vertices"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(d / "rig.json"));

  spit(d / "tube.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  r = run_tool(SWEEP_FIT_EXE, quoted(d / "tube.off") + " -o " + quoted(d / "rig.json") + " --mesh Tail --tip 0,0,1",
               d.io);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("tube.off: holds one mesh with no name (the format has none), so there is no mesh 'Tail'"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(d / "rig.json"));

  ASSERT_EQ((r = d.fit(" --mesh Tail" + tail_seeds())).code, 0) << r.err;
  const std::string rig = slurp(d / "rig.json");
  r = d.fit(" --mesh Ground" + tail_seeds());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("--mesh Ground: " + (d / "rig.json").string() + " is a rig of its mesh 'Tail'"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(slurp(d / "rig.json"), rig);
}

// No --mesh: the largest (the Tail, 875 vertices, over the Ground's 4), said in a note, with -v and
// in the report; a mesh's own name (not its node's) finds it too, and the rig records the node's.
TEST(SceneMeshes, TheLargestIsTakenByDefaultAndSaidSo) {
  const SceneMeshesDir d("scene-meshes-default");
  ToolRun r = d.fit(tail_seeds() + " -v --report " + quoted(d / "fit.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("note: " + (d / "creature.gltf").string() +
                       " holds 2 meshes; took 'Tail' (875 vertices, the largest; --mesh NAME takes another); "
                       "the others: 'Ground' 4 vertices"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("mesh " + (d / "creature.gltf").string() + " 'Tail' (the largest): 875 vertices"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("the file's meshes (--mesh NAME takes one): 'Tail' 875 vertices, 'Ground' 4 vertices"),
            std::string::npos)
      << r.out;
  const Json summary = Json::parse(slurp(d / "fit.json"))["mesh_summary"];
  EXPECT_EQ(summary["mesh_name"], "Tail");
  EXPECT_EQ(summary["taken"], "the largest");
  EXPECT_EQ(summary["vertices"], 875);
  ASSERT_EQ(summary["meshes"].size(), 2u);
  EXPECT_EQ(summary["meshes"][1], (Json{{"name", "Ground"}, {"mesh_name", "Ground"}, {"vertices", 4}}));
  EXPECT_EQ(Json::parse(slurp(d / "rig.json"))["mesh_name"], "Tail");

  Json doc = d.in;
  doc["nodes"][1]["name"] = "TailNode";
  spit(d / "creature.gltf", doc.dump(1));
  fs::remove(d / "rig.json");
  ASSERT_EQ((r = d.fit(" --mesh Tail" + tail_seeds())).code, 0) << r.err;
  EXPECT_EQ(Json::parse(slurp(d / "rig.json"))["mesh_name"], "TailNode");
  // Updating that rig, the mesh's name finds its node as well as the node's name does.
  r = run_tool(
      SWEEP_FIT_EXE,
      quoted(d / "creature.gltf") + " -o " + quoted(d / "rig.json") + " --mesh Tail --name second" + tail_seeds(),
      d.io);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json updated = Json::parse(slurp(d / "rig.json"));
  EXPECT_EQ(updated["mesh_name"], "TailNode");
  EXPECT_EQ(updated["sweeps"].size(), 2u);
}

// --space local: --root, --tip and --axis in the Tail's own space (as stored in the file) are taken to
// world by its node's transform: the rig is the one world seeds give (world space, as always).
TEST(SceneMeshes, LocalSeedsAreTakenToWorldByTheNodesTransform) {
  const SceneMeshesDir d("scene-meshes-local-seeds");
  const Eigen::Affine3d w = TexturedAsset::tail_world();
  ToolRun r =
      d.fit(" --mesh Tail --space local --root 0,0,0.02 --tip 0,0,1 -k 6 -n 8 -v --report " + quoted(d / "fit.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("--tip, --root and --axis are in the mesh's own space (--space local)"), std::string::npos)
      << r.out;
  EXPECT_EQ(Json::parse(slurp(d / "fit.json"))["mesh_summary"]["seeds_space"], "local");
  const Json local = Json::parse(slurp(d / "rig.json"));
  const Json& part = local["sweeps"][0]["part"];
  const Vec3 tip(part["tip"][0], part["tip"][1], part["tip"][2]);
  EXPECT_LT((tip - w * Vec3(0, 0, 1)).norm(), 1e-6) << part;  // assimp keeps node transforms in float
  fs::remove(d / "rig.json");
  ASSERT_EQ((r = d.fit(" --mesh Tail" + tail_seeds())).code, 0) << r.err;
  const Json world = Json::parse(slurp(d / "rig.json"));
  double worst = 0;
  const Json& a = local["sweeps"][0]["sections"];
  const Json& b = world["sweeps"][0]["sections"];
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(a[k]["center"][c].get<double>() - b[k]["center"][c].get<double>()));
  }
  EXPECT_LT(worst, 1e-5) << "the seeds given in world space are rounded to 6 decimals";
  r = run_tool(SWEEP_FIT_EXE, quoted(d / "creature.gltf") + " --list --space local", d.io);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("--space says what --root, --tip and --axis are in: it does not go with --list"),
            std::string::npos)
      << r.err;
}

// A rig from before mesh names (version 1, no mesh_name) reads the whole file as it always did: the
// Tail and the Ground, in world space, in the .pc2.
TEST(SceneMeshes, ARigWithoutAMeshNameReadsTheWholeFileAsBefore) {
  const SceneMeshesDir d("scene-meshes-old-rig");
  ToolRun r = d.fit(tail_seeds());
  ASSERT_EQ(r.code, 0) << r.err;
  d.make_rig_of_the_whole_file();
  ASSERT_EQ((r = d.bind()).code, 0) << r.err;
  ASSERT_EQ((r = d.bake("-o " + quoted(d / "out.pc2"))).code, 0) << r.err;
  int points = 0;
  const std::vector<float> frame0 = pc2_frame(slurp(d / "out.pc2"), 0, &points);
  const std::vector<float> local = d.tail_local();
  ASSERT_EQ(static_cast<std::size_t>(points), local.size() / 3 + 4);
  double worst = 0;
  for (std::size_t v = 0; v < local.size() / 3; ++v) {
    const Vec3 want = TexturedAsset::tail_world() * Vec3(local[3 * v], local[3 * v + 1], local[3 * v + 2]);
    worst = std::max(worst, (want - Vec3(frame0[3 * v], frame0[3 * v + 1], frame0[3 * v + 2])).norm());
  }
  const std::vector<float> ground =
      floats(d.in, d.in_bin, d.in["meshes"][1]["primitives"][0]["attributes"]["POSITION"], 3);
  for (std::size_t v = 0; v < 4; ++v) {
    const Vec3 want(ground[3 * v], ground[3 * v + 1] - 1, ground[3 * v + 2]);  // Ground's node: translation (0, -1, 0)
    const std::size_t at = 3 * (local.size() / 3 + v);
    worst = std::max(worst, (want - Vec3(frame0[at], frame0[at + 1], frame0[at + 2])).norm());
  }
  EXPECT_LT(worst, 1e-6);
}

// Such a rig reads the whole file, which has no one local space: adding a part to it with --space
// local is refused (exit 1, the rig as it was), not read as world points.
TEST(SceneMeshes, LocalSeedsIntoARigThatReadsTheWholeFileAreRefused) {
  const SceneMeshesDir d("scene-meshes-old-rig-local");
  ToolRun r = d.fit(tail_seeds());
  ASSERT_EQ(r.code, 0) << r.err;
  d.make_rig_of_the_whole_file();
  const std::string before = slurp(d / "rig.json");
  r = run_tool(SWEEP_FIT_EXE,
               quoted(d / "creature.gltf") + " -o " + quoted(d / "rig.json") +
                   " --name other --space local --root 0,0,0.02 --tip 0,0,1 -k 6 -n 8",
               d.io);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("--space local: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("names no mesh, so it reads the whole of"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'Tail' 875 vertices, 'Ground' 4 vertices"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(d / "rig.json"), before);
}

// A file that lists its meshes in another order than its scene reaches them: the Tail is mesh 1 and
// the Ground mesh 0, but the scene shows the Tail first, and assimp numbers meshes in the order the
// scene reaches them (its mesh 0 is the Tail's first primitive). `--mesh Tail` takes the Tail by the
// file's numbering: the fit is the Tail's, the .pc2 holds the Tail's stored positions at frame 0,
// and the .glb's targets go on mesh 1 alone.
TEST(SceneMeshes, TheNamedMeshIsTakenByTheFilesNumberingNotTheImporters) {
  const SceneMeshesDir d("scene-meshes-order");
  Json doc = d.in;
  std::swap(doc["meshes"][0], doc["meshes"][1]);
  doc["nodes"][1]["mesh"] = 1;  // Tail
  doc["nodes"][3]["mesh"] = 0;  // Ground
  spit(d / "creature.gltf", doc.dump(1));
  ToolRun r = d.fit(" --mesh Tail --report " + quoted(d / "fit.json") + tail_seeds());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(Json::parse(slurp(d / "fit.json"))["mesh_summary"]["vertices"], 875);
  ASSERT_EQ((r = d.bind()).code, 0) << r.err;
  ASSERT_EQ((r = d.bake("-o " + quoted(d / "out.glb") + " -o " + quoted(d / "out.pc2"))).code, 0) << r.err;
  std::vector<float> local;
  for (const Json& prim : doc["meshes"][1]["primitives"]) {
    const std::vector<float> p = floats(doc, d.in_bin, prim["attributes"]["POSITION"], 3);
    local.insert(local.end(), p.begin(), p.end());
  }
  int points = 0;
  const std::vector<float> frame0 = pc2_frame(slurp(d / "out.pc2"), 0, &points);
  ASSERT_EQ(frame0.size(), local.size()) << "the .pc2 must hold the Tail's vertices only";
  double worst = 0;  // the Tail's world positions taken back to its space: float rounding, as above
  for (std::size_t k = 0; k < local.size(); ++k) worst = std::max(worst, double(std::abs(frame0[k] - local[k])));
  EXPECT_LE(worst, 2 * std::numeric_limits<float>::epsilon());  // coordinates up to 1
  const auto expect_the_tail_deformed_alone = [](const fs::path& glb) {
    const Glb out = read_glb(glb);
    EXPECT_FALSE(out.json["meshes"][0]["primitives"][0].contains("targets")) << "the Ground gained targets";
    for (const Json& prim : out.json["meshes"][1]["primitives"])
      EXPECT_EQ(prim.value("targets", Json::array()).size(), 6u);
  };
  expect_the_tail_deformed_alone(d / "out.glb");

  // A rig of the whole file (no mesh name) reads the meshes in assimp's order, the Tail first: the
  // .glb still deforms the Tail's primitives alone.
  d.make_rig_of_the_whole_file();
  ASSERT_EQ((r = d.bind()).code, 0) << r.err;
  ASSERT_EQ((r = d.bake("-o " + quoted(d / "whole.glb"))).code, 0) << r.err;
  expect_the_tail_deformed_alone(d / "whole.glb");
}

// What the .glb cannot carry: exit 3, one line naming the file and what is wrong, nothing written.
void expect_refused(const std::string& name, const std::function<void(Json&)>& change, const std::string& expect,
                    int exit_code = 3, const char* remove = nullptr) {
  SCOPED_TRACE(name);
  const TexturedWorkspace ws("gltf-passthrough-" + name);
  Json doc = Json::parse(slurp(ws / "creature.gltf"));
  change(doc);
  spit(ws / "creature.gltf", doc.dump(1));
  if (remove) fs::remove(ws / remove);
  const std::set<std::string> before = listing(ws.work);
  const ToolRun r = ws.bake("-o " + quoted(ws / "out.glb") + " -o " + quoted(ws / "out.pc2"));
  EXPECT_EQ(r.code, exit_code) << r.err;
  const auto lines = r.err_lines();
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_EQ(lines[0].rfind("error: ", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find("creature.gltf: "), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find(expect), std::string::npos) << lines[0];
  EXPECT_EQ(listing(ws.work), before);
}

TEST(GltfPassthrough, WhatTheGlbCannotCarryIsRefused) {
  expect_refused(
      "targets",
      [](Json& d) {
        d["meshes"][0]["primitives"][1]["targets"] =
            Json::array({{{"POSITION", d["meshes"][0]["primitives"][1]["attributes"]["NORMAL"]}}});
      },
      "mesh 0 ('Tail') primitive 1 already has morph targets");
  expect_refused(
      "draco", [](Json& d) { d["extensionsUsed"] = {"KHR_draco_mesh_compression"}; },
      "uses KHR_draco_mesh_compression");
  expect_refused(
      "instances",
      [](Json& d) {
        d["nodes"].push_back({{"name", "Tail2"}, {"mesh", 0}, {"translation", {1, 0, 0}}});
        d["scenes"][0]["nodes"].push_back(4);
      },
      "node 1 ('Tail') and node 4 ('Tail2') show it with different transforms");
  expect_refused(
      "sparse",
      [](Json& d) {
        // The side's POSITION with a sparse override of vertex 0 by its own value (index 0 is the
        // side's first index; the value the view's first): the same positions, sparse storage.
        Json& side = d["meshes"][0]["primitives"][0];
        Json& position = d["accessors"][side["attributes"]["POSITION"].get<std::size_t>()];
        position["sparse"] = {{"count", 1},
                              {"indices",
                               {{"bufferView", d["accessors"][side["indices"].get<std::size_t>()]["bufferView"]},
                                {"componentType", 5125}}},
                              {"values", {{"bufferView", position["bufferView"]}}}};
      },
      "mesh 0 ('Tail') primitive 0: its POSITION is not a plain float accessor");
  // An image the .glb must embed but cannot read: bad input, exit 2.
  expect_refused(
      "missing-image", [](Json&) {}, "image 0 ('skin.png'): cannot read it", 2, "skin.png");
  // A .pc2 alone is still baked: the refusal is the .glb's.
  const TexturedWorkspace ws("gltf-passthrough-pc2-only");
  Json doc = Json::parse(slurp(ws / "creature.gltf"));
  doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  spit(ws / "creature.gltf", doc.dump(1));
  EXPECT_EQ(ws.bake("-o " + quoted(ws / "out.pc2")).code, 0);
}

// A moving body: the new animation moves node Tail (translation and rotation; its own scale kept)
// so that Creature · Tail(t) · (rest + delta) is the .pc2's position (in the Tail's rest space) in
// world space, in every frame.
TEST(GltfPassthrough, AMovingBodyMovesTheTailNodeComposedWithItsOwnTransform) {
  const TexturedWorkspace ws("gltf-passthrough-body");
  Json scene = Json::parse(kTexturedScene);
  scene["body"] = {{"interpolation", "linear"},
                   {"keys",
                    {{{"time", 0}, {"translation", {0, 0, 0}}},
                     {{"time", 0.5}, {"translation", {0.3, 0.1, -0.2}}, {"turn_degrees", 40}}}}};
  spit(ws / "scene.json", scene.dump());
  const ToolRun r = ws.bake("-o " + quoted(ws / "out.glb") + " -o " + quoted(ws / "out.pc2"));
  ASSERT_EQ(r.code, 0) << r.err;
  const Glb out = read_glb(ws / "out.glb");
  const Json in = Json::parse(slurp(ws / "creature.gltf"));
  EXPECT_EQ(out.json["nodes"], in["nodes"]) << "the rest transforms must stay as they were";
  const Json& bake = out.json["animations"][1];
  std::map<std::string, std::vector<float>> keys;
  for (const Json& c : bake["channels"]) {
    ASSERT_EQ(c["target"]["node"], 1);
    const std::string path = c["target"]["path"];
    if (path == "weights") continue;
    keys[path] = floats(out.json, out.bin, bake["samplers"][c["sampler"].get<std::size_t>()]["output"],
                        path == "rotation" ? 4 : 3);
  }
  ASSERT_EQ(keys.size(), 2u);
  const std::string pc2 = slurp(ws / "out.pc2");
  const Json& prim = out.json["meshes"][0]["primitives"][0];
  const std::vector<float> rest = floats(out.json, out.bin, prim["attributes"]["POSITION"], 3);
  double worst = 0, travelled = 0;
  for (int k = 0; k < 6; ++k) {
    const std::vector<float> d = floats(out.json, out.bin, prim["targets"][k]["POSITION"], 3);
    int points = 0;
    const std::vector<float> world = pc2_frame(pc2, k, &points);
    const float* t = &keys["translation"][3 * k];
    const float* q = &keys["rotation"][4 * k];
    Eigen::Affine3d local = Eigen::Affine3d::Identity();
    local.translate(Vec3(t[0], t[1], t[2]));
    local.rotate(Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized());
    local.scale(Vec3(1.2, 1.2, 1.5));
    const Eigen::Affine3d placed = TexturedAsset::creature() * local;
    for (std::size_t v = 0; v < rest.size() / 3; ++v) {
      const Vec3 got =
          placed * Vec3(rest[3 * v] + d[3 * v], rest[3 * v + 1] + d[3 * v + 1], rest[3 * v + 2] + d[3 * v + 2]);
      // The .pc2: the Tail's own space, the body's motion in it.
      const Vec3 want = TexturedAsset::tail_world() * Vec3(world[3 * v], world[3 * v + 1], world[3 * v + 2]);
      worst = std::max(worst, (got - want).norm());
      travelled = std::max(
          travelled, (want - TexturedAsset::tail_world() * Vec3(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2])).norm());
    }
  }
  std::cout << "moving body: largest distance from the .pc2 " << worst << " (the tail travels " << travelled << ")\n";
  EXPECT_GT(travelled, 0.2);
  EXPECT_LT(worst, 2e-6);
  int code = -1;
  const std::string report = validate(ws / "out.glb", &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numWarnings\": 0"), std::string::npos) << report;
}

// A .glb input (its buffer the BIN chunk, its image a data URI) comes back the same way: the image's
// bytes embedded unchanged, the Ground's bytes as they were, the validator clean.
TEST(GltfPassthrough, AGlbInputWithADataUriImageComesBackWhole) {
  const TexturedWorkspace ws("gltf-passthrough-glb");
  Json doc = Json::parse(slurp(ws / "creature.gltf"));
  const std::string bin = slurp(ws / "creature.bin");
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string b64;
  const std::string png = tiny_png();
  for (std::size_t i = 0; i < png.size(); i += 3) {
    std::uint32_t v = 0;
    for (std::size_t j = 0; j < 3; ++j) v = v << 8 | (i + j < png.size() ? static_cast<unsigned char>(png[i + j]) : 0u);
    for (std::size_t j = 0; j < 4; ++j) b64 += i + j <= png.size() ? k[(v >> (18 - 6 * j)) & 63] : '=';
  }
  doc["images"][0] = {{"name", "skin"}, {"uri", "data:image/png;base64," + b64}};
  doc["buffers"][0].erase("uri");
  spit(ws / "creature.glb", glb_bytes(doc, bin));
  Json rig = Json::parse(slurp(ws / "rig.json"));
  rig["mesh"] = "creature.glb";  // the same positions: the binding still holds
  spit(ws / "rig.json", rig.dump());
  fs::remove(ws / "creature.gltf");
  fs::remove(ws / "creature.bin");
  fs::remove(ws / "skin.png");
  const ToolRun r = ws.bake("-o " + quoted(ws / "out.glb"));
  ASSERT_EQ(r.code, 0) << r.err;
  const Glb out = read_glb(ws / "out.glb");
  EXPECT_EQ(out.json["nodes"], doc["nodes"]);
  EXPECT_EQ(out.json["materials"], doc["materials"]);
  EXPECT_EQ(view_bytes(out.json, out.bin, out.json["images"][0]["bufferView"]), png);
  const std::size_t ground = doc["meshes"][1]["primitives"][0]["attributes"]["TEXCOORD_0"];
  EXPECT_EQ(floats(out.json, out.bin, ground, 2), floats(doc, bin, ground, 2));
  EXPECT_EQ(out.json["meshes"][0]["primitives"][0]["targets"].size(), 6u);
  int code = -1;
  const std::string report = validate(ws / "out.glb", &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numWarnings\": 0"), std::string::npos) << report;
}

// A textured OBJ tube: `v` with colours, `vt` split at the seam, radial `vn` on the side and flat
// ones on the caps (a hard edge), material Skin (map_Kd skin.png) on the side, Bone on the caps.
void write_textured_obj(const fs::path& dir) {
  constexpr int R = TexturedAsset::kRings, S = TexturedAsset::kSegments;
  std::string obj = "mtllib creature.mtl\n";
  auto num = [](double x) { return std::to_string(x); };
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < S; ++j) {
      const double th = 2 * std::numbers::pi * j / S;
      obj += "v " + num(0.1 * std::cos(th)) + " " + num(0.1 * std::sin(th)) + " " + num(double(i) / (R - 1)) + " " +
             num(double(i) / (R - 1)) + " " + num(double(j) / S) + " 0.5\n";  // and a vertex colour
    }
  obj += "v 0 0 0 0.5 0.5 0.5\nv 0 0 1 0.5 0.5 0.5\n";
  for (int i = 0; i < R; ++i)
    for (int j = 0; j <= S; ++j) obj += "vt " + num(double(j) / S) + " " + num(double(i) / (R - 1)) + "\n";
  obj += "vt 0.5 0.5\n";
  for (int j = 0; j < S; ++j) {
    const double th = 2 * std::numbers::pi * j / S;
    obj += "vn " + num(std::cos(th)) + " " + num(std::sin(th)) + " 0\n";
  }
  obj += "vn 0 0 -1\nvn 0 0 1\nusemtl Skin\n";
  auto corner = [&](int i, int j, int jt) {
    return " " + std::to_string(i * S + j % S + 1) + "/" + std::to_string(i * (S + 1) + jt + 1) + "/" +
           std::to_string(j % S + 1);
  };
  for (int i = 0; i + 1 < R; ++i)
    for (int j = 0; j < S; ++j)
      obj += "f" + corner(i, j, j) + corner(i, j + 1, j + 1) + corner(i + 1, j + 1, j + 1) + corner(i + 1, j, j) + "\n";
  obj += "usemtl Bone\n";
  const int centre_vt = R * (S + 1) + 1;
  for (int j = 0; j < S; ++j) {
    auto c = [&](int i, int jj, int n) {
      return " " + std::to_string(i * S + jj % S + 1) + "/" + std::to_string(centre_vt) + "/" + std::to_string(n);
    };
    obj += "f " + std::to_string(R * S + 1) + "/" + std::to_string(centre_vt) + "/" + std::to_string(S + 1) +
           c(0, j + 1, S + 1) + c(0, j, S + 1) + "\n";
    obj += "f " + std::to_string(R * S + 2) + "/" + std::to_string(centre_vt) + "/" + std::to_string(S + 2) +
           c(R - 1, j, S + 2) + c(R - 1, j + 1, S + 2) + "\n";
  }
  spit(dir / "creature.obj", obj);
  spit(dir / "creature.mtl", "newmtl Skin\nKd 0.8 0.8 0.8\nmap_Kd skin.png\nnewmtl Bone\nKd 0.9 0.9 0.85\n");
  spit(dir / "skin.png", tiny_png());
}

// Part b: a textured OBJ (+ .mtl + .png) baked to .glb carries its UVs (split at the seam, as glTF
// needs), normals, vertex colours (`v x y z r g b`) and materials with the image embedded, and the
// targets follow the .pc2.
TEST(ObjPassthrough, UvsNormalsAndTheMaterialsImageCarryIntoTheGlb) {
  constexpr int R = TexturedAsset::kRings, S = TexturedAsset::kSegments;
  const fs::path top = scratch_dir("obj-passthrough"), dir = top / "work", io = top / "io";
  fs::create_directories(dir);
  fs::create_directories(io);
  write_textured_obj(dir);
  fit_and_bind(dir, io, "creature.obj", " -k 6 -n 8");
  spit(dir / "scene.json", kTexturedScene);
  const ToolRun r = run_tool(SWEEP_SIM_EXE,
                             quoted(dir / "rig.json") + " --scene " + quoted(dir / "scene.json") + " -q -o " +
                                 quoted(dir / "out.glb") + " -o " + quoted(dir / "out.pc2"),
                             io);
  ASSERT_EQ(r.code, 0) << r.err;
  const Glb out = read_glb(dir / "out.glb");
  ASSERT_EQ(out.json["meshes"].size(), 1u);
  ASSERT_EQ(out.json["materials"].size(), 2u);
  EXPECT_EQ(out.json["materials"][0]["name"], "Skin");
  EXPECT_EQ(out.json["materials"][1]["name"], "Bone");
  EXPECT_EQ(out.json["materials"][1]["pbrMetallicRoughness"]["baseColorFactor"], (Json{0.9, 0.9, 0.85, 1.0}));
  const std::size_t texture = out.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"];
  const std::size_t image = out.json["textures"][texture]["source"];
  EXPECT_EQ(view_bytes(out.json, out.bin, out.json["images"][image]["bufferView"]), tiny_png());
  const Json& side = out.json["meshes"][0]["primitives"][0];
  EXPECT_EQ(side["material"], 0);
  const std::vector<float> rest = floats(out.json, out.bin, side["attributes"]["POSITION"], 3);
  const std::vector<float> uv = floats(out.json, out.bin, side["attributes"]["TEXCOORD_0"], 2);
  const std::vector<float> normals = floats(out.json, out.bin, side["attributes"]["NORMAL"], 3);
  const std::vector<float> colours = floats(out.json, out.bin, side["attributes"]["COLOR_0"], 4);
  // One vertex array for both primitives: the mesh's vertices in its order, then the corners that
  // differ (the seam's second copy of each ring's first vertex, the caps' rims with their flat vn).
  const Mesh mesh = assets::read_mesh(dir / "creature.obj");
  EXPECT_EQ(out.json["meshes"][0]["primitives"][1]["attributes"], side["attributes"]);
  ASSERT_EQ(rest.size() / 3, mesh.vertex_count() + R + 2 * S);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(rest[3 * v + c], static_cast<float>(mesh.positions[v][c])) << "vertex order: " << v;
  const std::vector<std::uint32_t> side_triangles = uints(out.json, out.bin, side["indices"]);
  const std::set<std::uint32_t> used(side_triangles.begin(), side_triangles.end());
  EXPECT_EQ(used.size(), static_cast<std::size_t>(R * (S + 1))) << "one vertex a (v, vt, vn) corner: the seam split";
  // Each side vertex's UV is its corner's (u, 1 - v), its normal the radial vn, its source the v at its place.
  std::map<std::array<float, 3>, std::uint32_t> by_position;
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    const Eigen::Vector3f p = mesh.positions[v].cast<float>();
    by_position[{p.x(), p.y(), p.z()}] = v;
  }
  std::set<std::pair<int, int>> seen;
  double worst_uv = 0;
  std::vector<std::uint32_t> source(rest.size() / 3);
  for (std::size_t v = 0; v < source.size(); ++v) {
    const auto it = by_position.find({rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]});
    ASSERT_NE(it, by_position.end()) << v;
    source[v] = it->second;
    if (!used.count(static_cast<std::uint32_t>(v))) continue;
    const int i = static_cast<int>(it->second) / S, j = static_cast<int>(it->second) % S;
    const int jt = j == 0 && uv[2 * v] > 0.5f ? S : j;  // the seam's second copy
    seen.insert({i, jt});
    worst_uv =
        std::max({worst_uv, std::abs(uv[2 * v] - double(jt) / S), std::abs(uv[2 * v + 1] - (1 - double(i) / (R - 1)))});
    const double th = 2 * std::numbers::pi * j / S;
    EXPECT_NEAR(normals[3 * v], std::cos(th), 1e-5);
    EXPECT_NEAR(colours[4 * v], double(i) / (R - 1), 1e-6);
    EXPECT_NEAR(colours[4 * v + 1], double(j) / S, 1e-6);
  }
  EXPECT_EQ(seen.size(), used.size());
  EXPECT_LT(worst_uv, 1e-6);
  // The targets: rest + delta at weight 1 is the .pc2's frame at the vertex's source.
  const std::string pc2 = slurp(dir / "out.pc2");
  double worst = 0, moved = 0;
  for (int k = 0; k < 6; ++k) {
    const std::vector<float> d = floats(out.json, out.bin, side["targets"][k]["POSITION"], 3);
    int points = 0;
    const std::vector<float> world = pc2_frame(pc2, k, &points);
    for (std::size_t v = 0; v < source.size(); ++v)
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, double(std::abs(rest[3 * v + c] + d[3 * v + c] - world[3 * source[v] + c])));
        moved = std::max(moved, double(std::abs(d[3 * v + c])));
      }
  }
  std::cout << "obj passthrough: largest move " << moved << ", rest + delta against the .pc2 " << worst << "\n";
  EXPECT_GT(moved, 0.02);
  EXPECT_LT(worst, 1e-6);
  int code = -1;
  const std::string report = validate(dir / "out.glb", &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numWarnings\": 0"), std::string::npos) << report;
}

// An .mtl written on Windows names its textures with backslashes (".\\skin.png"): read as "/",
// the image is found and embedded as with a forward slash.
TEST(ObjPassthrough, WindowsSeparatorsInTheMaterialLibraryAreRead) {
  const fs::path top = scratch_dir("obj-windows-mtl"), dir = top / "work", io = top / "io";
  fs::create_directories(dir / "textures");
  fs::create_directories(io);
  write_textured_obj(dir);
  fs::rename(dir / "skin.png", dir / "textures" / "skin.png");
  spit(dir / "creature.mtl",
       "newmtl Skin\r\nKd 0.8 0.8 0.8\r\nmap_Kd .\\textures\\skin.png\r\n"
       "newmtl Bone\r\nKd 0.9 0.9 0.85\r\n");
  fit_and_bind(dir, io, "creature.obj", " -k 6 -n 8");
  spit(dir / "scene.json", kTexturedScene);
  const ToolRun r = run_tool(
      SWEEP_SIM_EXE,
      quoted(dir / "rig.json") + " --scene " + quoted(dir / "scene.json") + " -q -o " + quoted(dir / "out.glb"), io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const Glb out = read_glb(dir / "out.glb");
  const std::size_t texture = out.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"];
  const std::size_t image = out.json["textures"][texture]["source"];
  EXPECT_EQ(view_bytes(out.json, out.bin, out.json["images"][image]["bufferView"]), tiny_png());
}

// Normals that are not finite or have no length (`vn nan 0 1`, `vn 0 0 0`) would make every
// target's normal delta NaN and the file invalid: they are recomputed from the faces round the
// vertex (area-weighted), with a warning that counts them, and the .glb passes the validator. On
// the tube's side, away from the caps, that normal is radial by symmetry: what the file's own vn
// said there.
TEST(ObjPassthrough, NanAndZeroNormalsAreRecomputedFromTheFaces) {
  constexpr int R = TexturedAsset::kRings, S = TexturedAsset::kSegments;
  const fs::path top = scratch_dir("obj-bad-normals"), dir = top / "work", io = top / "io";
  fs::create_directories(dir);
  fs::create_directories(io);
  write_textured_obj(dir);
  std::string obj = slurp(dir / "creature.obj");
  const std::size_t first = obj.find("\nvn ") + 1, second = obj.find("\nvn ", first) + 1;
  const std::size_t second_end = obj.find('\n', second);
  obj.replace(second, second_end - second, "vn 0 0 0");             // the normal of the vertices at j = 1
  obj.replace(first, obj.find('\n', first) - first, "vn nan 0 1");  // ... and at j = 0
  spit(dir / "creature.obj", obj);
  fit_and_bind(dir, io, "creature.obj", " -k 6 -n 8");
  spit(dir / "scene.json", kTexturedScene);
  const ToolRun r = run_tool(
      SWEEP_SIM_EXE,
      quoted(dir / "rig.json") + " --scene " + quoted(dir / "scene.json") + " -q -o " + quoted(dir / "out.glb"), io);
  ASSERT_EQ(r.code, 0) << r.err;
  // The side's corners at j = 0 (with the seam's second copy) and j = 1, on every ring.
  const std::string count = std::to_string(3 * R);
  ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
  EXPECT_NE(r.err.find("warning: " + (dir / "creature.obj").string() + ": mesh 0 primitive 0: " + count +
                       " normals are not finite or of no length (first: vertex 0 (nan, 0, 1)); recomputed from "
                       "the faces round each vertex (area-weighted)"),
            std::string::npos)
      << r.err;
  const Glb out = read_glb(dir / "out.glb");
  const Json& side = out.json["meshes"][0]["primitives"][0];
  const std::vector<float> rest = floats(out.json, out.bin, side["attributes"]["POSITION"], 3);
  const std::vector<float> normals = floats(out.json, out.bin, side["attributes"]["NORMAL"], 3);
  double worst = 0;
  int checked = 0;
  for (std::size_t v = 0; v < normals.size() / 3; ++v) {
    const Eigen::Vector3d n(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
    ASSERT_TRUE(n.allFinite()) << v;
    EXPECT_NEAR(n.norm(), 1.0, 1e-6) << v;
    const Eigen::Vector3d p(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]);
    const double ring = p.z() * (R - 1);
    if (ring < 0.5 || ring > R - 1.5 || std::hypot(p.x(), p.y()) < 0.05) continue;  // caps, their rims
    const Eigen::Vector3d radial = Eigen::Vector3d(p.x(), p.y(), 0).normalized();
    worst = std::max(worst, (n - radial).norm());
    ++checked;
  }
  EXPECT_GT(checked, (R - 2) * S);
  EXPECT_LT(worst, 1e-5);
  for (std::size_t k = 0; k < side["targets"].size(); ++k) {
    for (const float x : floats(out.json, out.bin, side["targets"][k]["NORMAL"], 3)) ASSERT_TRUE(std::isfinite(x)) << k;
  }
  int code = -1;
  const std::string report = validate(dir / "out.glb", &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numErrors\": 0"), std::string::npos) << report;
}

// A glTF's NORMAL with a NaN and a zero (the tail's side, rings 5 and 6, mid-tube): recomputed from
// the faces round the vertex (area-weighted; on this cylinder radial in the tail's own space, the
// node's scale being along its axis), the accessor re-pointed at the repaired values, a warning
// counting them, and the .glb valid.
TEST(GltfPassthrough, NanAndZeroNormalsAreRecomputedFromTheFaces) {
  constexpr int S = TexturedAsset::kSegments;
  const TexturedWorkspace ws("gltf-bad-normals");
  const Json doc = Json::parse(slurp(ws / "creature.gltf"));
  const std::size_t normal_accessor = doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"];
  const Json& accessor = doc["accessors"][normal_accessor];
  const std::size_t at = doc["bufferViews"][accessor["bufferView"].get<std::size_t>()].value("byteOffset", 0) +
                         accessor.value("byteOffset", 0);
  std::string bin = slurp(ws / "creature.bin");
  const std::uint32_t nan_vertex = 5 * (S + 1) + 1, zero_vertex = 6 * (S + 1) + 2;
  const float nan_normal[3] = {std::numeric_limits<float>::quiet_NaN(), 0, 1}, zero[3] = {0, 0, 0};
  std::memcpy(bin.data() + at + 12 * nan_vertex, nan_normal, 12);
  std::memcpy(bin.data() + at + 12 * zero_vertex, zero, 12);
  spit(ws / "creature.bin", bin);
  const ToolRun r = ws.bake("-o " + quoted(ws / "out.glb"));
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
  EXPECT_NE(r.err.find("warning: " + (ws / "creature.gltf").string() +
                       ": mesh 0 primitive 0: 2 normals are not "
                       "finite or of no length (first: vertex " +
                       std::to_string(nan_vertex) +
                       " (nan, 0, 1)); "
                       "recomputed from the faces round each vertex (area-weighted)"),
            std::string::npos)
      << r.err;
  const Glb out = read_glb(ws / "out.glb");
  const Json& side = out.json["meshes"][0]["primitives"][0];
  const std::vector<float> normals = floats(out.json, out.bin, side["attributes"]["NORMAL"], 3);
  for (const auto& [v, j] : {std::pair{nan_vertex, 1}, std::pair{zero_vertex, 2}}) {
    const double th = 2 * std::numbers::pi * j / S;
    EXPECT_NEAR(normals[3 * v], std::cos(th), 1e-5) << v;
    EXPECT_NEAR(normals[3 * v + 1], std::sin(th), 1e-5) << v;
    EXPECT_NEAR(normals[3 * v + 2], 0, 1e-5) << v;
  }
  for (const float x : normals) ASSERT_TRUE(std::isfinite(x));
  for (std::size_t k = 0; k < side["targets"].size(); ++k) {
    for (const float x : floats(out.json, out.bin, side["targets"][k]["NORMAL"], 3)) ASSERT_TRUE(std::isfinite(x)) << k;
  }
  int code = -1;
  const std::string report = validate(ws / "out.glb", &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numErrors\": 0"), std::string::npos) << report;
}

// Blender imports the OBJ and its .glb alike: the same (position, UV) corners, the same materials
// and image, and the .glb plays the .pc2. Skipped without Blender.
// An OBJ whose only extra is a vertex colour (`v x y z r g b`, plain `f` lines) is carried too
// (the passthrough used to look only for vt, vn and usemtl, and dropped the colours); and every
// POSITION target declares the bounds of its own values, the unlisted vertices' zeros included.
TEST(ObjPassthrough, VertexColoursAloneAreCarriedAndEveryTargetDeclaresItsBounds) {
  constexpr int R = 17, S = 12;
  const fs::path top = scratch_dir("obj-colours"), dir = top / "work", io = top / "io";
  fs::create_directories(dir);
  fs::create_directories(io);
  std::string obj;
  auto num = [](double x) { return std::to_string(x); };
  std::vector<std::array<double, 3>> colours;
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < S; ++j) {
      const double th = 2 * std::numbers::pi * j / S;
      colours.push_back({double(i) / (R - 1), double(j) / S, 0.25});
      obj += "v " + num(0.1 * std::cos(th)) + " " + num(0.1 * std::sin(th)) + " " + num(double(i) / (R - 1)) + " " +
             num(colours.back()[0]) + " " + num(colours.back()[1]) + " " + num(colours.back()[2]) + "\n";
    }
  obj += "v 0 0 0 0 0 0\nv 0 0 1 1 1 1\n";
  colours.push_back({0, 0, 0});
  colours.push_back({1, 1, 1});
  auto id = [&](int i, int j) { return std::to_string(i * S + j % S + 1); };
  for (int i = 0; i + 1 < R; ++i)
    for (int j = 0; j < S; ++j)
      obj += "f " + id(i, j) + " " + id(i, j + 1) + " " + id(i + 1, j + 1) + " " + id(i + 1, j) + "\n";
  for (int j = 0; j < S; ++j) {
    obj += "f " + std::to_string(R * S + 1) + " " + id(0, j + 1) + " " + id(0, j) + "\n";
    obj += "f " + std::to_string(R * S + 2) + " " + id(R - 1, j) + " " + id(R - 1, j + 1) + "\n";
  }
  spit(dir / "colours.obj", obj);
  fit_and_bind(dir, io, "colours.obj", " -k 6 -n 8");
  spit(dir / "scene.json", kTexturedScene);
  const ToolRun r = run_tool(
      SWEEP_SIM_EXE,
      quoted(dir / "rig.json") + " --scene " + quoted(dir / "scene.json") + " -q -o " + quoted(dir / "out.glb"), io);
  ASSERT_EQ(r.code, 0) << r.err;
  const Glb out = read_glb(dir / "out.glb");
  const Json& primitive = out.json["meshes"][0]["primitives"][0];
  ASSERT_TRUE(primitive["attributes"].contains("COLOR_0")) << primitive.dump();
  const std::vector<float> colour = floats(out.json, out.bin, primitive["attributes"]["COLOR_0"], 4);
  ASSERT_EQ(colour.size(), 4 * colours.size());  // no seams: one glTF vertex an OBJ vertex
  for (std::size_t v = 0; v < colours.size(); ++v)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(colour[4 * v + c], colours[v][c], 1e-6) << v;
  ASSERT_TRUE(primitive.contains("targets"));
  for (const Json& target : primitive["targets"]) {
    const std::size_t accessor = target["POSITION"];
    const std::vector<float> d = floats(out.json, out.bin, accessor, 3);
    for (int c = 0; c < 3; ++c) {
      float lo = d[c], hi = d[c];
      for (std::size_t v = 0; v < d.size() / 3; ++v) {
        lo = std::min(lo, d[3 * v + c]);
        hi = std::max(hi, d[3 * v + c]);
      }
      EXPECT_EQ(out.json["accessors"][accessor]["min"][c].get<float>(), lo) << accessor;
      EXPECT_EQ(out.json["accessors"][accessor]["max"][c].get<float>(), hi) << accessor;
    }
  }
  int code = 0;
  const std::string report = validate(dir / "out.glb", &code);
  EXPECT_EQ(code, 0) << report;
}

TEST(ObjPassthrough, BlenderShowsTheObjsSurfaceAndPlaysTheBake) {
  if (!have_blender()) GTEST_SKIP() << "blender is not installed";
  const fs::path top = scratch_dir("obj-passthrough-blender"), dir = top / "work", io = top / "io";
  fs::create_directories(dir);
  fs::create_directories(io);
  write_textured_obj(dir);
  fit_and_bind(dir, io, "creature.obj", " -k 6 -n 8");
  spit(dir / "scene.json", kTexturedScene);
  const ToolRun r = run_tool(SWEEP_SIM_EXE,
                             quoted(dir / "rig.json") + " --scene " + quoted(dir / "scene.json") + " -q -o " +
                                 quoted(dir / "out.glb") + " -o " + quoted(dir / "out.pc2"),
                             io);
  ASSERT_EQ(r.code, 0) << r.err;
  const fs::path script = fs::path(SWEEP_SOURCE_DIR) / "tests/blender/check_passthrough.py";
  const ToolRun b = run_tool("blender",
                             "-b --factory-startup --python-exit-code 1 --python " + quoted(script) + " -- " +
                                 quoted(dir / "creature.obj") + " " + quoted(dir / "out.glb") + " " +
                                 quoted(dir / "out.pc2") + " 10 creature",
                             io);
  std::string lines;
  std::istringstream in(b.out);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("ok", 0) == 0 || line.rfind("FAIL", 0) == 0 || line.rfind("blender check", 0) == 0)
      lines += line + "\n";
  }
  std::cout << lines;
  EXPECT_EQ(b.code, 0) << b.out << b.err;
  EXPECT_NE(lines.find("blender check: passed"), std::string::npos) << b.out << b.err;
}

// FBX (read by assimp, welded by position): the same tube written as FBX by Blender (texture
// embedded) carries its UVs, normals and materials with the image, and the targets follow the .pc2.
// Skipped without Blender (which writes the FBX).
TEST(FbxPassthrough, UvsNormalsAndTheMaterialsImageCarryIntoTheGlb) {
  if (!have_blender()) GTEST_SKIP() << "blender is not installed (it writes the FBX)";
  constexpr int R = TexturedAsset::kRings, S = TexturedAsset::kSegments;
  const fs::path top = scratch_dir("fbx-passthrough"), dir = top / "work", io = top / "io";
  fs::create_directories(dir);
  fs::create_directories(io);
  write_textured_obj(dir / "..");
  const ToolRun x = obj_to_fbx(top / "creature.obj", dir / "creature.fbx", io);
  ASSERT_EQ(x.code, 0) << x.out << x.err;
  fit_and_bind(dir, io, "creature.fbx", " -k 6 -n 8");
  spit(dir / "scene.json", kTexturedScene);
  const ToolRun r = run_tool(SWEEP_SIM_EXE,
                             quoted(dir / "rig.json") + " --scene " + quoted(dir / "scene.json") + " -q -o " +
                                 quoted(dir / "out.glb") + " -o " + quoted(dir / "out.pc2"),
                             io);
  ASSERT_EQ(r.code, 0) << r.err;
  const Glb out = read_glb(dir / "out.glb");
  ASSERT_TRUE(out.json.contains("materials"));
  std::size_t skin = 0;
  for (std::size_t m = 0; m < out.json["materials"].size(); ++m)
    skin = out.json["materials"][m]["name"] == "Skin" ? m : skin;
  ASSERT_EQ(out.json["materials"][skin]["name"], "Skin");
  const std::size_t texture = out.json["materials"][skin]["pbrMetallicRoughness"]["baseColorTexture"]["index"];
  EXPECT_EQ(view_bytes(out.json, out.bin,
                       out.json["images"][out.json["textures"][texture]["source"].get<std::size_t>()]["bufferView"]),
            tiny_png());
  const Mesh mesh = assets::read_mesh(dir / "creature.fbx");
  std::map<std::array<float, 3>, std::uint32_t> by_position;
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    const Eigen::Vector3f p = mesh.positions[v].cast<float>();
    by_position[{p.x(), p.y(), p.z()}] = v;
  }
  // The .pc2 holds the mesh in its own space: its node's world transform maps it to the .glb's.
  const Eigen::Affine3d to_world =
      assets::read_scene_mesh(dir / "creature.fbx", "", assets::MeshPick::only_or_largest).to_world;
  const std::string pc2 = slurp(dir / "out.pc2");
  double worst_uv = 0, worst = 0, moved = 0;
  std::size_t side_vertices = 0;
  for (const Json& prim : out.json["meshes"][0]["primitives"]) {
    const std::vector<float> rest = floats(out.json, out.bin, prim["attributes"]["POSITION"], 3);
    std::vector<std::uint32_t> source;
    for (std::size_t v = 0; v < rest.size() / 3; ++v) {
      const auto it = by_position.find({rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]});
      ASSERT_NE(it, by_position.end());
      source.push_back(it->second);
    }
    for (int k = 0; k < 6; ++k) {
      const std::vector<float> d = floats(out.json, out.bin, prim["targets"][k]["POSITION"], 3);
      int points = 0;
      const std::vector<float> local = pc2_frame(pc2, k, &points);
      for (std::size_t v = 0; v < source.size(); ++v) {
        const std::size_t at = 3 * source[v];
        const Vec3 world = to_world * Vec3(local[at], local[at + 1], local[at + 2]);
        for (int c = 0; c < 3; ++c) {
          worst = std::max(worst, std::abs(rest[3 * v + c] + d[3 * v + c] - world[c]));
          moved = std::max(moved, double(std::abs(d[3 * v + c])));
        }
      }
    }
    if (prim["material"] != skin) continue;
    const std::vector<float> uv = floats(out.json, out.bin, prim["attributes"]["TEXCOORD_0"], 2);
    const std::vector<std::uint32_t> triangles = uints(out.json, out.bin, prim["indices"]);
    const std::set<std::uint32_t> used(triangles.begin(), triangles.end());
    side_vertices = used.size();
    for (const std::uint32_t v : used) {
      const double z = rest[3 * v + 2], th = std::atan2(rest[3 * v + 1], rest[3 * v]);
      const int i = static_cast<int>(std::lround(z * (R - 1)));
      int j = static_cast<int>(std::lround(th / (2 * std::numbers::pi) * S + S)) % S;
      if (j == 0 && uv[2 * v] > 0.5f) j = S;  // the seam's second copy
      worst_uv = std::max(
          {worst_uv, std::abs(uv[2 * v] - double(j) / S), std::abs(uv[2 * v + 1] - (1 - double(i) / (R - 1)))});
    }
  }
  std::cout << "fbx passthrough: " << side_vertices << " side vertices, UV error " << worst_uv << ", largest move "
            << moved << ", rest + delta against the .pc2 " << worst << "\n";
  EXPECT_EQ(side_vertices, static_cast<std::size_t>(R * (S + 1)));
  EXPECT_LT(worst_uv, 1e-5);
  EXPECT_GT(moved, 0.02);
  EXPECT_LT(worst, 1e-6);
  int code = -1;
  const std::string report = validate(dir / "out.glb", &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numWarnings\": 0"), std::string::npos) << report;
}

// FBX's unit: assimp applies no unit scale (no post-processing), so the points are in the
// file's unit, which sweep-fit -v and the report say from the file's UnitScaleFactor. Blender writes
// the tube in metres (UnitScaleFactor 100, coordinates as in the OBJ) and in centimetres
// (UnitScaleFactor 1, coordinates × 100); each fits with seeds in its own unit. Skipped without
// Blender (which writes the FBX).
TEST(SceneMeshes, AnFbxsUnitIsSaidAndNotApplied) {
  if (!have_blender()) GTEST_SKIP() << "blender is not installed (it writes the FBX)";
  const fs::path top = scratch_dir("scene-meshes-fbx-unit"), dir = top / "work", io = top / "io";
  fs::create_directories(dir);
  fs::create_directories(io);
  write_textured_obj(top);
  struct Case {
    const char* file;
    const char* blender_args;
    double scale;  // file units per OBJ unit
    std::string said;
    double metres_per_unit;
  };
  const Case cases[] = {
      {"metres.fbx", "", 1, "FBX UnitScaleFactor 100 (the file's unit is 100 cm = 1 m): points are in metres", 1},
      {"centimetres.fbx", " 1 FBX_SCALE_NONE", 100,
       "FBX UnitScaleFactor 1 (the file's unit is 1 cm): points are in centimetres (× 0.01 → metres; a material's "
       "metres_per_unit 0.01)",
       0.01},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const ToolRun x = obj_to_fbx(top / "creature.obj", dir / c.file, io, c.blender_args);
    ASSERT_EQ(x.code, 0) << x.out << x.err;
    const std::string seeds = " --root 0,0," + std::to_string(0.02 * c.scale) + " --tip 0,0," + std::to_string(c.scale);
    const ToolRun r = run_tool(SWEEP_FIT_EXE,
                               quoted(dir / c.file) + " -o " + quoted(dir / (std::string(c.file) + ".rig.json")) +
                                   " --name tube -k 6 -n 8 -v --report " + quoted(dir / "fit.json") + seeds,
                               io);
    ASSERT_EQ(r.code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("no unit scale; " + c.said), std::string::npos) << r.out;
    const Json summary = Json::parse(slurp(dir / "fit.json"))["mesh_summary"];
    EXPECT_EQ(summary["unit"]["metres_per_unit"].get<double>(), c.metres_per_unit);
    EXPECT_EQ(summary["unit"]["unit_scale_factor"].get<double>(), 100 * c.metres_per_unit);
    // Not applied: the tube's length (1 in the OBJ) is 1 or 100 in the file's unit.
    EXPECT_NEAR(summary["bounding_box"]["max"][2].get<double>(), c.scale, 1e-6 * c.scale);
    std::cout << c.file << ": " << c.said << "; bounding box z to " << summary["bounding_box"]["max"][2] << "\n";
  }
}

// The passthrough .glb is the same bytes on every run and thread count, from a glTF and from an OBJ;
// an OBJ whose texture is missing is baked with a warning naming it, the material kept with its
// base colour and no image (files other tools write often name textures not sent along).
TEST(GltfPassthrough, SameBytesEveryRunAndAnObjsMissingTextureIsAWarning) {
  const TexturedWorkspace ws("gltf-passthrough-determinism");
  const std::string args = " --scene " + quoted(ws / "scene.json") + " -q ";
  ASSERT_EQ(
      run_tool(SWEEP_SIM_EXE, quoted(ws / "rig.json") + args + "-o " + quoted(ws / "a.glb"), ws.io, "OMP_NUM_THREADS=1")
          .code,
      0);
  ASSERT_EQ(
      run_tool(SWEEP_SIM_EXE, quoted(ws / "rig.json") + args + "-o " + quoted(ws / "b.glb"), ws.io, "OMP_NUM_THREADS=2")
          .code,
      0);
  EXPECT_EQ(slurp(ws / "a.glb"), slurp(ws / "b.glb"));
  EXPECT_GT(slurp(ws / "a.glb").size(), 10000u);

  const fs::path top = scratch_dir("obj-passthrough-determinism"), dir = top / "work", io = top / "io";
  fs::create_directories(dir);
  fs::create_directories(io);
  write_textured_obj(dir);
  fit_and_bind(dir, io, "creature.obj", " -k 6 -n 8");
  spit(dir / "scene.json", kTexturedScene);
  const std::string obj_args = quoted(dir / "rig.json") + " --scene " + quoted(dir / "scene.json") + " -q -o ";
  ASSERT_EQ(run_tool(SWEEP_SIM_EXE, obj_args + quoted(dir / "a.glb"), io, "OMP_NUM_THREADS=1").code, 0);
  ASSERT_EQ(run_tool(SWEEP_SIM_EXE, obj_args + quoted(dir / "b.glb"), io, "OMP_NUM_THREADS=2").code, 0);
  EXPECT_EQ(slurp(dir / "a.glb"), slurp(dir / "b.glb"));
  fs::remove(dir / "a.glb");
  fs::remove(dir / "b.glb");
  fs::remove(dir / "skin.png");
  const ToolRun r = run_tool(SWEEP_SIM_EXE, obj_args + quoted(dir / "c.glb") + " -o " + quoted(dir / "c.pc2"), io);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
  EXPECT_EQ(r.err_lines()[0].rfind("warning: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("skin.png: cannot read material 'Skin''s texture (map_Kd, line 3 of its library)"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("the material keeps its base colour only"), std::string::npos) << r.err;
  const Glb c = read_glb(dir / "c.glb");
  EXPECT_EQ(c.json["materials"][0]["name"], "Skin");
  EXPECT_EQ(c.json["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"], (Json{0.8, 0.8, 0.8, 1.0}));
  EXPECT_FALSE(c.json["materials"][0]["pbrMetallicRoughness"].contains("baseColorTexture"));
  EXPECT_FALSE(c.json.contains("images") && !c.json["images"].empty());
  int code = -1;
  const std::string report = validate(dir / "c.glb", &code);
  EXPECT_EQ(code, 0) << report;
}

// Blender's glTF importer (tests/blender/check_passthrough.py): the bake keeps the Tail's UVs,
// colours, materials and image, and its animation plays the .pc2's frames. Skipped without Blender.
TEST(GltfPassthrough, BlenderShowsTheAssetAndPlaysTheBake) {
  if (!have_blender()) GTEST_SKIP() << "blender is not installed";
  const TexturedWorkspace ws("gltf-passthrough-blender");
  const ToolRun r = ws.bake("-o " + quoted(ws / "out.glb") + " -o " + quoted(ws / "out.pc2"));
  ASSERT_EQ(r.code, 0) << r.err;
  const fs::path script = fs::path(SWEEP_SOURCE_DIR) / "tests/blender/check_passthrough.py";
  const ToolRun b = run_tool("blender",
                             "-b --factory-startup --python-exit-code 1 --python " + quoted(script) + " -- " +
                                 quoted(ws / "creature.gltf") + " " + quoted(ws / "out.glb") + " " +
                                 quoted(ws / "out.pc2") + " 10 Tail",
                             ws.io);
  std::string lines;
  std::istringstream in(b.out);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("ok", 0) == 0 || line.rfind("FAIL", 0) == 0 || line.rfind("blender check", 0) == 0)
      lines += line + "\n";
  }
  std::cout << lines;
  EXPECT_EQ(b.code, 0) << b.out << b.err;
  EXPECT_NE(lines.find("blender check: passed"), std::string::npos) << b.out << b.err;
}

}  // namespace
}  // namespace sweep::test
