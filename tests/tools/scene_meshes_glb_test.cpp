// The .glb bake of a file read through assimp keeps every mesh of it: a Collada file written by the
// test holds three meshes on three nodes (Body, Tail, Prop; two of them moved by their node's
// matrix) and two materials (Body and Prop red, Tail blue). The tail is fitted (sweep-fit --mesh
// Tail), bound and pushed. The .glb must hold three nodes and meshes in the file's order, named as
// the file names them, each with its material; Body and Prop where the file places them, with no
// morph target; Tail's POSITION plus each frame's target the .pc2's frame; and pass the Khronos
// validator.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "glb_file.h"
#include "sweep/assets/mesh_surface.h"
#include "sweep/core/error.h"
#include "tool_runner.h"

namespace sweep::test {
namespace {

using Json = nlohmann::json;
using Vec3 = Eigen::Vector3d;
using Mat4 = Eigen::Matrix4d;

struct NodeMesh {
  std::string name, material;
  Mat4 matrix = Mat4::Identity();  // the node's, local → world
  std::vector<Vec3> local;         // as written (exact in float)
  std::vector<int> triangles;
  Vec3 world(std::size_t v) const { return (matrix * local[v].homogeneous()).head<3>(); }
};

// A box of half sizes h.
NodeMesh box(const std::string& name, const Vec3& h) {
  NodeMesh p;
  p.name = name;
  p.material = "Red";
  for (int k = 0; k < 8; ++k)
    p.local.emplace_back((k & 1 ? 1 : -1) * h.x(), (k & 2 ? 1 : -1) * h.y(), (k & 4 ? 1 : -1) * h.z());
  p.triangles = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return p;
}

// A closed tube along +z from 0 to 1 (radius 0.1): 11 rings of 8, a centre at each end.
NodeMesh tube() {
  NodeMesh p;
  p.name = "Tail";
  p.material = "Blue";
  constexpr int kRings = 11, kSegments = 8;
  for (int i = 0; i < kRings; ++i) {
    for (int j = 0; j < kSegments; ++j) {
      const double a = 2 * 3.14159265358979 * j / kSegments;
      p.local.emplace_back(static_cast<float>(0.1 * std::cos(a)), static_cast<float>(0.1 * std::sin(a)), 0.1 * i);
    }
  }
  const int bottom = kRings * kSegments, top = bottom + 1;
  p.local.emplace_back(0, 0, 0);
  p.local.emplace_back(0, 0, 1);
  for (int i = 0; i + 1 < kRings; ++i) {
    for (int j = 0; j < kSegments; ++j) {
      const int a = i * kSegments + j, b = i * kSegments + (j + 1) % kSegments;
      p.triangles.insert(p.triangles.end(), {a, b, a + kSegments, b, b + kSegments, a + kSegments});
    }
  }
  for (int j = 0; j < kSegments; ++j) {
    p.triangles.insert(p.triangles.end(), {bottom, (j + 1) % kSegments, j});
    const int last = (kRings - 1) * kSegments;
    p.triangles.insert(p.triangles.end(), {top, last + j, last + (j + 1) % kSegments});
  }
  return p;
}

std::vector<NodeMesh> pieces() {
  NodeMesh body = box("Body", Vec3(0.3, 0.2, 0.25));
  body.matrix(2, 3) = -0.5;
  NodeMesh prop = box("Prop", Vec3(0.1, 0.2, 0.05));
  prop.matrix << 0, -1, 0, 2, 1, 0, 0, 0.5, 0, 0, 1, -1, 0, 0, 0, 1;  // a quarter turn about z, moved
  return {body, tube(), prop};
}

const std::map<std::string, std::array<double, 4>> kColours = {{"Red", {0.8, 0.1, 0.1, 1}},
                                                               {"Blue", {0.1, 0.2, 0.9, 1}}};

std::string collada(const std::vector<NodeMesh>& list) {
  std::ostringstream geometries, nodes, effects, materials;
  geometries.precision(9);
  nodes.precision(17);
  for (const auto& [name, c] : kColours) {
    effects << "<effect id=\"" << name << "-fx\"><profile_COMMON><technique sid=\"common\"><lambert><diffuse><color>"
            << c[0] << ' ' << c[1] << ' ' << c[2] << ' ' << c[3]
            << "</color></diffuse></lambert></technique></profile_COMMON></effect>\n";
    materials << "<material id=\"" << name << "\" name=\"" << name << "\"><instance_effect url=\"#" << name
              << "-fx\"/></material>\n";
  }
  for (const NodeMesh& p : list) {
    geometries << "<geometry id=\"" << p.name << "-mesh\" name=\"" << p.name << "\"><mesh><source id=\"" << p.name
               << "-p\"><float_array id=\"" << p.name << "-pa\" count=\"" << 3 * p.local.size() << "\">";
    for (const Vec3& v : p.local) geometries << v.x() << ' ' << v.y() << ' ' << v.z() << ' ';
    geometries << "</float_array><technique_common><accessor source=\"#" << p.name << "-pa\" count=\"" << p.local.size()
               << "\" stride=\"3\"><param name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/>"
               << "<param name=\"Z\" type=\"float\"/></accessor></technique_common></source><vertices id=\"" << p.name
               << "-v\"><input semantic=\"POSITION\" source=\"#" << p.name << "-p\"/></vertices><triangles count=\""
               << p.triangles.size() / 3 << "\" material=\"" << p.material
               << "-sym\"><input semantic=\"VERTEX\" source=\"#" << p.name << "-v\" offset=\"0\"/><p>";
    for (const int t : p.triangles) geometries << t << ' ';
    geometries << "</p></triangles></mesh></geometry>\n";
    nodes << "<node id=\"" << p.name << "\" name=\"" << p.name << "\" type=\"NODE\"><matrix sid=\"transform\">";
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) nodes << p.matrix(r, c) << ' ';
    nodes << "</matrix><instance_geometry url=\"#" << p.name << "-mesh\"><bind_material><technique_common>"
          << "<instance_material symbol=\"" << p.material << "-sym\" target=\"#" << p.material
          << "\"/></technique_common></bind_material></instance_geometry></node>\n";
  }
  return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
<library_effects>
)" + effects.str() +
         "</library_effects>\n<library_materials>\n" + materials.str() +
         "</library_materials>\n<library_geometries>\n" + geometries.str() +
         "</library_geometries>\n<library_visual_scenes><visual_scene id=\"Scene\" name=\"Scene\">\n" + nodes.str() +
         R"(</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";
}

TEST(SceneMeshesGlb, EveryMeshOfAColladaFileIsKeptTheStillOnesWhereTheFilePlacesThem) {
  const fs::path top = scratch_dir("scene-meshes-glb"), work = top / "work", io = top / "io";
  fs::create_directories(work);
  fs::create_directories(io);
  const std::vector<NodeMesh> list = pieces();
  spit(work / "three.dae", collada(list));
  // The paper's springs (--springs): the scene's push is sized for them.
  const ToolRun fit = run_tool(SWEEP_FIT_EXE,
                               quoted(work / "three.dae") + " --mesh Tail -o " + quoted(work / "rig.json") +
                                   " --name tail --root 0,0,0.02 --tip 0,0,1 -k 6 -n 8 -q --springs",
                               io);
  ASSERT_EQ(fit.code, 0) << fit.err;
  const ToolRun bind = run_tool(SWEEP_BIND_EXE, quoted(work / "rig.json") + " -q", io);
  ASSERT_EQ(bind.code, 0) << bind.err;
  spit(work / "scene.json", R"({"format": "sweep-scene", "version": 1, "duration": 0.5, "fps": 10,
    "forces": [{"sweep": "tail", "t": 1, "theta": 0, "vector": [0, 30, 0], "start": 0, "end": 0.2}]})");
  const ToolRun bake = run_tool(SWEEP_SIM_EXE,
                                quoted(work / "rig.json") + " --scene " + quoted(work / "scene.json") + " -q -o " +
                                    quoted(work / "out.pc2") + " -o " + quoted(work / "out.glb"),
                                io);
  ASSERT_EQ(bake.code, 0) << bake.err;

  const Glb out = read_glb(work / "out.glb");
  ASSERT_EQ(out.json["nodes"].size(), 3u) << out.json.dump(1);
  ASSERT_EQ(out.json["meshes"].size(), 3u);
  ASSERT_EQ(out.json["materials"].size(), 2u);
  const std::string pc2 = slurp(work / "out.pc2");
  double worst_still = 0, worst_moving = 0, moved = 0;
  for (std::size_t k = 0; k < list.size(); ++k) {
    const NodeMesh& piece = list[k];
    const Json& node = out.json["nodes"][k];
    EXPECT_EQ(node["name"], piece.name);
    ASSERT_TRUE(node.contains("mesh"));
    EXPECT_FALSE(node.contains("matrix") || node.contains("translation") || node.contains("rotation"))
        << "placed in world space: the node has no transform of its own";
    const Json& mesh = out.json["meshes"][node["mesh"].get<std::size_t>()];
    EXPECT_EQ(mesh["name"], piece.name + "-mesh");  // assimp names a Collada mesh by its geometry's id
    ASSERT_EQ(mesh["primitives"].size(), 1u);
    const Json& prim = mesh["primitives"][0];
    const Json& material = out.json["materials"][prim["material"].get<std::size_t>()];
    EXPECT_EQ(material["name"], piece.material);
    const std::array<double, 4>& colour = kColours.at(piece.material);
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(material["pbrMetallicRoughness"]["baseColorFactor"][c].get<double>(), colour[c], 1e-6);
    // Its vertices (one per position: the file gives each corner its position alone) are the piece's,
    // placed in world space by its node; each output vertex found by its nearest input vertex.
    const std::vector<float> rest = floats(out.json, out.bin, prim["attributes"]["POSITION"], 3);
    ASSERT_EQ(rest.size(), 3 * piece.local.size());
    std::vector<std::size_t> of(piece.local.size());
    std::vector<char> found(piece.local.size(), 0);
    for (std::size_t i = 0; i < of.size(); ++i) {
      const Vec3 got(rest[3 * i], rest[3 * i + 1], rest[3 * i + 2]);
      double best = 1e300;
      for (std::size_t v = 0; v < piece.local.size(); ++v) {
        if ((piece.world(v) - got).norm() < best) best = (piece.world(v) - got).norm(), of[i] = v;
      }
      found[of[i]] = 1;
      if (piece.name != "Tail") worst_still = std::max(worst_still, best);
    }
    EXPECT_EQ(std::count(found.begin(), found.end(), 1), static_cast<long>(found.size())) << piece.name;
    if (piece.name != "Tail") {
      EXPECT_FALSE(prim.contains("targets")) << piece.name << " is not the rig's: it never moves";
      continue;
    }
    // The tail: the .pc2 holds the mesh read (--mesh Tail, in its own space: its node's is the
    // identity), welded in first-use order, which the .glb's vertices keep (no seam copies here);
    // POSITION + target k is its frame k, vertex for vertex.
    ASSERT_TRUE(prim.contains("targets"));
    ASSERT_EQ(prim["targets"].size(), 6u);
    for (int f = 0; f < 6; ++f) {
      int points = 0;
      const std::vector<float> frame = pc2_frame(pc2, f, &points);
      ASSERT_EQ(static_cast<std::size_t>(points), piece.local.size());
      const std::vector<float> d = floats(out.json, out.bin, prim["targets"][f]["POSITION"], 3);
      for (std::size_t i = 0; i < of.size(); ++i) {
        const Vec3 baked(frame[3 * i], frame[3 * i + 1], frame[3 * i + 2]);
        const Vec3 at_rest(rest[3 * i], rest[3 * i + 1], rest[3 * i + 2]);
        worst_moving = std::max(worst_moving, (at_rest + Vec3(d[3 * i], d[3 * i + 1], d[3 * i + 2]) - baked).norm());
        moved = std::max(moved, (baked - piece.world(of[i])).norm());
      }
    }
  }
  EXPECT_LT(worst_still, 1e-6) << "the still meshes where the file places them";
  EXPECT_LT(worst_moving, 1e-6) << "the tail's morphed positions against the .pc2";
  EXPECT_GT(moved, 0.02) << "the push hardly moved the tail: the check above could not fail";
  int code = -1;
  const std::string report = validate(work / "out.glb", &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numErrors\": 0"), std::string::npos) << report;
}

// A texture the file names but that is neither in it nor beside it: the .glb bake warns, naming
// the file, the material and the texture, and keeps the material with its base colour; asked with
// no one to warn, it is refused (bad input) as before.
TEST(SceneMeshesGlb, AMissingTextureIsAWarningAndTheMaterialKeepsItsColour) {
  const fs::path dir = scratch_dir("scene-meshes-missing-texture");
  fs::create_directories(dir);
  std::string text = collada(pieces());
  const std::string effect = "<effect id=\"Blue-fx\"><profile_COMMON>";
  const std::size_t at = text.find(effect);
  ASSERT_NE(at, std::string::npos);
  text.insert(at + effect.size(),
              "<newparam sid=\"s-surface\"><surface type=\"2D\"><init_from>gone</init_from></surface></newparam>"
              "<newparam sid=\"s-sampler\"><sampler2D><source>s-surface</source></sampler2D></newparam>");
  const std::size_t colour = text.find("<diffuse>", at);
  text.insert(colour + 9, "<texture texture=\"s-sampler\" texcoord=\"UV\"/>");
  text.replace(text.find("<library_effects>"), 17,
               "<library_images><image id=\"gone\" name=\"gone\"><init_from>textures/gone.png</init_from></image>"
               "</library_images>\n<library_effects>");
  spit(dir / "missing.dae", text);
  std::vector<std::string> warnings;
  const assets::SceneSurface surface =
      assets::read_scene_surface(dir / "missing.dae", "Tail", [&](const std::string& w) { warnings.push_back(w); });
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("missing.dae"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("'Blue'"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("gone.png"), std::string::npos) << warnings[0];
  ASSERT_EQ(surface.nodes.size(), 3u);
  bool blue = false;
  for (const assets::SurfaceMaterial& m : surface.materials) {
    if (m.name != "Blue") continue;
    blue = true;
    EXPECT_TRUE(m.texture.empty());
    EXPECT_NEAR(m.colour[2], 0.9, 1e-6);
  }
  EXPECT_TRUE(blue);
  EXPECT_THROW(assets::read_scene_surface(dir / "missing.dae", "Tail"), Error);
}

}  // namespace
}  // namespace sweep::test
