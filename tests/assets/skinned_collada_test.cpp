// A skinned character read through assimp bakes to a rigged .glb as a glTF character does
// (skin_gltf.h): the creature of skinned_glb_support.h written as Collada by the test (its mesh,
// skin, inverse binds, node tree and both clips, each animated node keyed by its local matrix at
// its clip's key times), its tail bound and baked walking. The .glb must pass the Khronos
// validator, keep the input's joints and clips as assimp reads them, and, read back with tinygltf
// and skinned here, show the .pc2.
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "assets/skinned_glb_support.h"
#include "sweep/assets/gltf_skin.h"
#include "sweep/io/binding_file.h"

namespace sweep::test {
namespace {

using namespace skinned_glb;

std::string row_major(const Mat4& m) {
  std::ostringstream out;
  out.precision(17);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out << m(r, c) << ' ';
  return out.str();
}

// Props beside the creature (with_prop): a box of these corners on a root node "Prop" moved by
// kPropAt, a mesh of no skin; and the same box at kSaddleAt, "Saddle", skinned to the Hip alone
// (the creature's inverse bind matrix for it).
const Vec3 kPropAt(2, 0.5, -1), kSaddleAt(0, 0.75, -0.3);
std::vector<Vec3> prop_corners() {
  std::vector<Vec3> out;
  for (int k = 0; k < 8; ++k) out.emplace_back(k & 1 ? 0.25 : -0.25, k & 2 ? 0.5 : -0.5, k & 4 ? 0.125 : -0.125);
  return out;
}

// The creature as Collada: the same vertices (mesh space = world: its node is at the origin),
// triangles, weights and inverse binds; nodes named as the glTF's, each with its rest matrix.
void write_creature_dae(const fs::path& dae, bool with_prop = false) {
  const fs::path gltf = fs::path(SWEEP_SOURCE_DIR) / "meshes/skinned_tail.gltf";
  const Mesh mesh = assets::read_mesh(gltf);
  const assets::SkinModel m = *assets::read_gltf_skin(gltf, mesh.positions, Eigen::Affine3d::Identity());
  const std::size_t n = mesh.vertex_count();
  std::ostringstream pos, tris, vcount, v, weights, names, ibm;
  pos.precision(17);
  weights.precision(17);
  for (const Vec3& p : m.bind_positions) pos << p.x() << ' ' << p.y() << ' ' << p.z() << ' ';
  const std::vector<std::uint32_t> triangles = mesh.triangles();
  for (const std::uint32_t t : triangles) tris << t << ' ';
  int weight_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    int used = 0;
    for (int e = 0; e < 4; ++e) {
      if (m.vertex_weights[i][e] == 0) continue;
      v << m.vertex_joints[i][e] << ' ' << weight_count++ << ' ';
      weights << m.vertex_weights[i][e] << ' ';
      ++used;
    }
    vcount << used << ' ';
  }
  for (std::size_t k = 0; k < m.joints.size(); ++k) {
    names << m.nodes[static_cast<std::size_t>(m.joints[k])].name << ' ';
    ibm << row_major(m.inverse_bind[k]);
  }
  // Rest matrices, and each clip's animated nodes keyed by their local matrix at its key times.
  const std::vector<Mat4> rest = assets::world_transforms(m, -1, 0);
  auto local = [&](const std::vector<Mat4>& world, std::size_t i) {
    const int p = m.nodes[i].parent;
    return p < 0 ? world[i] : Mat4(world[static_cast<std::size_t>(p)].inverse() * world[i]);
  };
  std::ostringstream animations;
  animations.precision(17);
  for (std::size_t c = 0; c < m.clips.size(); ++c) {
    const assets::SkinClip& clip = m.clips[c];
    animations << "<animation id=\"clip" << c << "\" name=\"" << clip.name << "\">\n";
    std::set<int> nodes;
    for (const assets::ClipChannel& ch : clip.channels) nodes.insert(ch.node);
    for (const int node : nodes) {
      std::set<double> times;
      for (const assets::ClipChannel& ch : clip.channels)
        if (ch.node == node) times.insert(ch.times.begin(), ch.times.end());
      std::ostringstream t, keys;
      t.precision(17);
      for (const double time : times) {
        t << time << ' ';
        keys << row_major(
            local(assets::world_transforms(m, static_cast<int>(c), time), static_cast<std::size_t>(node)));
      }
      const std::string id = "c" + std::to_string(c) + "n" + std::to_string(node);
      const std::string name = m.nodes[static_cast<std::size_t>(node)].name;
      animations << "<source id=\"" << id << "-t\"><float_array id=\"" << id << "-ta\" count=\"" << times.size()
                 << "\">" << t.str() << "</float_array><technique_common><accessor source=\"#" << id << "-ta\" count=\""
                 << times.size()
                 << "\" stride=\"1\"><param name=\"TIME\" type=\"float\"/></accessor></technique_common></source>\n"
                 << "<source id=\"" << id << "-m\"><float_array id=\"" << id << "-ma\" count=\"" << 16 * times.size()
                 << "\">" << keys.str() << "</float_array><technique_common><accessor source=\"#" << id
                 << "-ma\" count=\"" << times.size()
                 << "\" stride=\"16\"><param name=\"TRANSFORM\" type=\"float4x4\"/></accessor></technique_common>"
                 << "</source>\n<sampler id=\"" << id << "-s\"><input semantic=\"INPUT\" source=\"#" << id
                 << "-t\"/><input semantic=\"OUTPUT\" source=\"#" << id << "-m\"/></sampler>\n<channel source=\"#" << id
                 << "-s\" target=\"" << name << "/transform\"/>\n";
    }
    animations << "</animation>\n";
  }
  std::function<std::string(std::size_t)> node_xml = [&](std::size_t i) {
    const std::string& name = m.nodes[i].name;
    const bool is_joint = std::find(m.joints.begin(), m.joints.end(), static_cast<int>(i)) != m.joints.end();
    std::string xml = "<node id=\"" + name + "\" name=\"" + name + "\" sid=\"" + name + "\" type=\"" +
                      (is_joint ? "JOINT" : "NODE") + "\"><matrix sid=\"transform\">" + row_major(local(rest, i)) +
                      "</matrix>";
    if (static_cast<int>(i) == m.mesh_node)
      xml += "<instance_controller url=\"#skin\"><skeleton>#" + m.nodes[static_cast<std::size_t>(m.joints[0])].name +
             "</skeleton></instance_controller>";
    for (std::size_t c = 0; c < m.nodes.size(); ++c)
      if (m.nodes[c].parent == static_cast<int>(i)) xml += node_xml(c);
    return xml + "</node>\n";
  };
  std::string scene;
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    if (m.nodes[i].parent < 0) scene += node_xml(i);
  std::string prop_geometry, saddle_controller;
  if (with_prop) {
    std::ostringstream corners;
    for (const Vec3& c : prop_corners()) corners << c.x() << ' ' << c.y() << ' ' << c.z() << ' ';
    prop_geometry =
        R"(<geometry id="prop-mesh" name="Prop"><mesh><source id="pp"><float_array id="ppa" count="24">)" +
        corners.str() +
        R"(</float_array><technique_common><accessor source="#ppa" count="8" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="pv"><input semantic="POSITION" source="#pp"/></vertices>
<triangles count="12"><input semantic="VERTEX" source="#pv" offset="0"/><p>0 2 1 1 2 3 4 5 6 5 7 6 0 1 4 1 5 4 2 6 3 3 6 7 0 4 2 2 4 6 1 3 5 3 7 5</p></triangles>
</mesh></geometry>
)";
    scene += "<node id=\"Prop\" name=\"Prop\" type=\"NODE\"><matrix sid=\"transform\">1 0 0 " +
             std::to_string(kPropAt.x()) + " 0 1 0 " + std::to_string(kPropAt.y()) + " 0 0 1 " +
             std::to_string(kPropAt.z()) + " 0 0 0 1</matrix><instance_geometry url=\"#prop-mesh\"/></node>\n";
    std::ostringstream saddle;
    saddle.precision(17);
    for (const Vec3& c : prop_corners())
      saddle << c.x() + kSaddleAt.x() << ' ' << c.y() + kSaddleAt.y() << ' ' << c.z() + kSaddleAt.z() << ' ';
    prop_geometry +=
        R"(<geometry id="saddle-mesh" name="Saddle"><mesh><source id="sp"><float_array id="spa" count="24">)" +
        saddle.str() +
        R"(</float_array><technique_common><accessor source="#spa" count="8" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="sv"><input semantic="POSITION" source="#sp"/></vertices>
<triangles count="12"><input semantic="VERTEX" source="#sv" offset="0"/><p>0 2 1 1 2 3 4 5 6 5 7 6 0 1 4 1 5 4 2 6 3 3 6 7 0 4 2 2 4 6 1 3 5 3 7 5</p></triangles>
</mesh></geometry>
)";
    const std::size_t hip = static_cast<std::size_t>(m.joint_of_node(m.find_node("Hip")));
    saddle_controller =
        R"(<controller id="saddle-skin" name="saddle-skin"><skin source="#saddle-mesh">
<bind_shape_matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</bind_shape_matrix>
<source id="sj"><Name_array id="sja" count="1">Hip</Name_array><technique_common><accessor source="#sja" count="1" stride="1"><param name="JOINT" type="name"/></accessor></technique_common></source>
<source id="sb"><float_array id="sba" count="16">)" +
        row_major(m.inverse_bind[hip]) +
        R"(</float_array><technique_common><accessor source="#sba" count="1" stride="16"><param name="TRANSFORM" type="float4x4"/></accessor></technique_common></source>
<source id="sw"><float_array id="swa" count="1">1</float_array><technique_common><accessor source="#swa" count="1" stride="1"><param name="WEIGHT" type="float"/></accessor></technique_common></source>
<joints><input semantic="JOINT" source="#sj"/><input semantic="INV_BIND_MATRIX" source="#sb"/></joints>
<vertex_weights count="8"><input semantic="JOINT" source="#sj" offset="0"/><input semantic="WEIGHT" source="#sw" offset="1"/>
<vcount>1 1 1 1 1 1 1 1</vcount><v>0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0</v></vertex_weights>
</skin></controller>
)";
    scene +=
        "<node id=\"Saddle\" name=\"Saddle\" type=\"NODE\"><instance_controller "
        "url=\"#saddle-skin\"><skeleton>#Hip</skeleton></instance_controller></node>\n";
  }
  std::ofstream out(dae);
  out << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
<library_geometries><geometry id="creature-mesh" name="creature"><mesh>
<source id="p"><float_array id="pa" count=")"
      << 3 * n << "\">" << pos.str() << R"(</float_array><technique_common><accessor source="#pa" count=")" << n
      << R"(" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles count=")"
      << triangles.size() / 3 << R"("><input semantic="VERTEX" source="#v" offset="0"/><p>)" << tris.str()
      << R"(</p></triangles>
</mesh></geometry>
)" << prop_geometry
      << R"(</library_geometries>
<library_controllers><controller id="skin" name="skin"><skin source="#creature-mesh">
<bind_shape_matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</bind_shape_matrix>
<source id="j"><Name_array id="ja" count=")"
      << m.joints.size() << "\">" << names.str() << R"(</Name_array><technique_common><accessor source="#ja" count=")"
      << m.joints.size() << R"(" stride="1"><param name="JOINT" type="name"/></accessor></technique_common></source>
<source id="b"><float_array id="ba" count=")"
      << 16 * m.joints.size() << "\">" << ibm.str()
      << R"(</float_array><technique_common><accessor source="#ba" count=")" << m.joints.size()
      << R"(" stride="16"><param name="TRANSFORM" type="float4x4"/></accessor></technique_common></source>
<source id="w"><float_array id="wa" count=")"
      << weight_count << "\">" << weights.str() << R"(</float_array><technique_common><accessor source="#wa" count=")"
      << weight_count << R"(" stride="1"><param name="WEIGHT" type="float"/></accessor></technique_common></source>
<joints><input semantic="JOINT" source="#j"/><input semantic="INV_BIND_MATRIX" source="#b"/></joints>
<vertex_weights count=")"
      << n << R"("><input semantic="JOINT" source="#j" offset="0"/><input semantic="WEIGHT" source="#w" offset="1"/>
<vcount>)"
      << vcount.str() << "</vcount><v>" << v.str() << R"(</v></vertex_weights>
</skin></controller>
)" << saddle_controller
      << R"(</library_controllers>
<library_animations>
)" << animations.str()
      << R"(</library_animations>
<library_visual_scenes><visual_scene id="Scene" name="Scene">
)" << scene
      << R"(</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";
}

struct DaeBake {
  Asset asset;
  fs::path glb, pc2, report;
  bool ok = false;
};
const DaeBake& dae_bake() {
  static const DaeBake bake = [] {
    DaeBake b{{here("creature.dae"), here("creature.rig.json"), here("creature.bind")},
              here("creature.glb"),
              here("creature.pc2"),
              here("creature.report.json")};
    write_creature_dae(b.asset.gltf);
    // assimp names a Collada clip after the first clip and its own: "Walk_Walk", "Walk_Blink".
    std::string walk = kWalk;
    walk.replace(walk.find("\"Walk\""), 6, "\"Walk_Walk\"");
    io::write_rig(b.asset.rig, rig_of({straight_sweep("tail", false)}, "creature.dae"));
    const std::string bind =
        std::string(SWEEP_BIND_EXE) + " -q '" + b.asset.rig.string() + "' -o '" + b.asset.binding.string() + "'";
    b.ok = std::system(bind.c_str()) == 0 &&
           run_sim(b.asset, walk, "-o '" + b.glb.string() + "' -o '" + b.pc2.string() + "'", "creature",
                   "--report '" + b.report.string() + "'") == 0;
    return b;
  }();
  return bake;
}

TEST(SkinnedCollada, TheGlbPassesTheKhronosValidator) {
  const DaeBake& bake = dae_bake();
  ASSERT_TRUE(bake.ok) << io::read_file(here("creature.err"));
  int code = -1;
  const std::string report = validate(bake.glb, &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numErrors\": 0"), std::string::npos) << report;
}

// The skin's joints, in order, are the input's bones as assimp reads them (then the parts' new
// joints), and the animations are the input's clips, in order, then "sweep bake".
TEST(SkinnedCollada, KeepsTheInputsJointsAndClips) {
  const DaeBake& bake = dae_bake();
  ASSERT_TRUE(bake.ok) << io::read_file(here("creature.err"));
  Assimp::Importer importer;
  const aiScene* in = importer.ReadFile(bake.asset.gltf.string(), 0);
  ASSERT_NE(in, nullptr);
  std::vector<std::string> bones, clips;
  for (unsigned k = 0; k < in->mNumMeshes; ++k)
    for (unsigned b = 0; b < in->mMeshes[k]->mNumBones; ++b)
      if (std::find(bones.begin(), bones.end(), in->mMeshes[k]->mBones[b]->mName.C_Str()) == bones.end())
        bones.push_back(in->mMeshes[k]->mBones[b]->mName.C_Str());
  for (unsigned a = 0; a < in->mNumAnimations; ++a) clips.push_back(in->mAnimations[a]->mName.C_Str());
  ASSERT_EQ(bones.size(), 4u) << "the creature's Hip, Tail1, Tail2, Tail3";
  ASSERT_EQ(clips.size(), 2u) << "Walk and Blink";

  const tinygltf::Model out = load(bake.glb);
  ASSERT_EQ(out.skins.size(), 1u);
  const std::vector<int>& joints = out.skins[0].joints;
  ASSERT_GT(joints.size(), bones.size()) << "the parts' joints are added";
  for (std::size_t k = 0; k < bones.size(); ++k)
    EXPECT_EQ(out.nodes[static_cast<std::size_t>(joints[k])].name, bones[k]);
  ASSERT_EQ(out.animations.size(), clips.size() + 1);
  for (std::size_t a = 0; a < clips.size(); ++a) EXPECT_EQ(out.animations[a].name, clips[a]);
  EXPECT_EQ(out.animations.back().name, "sweep bake");
}

// "sweep bake" skinned here at every frame is the .pc2: the tail within the skinned-export error
// the bake reports (and under 1 % of its length), every other vertex — the input's skin as assimp
// read it, played by the bake — to 1e-5 of the tail's length.
TEST(SkinnedCollada, TheBakedClipSkinnedIsTheBake) {
  const DaeBake& bake = dae_bake();
  ASSERT_TRUE(bake.ok) << io::read_file(here("creature.err"));
  const tinygltf::Model out = load(bake.glb);
  const int baked = find_animation(out, "sweep bake");
  ASSERT_GE(baked, 0);
  const Pc2 cache(bake.pc2);
  ASSERT_EQ(cache.frames, 31);
  const std::vector<char> part = part_vertices(bake.asset);
  const double length = 1.0;  // the tail's
  double worst = 0, worst_outside = 0, moved = 0, moved_outside = 0;
  for (int k = 0; k < cache.frames; ++k) {
    const std::vector<Vec3> shown = played(out, baked, static_cast<std::size_t>(k), /*morph=*/false).positions;
    ASSERT_EQ(shown.size(), part.size());
    for (std::size_t v = 0; v < shown.size(); ++v) {
      const double e = (shown[v] - cache.at(k, v)).norm();
      (part[v] ? worst : worst_outside) = std::max(part[v] ? worst : worst_outside, e);
      (part[v] ? moved : moved_outside) =
          std::max(part[v] ? moved : moved_outside, (cache.at(k, v) - cache.at(0, v)).norm());
    }
  }
  // Independently of assimp: the glTF creature the Collada file was written from, skinned by its
  // own clip. The looping bake plays Walk at scene time mod 1 s (the preroll runs before frame 0):
  // frames 0, 15 and 30 at 0, 0.5 and 0 s, key times of every channel, where the Collada keys are
  // the glTF's pose exactly.
  const fs::path gltf = fs::path(SWEEP_SOURCE_DIR) / "meshes/skinned_tail.gltf";
  const Mesh original = assets::read_mesh(gltf);
  const assets::SkinModel skin = *assets::read_gltf_skin(gltf, original.positions, Eigen::Affine3d::Identity());
  std::map<std::array<double, 3>, std::size_t> by_position;
  for (std::size_t v = 0; v < original.vertex_count(); ++v)
    by_position[{original.positions[v].x(), original.positions[v].y(), original.positions[v].z()}] = v;
  const Mesh read = assets::read_mesh(bake.asset.gltf);
  double worst_input = 0;
  for (const int k : {0, 15, 30}) {
    const std::vector<Mat4> joint =
        assets::joint_matrices(skin, assets::world_transforms(skin, skin.find_clip("Walk"), std::fmod(k / 30.0, 1.0)));
    const std::vector<Vec3> shown = played(out, baked, static_cast<std::size_t>(k), /*morph=*/false).positions;
    for (std::size_t v = 0; v < read.vertex_count(); ++v) {
      if (part[v]) continue;
      const auto it = by_position.find({read.positions[v].x(), read.positions[v].y(), read.positions[v].z()});
      ASSERT_NE(it, by_position.end()) << "vertex " << v << " is not a vertex of the glTF creature";
      worst_input = std::max(worst_input, (shown[v] - assets::skin_vertex(skin, joint, it->second)).norm());
    }
  }
  EXPECT_LT(worst_input, 1e-5 * length);

  const Json report = Json::parse(io::read_file(bake.report));
  EXPECT_TRUE(report.value("skin_joints_in_character", false));
  const double reported = report.at("skin_error_max_relative").get<double>();
  EXPECT_LE(worst / length, reported * (1 + 1e-3) + 1e-6) << "the error the bake reports is the file's";
  EXPECT_LT(worst, 0.01 * length);
  EXPECT_LT(worst_outside, 1e-5 * length);
  EXPECT_GT(moved, 0.1 * length) << "the tail hardly moved: the checks above could not fail";
  EXPECT_GT(moved_outside, 0.01 * length) << "the walk hardly moved the body: the check above could not fail";
  std::cout << "Collada creature: the tail against the .pc2, max " << worst / length << " of its length (reported "
            << reported << "); outside it " << worst_outside << " (against the glTF creature's own skinning "
            << worst_input << ")\n";
}

// --morph: one morph target a frame under the character's skin (its offsets taken back through each
// vertex's skinning matrix); the .glb passes the validator and, skinned here with its targets, is
// the .pc2 to float precision at every vertex.
TEST(SkinnedCollada, WithMorphTargetsTheGlbSkinnedIsTheBakeToFloatPrecision) {
  const DaeBake& bake = dae_bake();
  ASSERT_TRUE(bake.ok) << io::read_file(here("creature.err"));
  const fs::path glb = here("creature.morph.glb");
  std::string walk = kWalk;
  walk.replace(walk.find("\"Walk\""), 6, "\"Walk_Walk\"");
  ASSERT_EQ(run_sim(bake.asset, walk, "-o '" + glb.string() + "'", "creature.morph", "--morph"), 0)
      << io::read_file(here("creature.morph.err"));
  int code = -1;
  const std::string report = validate(glb, &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numErrors\": 0"), std::string::npos) << report;
  const tinygltf::Model out = load(glb);
  const int baked = find_animation(out, "sweep bake");
  ASSERT_GE(baked, 0);
  ASSERT_EQ(out.meshes[0].primitives[0].targets.size(), 31u);
  const Pc2 cache(bake.pc2);
  double worst = 0, moved = 0;
  for (int k = 0; k < cache.frames; ++k) {
    const std::vector<Vec3> shown = played(out, baked, static_cast<std::size_t>(k)).positions;
    ASSERT_EQ(shown.size(), static_cast<std::size_t>(cache.points));
    for (std::size_t v = 0; v < shown.size(); ++v) {
      worst = std::max(worst, (shown[v] - cache.at(k, v)).norm());
      moved = std::max(moved, (cache.at(k, v) - cache.at(0, v)).norm());
    }
  }
  EXPECT_LT(worst, 1e-5);  // the tail is 1 long
  EXPECT_GT(moved, 0.1) << "the tail hardly moved: the check above could not fail";
}

// The first skin's joint matrices as animation `animation` poses the nodes at its key k.
std::vector<Mat4> joints_at(const tinygltf::Model& m, int animation, std::size_t k) {
  NodePoses pose = rest_poses(m);
  const tinygltf::Animation& a = m.animations[static_cast<std::size_t>(animation)];
  for (const tinygltf::AnimationChannel& ch : a.channels) {
    const std::vector<double> v = numbers(m, a.samplers[static_cast<std::size_t>(ch.sampler)].output);
    const auto n = static_cast<std::size_t>(ch.target_node);
    if (ch.target_path == "translation") pose.t[n] = Vec3(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
    if (ch.target_path == "scale") pose.s[n] = Vec3(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
    if (ch.target_path == "rotation") pose.r[n] = Quat(v[4 * k + 3], v[4 * k], v[4 * k + 1], v[4 * k + 2]);
  }
  return skin_joint_matrices(m, pose);
}

// Props in the file beside the skinned character: the rig names the character's mesh; the .glb
// keeps each on a node of its own and passes the validator. The static one is where the file
// places it, moved by no clip, with no skin or target; the one skinned to the Hip is skinned by the
// character's skin, and playing "sweep bake" moves it as the glTF creature's own Hip moves in its
// Walk (an independent skinning). The character keeps its bones and clips.
TEST(SkinnedCollada, PropsBesideTheCharacterAreKeptTheStaticStillTheSkinnedOnItsJoint) {
  const Asset asset{here("prop.dae"), here("prop.rig.json"), here("prop.bind")};
  write_creature_dae(asset.gltf, /*with_prop=*/true);
  const fs::path gltf = fs::path(SWEEP_SOURCE_DIR) / "meshes/skinned_tail.gltf";
  const assets::SkinModel model =
      *assets::read_gltf_skin(gltf, assets::read_mesh(gltf).positions, Eigen::Affine3d::Identity());
  Rig rig = rig_of({straight_sweep("tail", false)}, "prop.dae");
  rig.mesh_name = model.nodes[static_cast<std::size_t>(model.mesh_node)].name;
  io::write_rig(asset.rig, rig);
  ASSERT_EQ(
      std::system((std::string(SWEEP_BIND_EXE) + " -q '" + asset.rig.string() + "' -o '" + asset.binding.string() + "'")
                      .c_str()),
      0);
  std::string walk = kWalk;
  walk.replace(walk.find("\"Walk\""), 6, "\"Walk_Walk\"");
  const fs::path glb = here("prop.glb");
  ASSERT_EQ(run_sim(asset, walk, "-o '" + glb.string() + "'", "prop"), 0) << io::read_file(here("prop.err"));
  int code = -1;
  const std::string report = validate(glb, &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numErrors\": 0"), std::string::npos) << report;

  const tinygltf::Model out = load(glb);
  ASSERT_EQ(out.meshes.size(), 3u) << "the character's, the prop's and the saddle's";
  ASSERT_EQ(out.skins.size(), 1u);
  const std::vector<std::string> bones = {"Hip", "Tail1", "Tail2", "Tail3"};
  ASSERT_GT(out.skins[0].joints.size(), bones.size()) << "the parts' joints are added";
  for (std::size_t j = 0; j < bones.size(); ++j)
    EXPECT_EQ(out.nodes[static_cast<std::size_t>(out.skins[0].joints[j])].name, bones[j]);
  ASSERT_EQ(out.animations.size(), 3u);
  EXPECT_EQ(out.animations[0].name, "Walk_Walk");
  EXPECT_EQ(out.animations[1].name, "Walk_Blink");
  EXPECT_EQ(out.animations[2].name, "sweep bake");
  int prop = -1, named_prop = 0;
  for (std::size_t n = 0; n < out.nodes.size(); ++n) {
    named_prop += out.nodes[n].name == "Prop";
    if (out.nodes[n].name == "Prop" && out.nodes[n].mesh >= 0) prop = static_cast<int>(n);
  }
  ASSERT_GE(prop, 0) << "the prop's node, showing its mesh";
  EXPECT_EQ(named_prop, 1) << "the file's node shows it (no copy beside it)";
  const tinygltf::Node& node = out.nodes[static_cast<std::size_t>(prop)];
  EXPECT_EQ(node.skin, -1);
  EXPECT_TRUE(node.translation.empty() && node.rotation.empty() && node.matrix.empty())
      << "placed in world space: its node has no transform";
  for (const tinygltf::Animation& a : out.animations)
    for (const tinygltf::AnimationChannel& ch : a.channels) EXPECT_NE(ch.target_node, prop) << a.name;
  int roots_with_prop = 0;
  for (const int root : out.scenes[0].nodes) roots_with_prop += root == prop;
  EXPECT_EQ(roots_with_prop, 1) << "the prop is in the scene";
  const tinygltf::Primitive& p = out.meshes[static_cast<std::size_t>(node.mesh)].primitives[0];
  EXPECT_TRUE(p.targets.empty());
  EXPECT_FALSE(p.attributes.contains("JOINTS_0"));
  const std::vector<double> at = numbers(out, p.attributes.at("POSITION"));
  const std::vector<Vec3> corners = prop_corners();
  ASSERT_EQ(at.size(), 3 * corners.size());
  double worst = 0;
  for (std::size_t v = 0; v < corners.size(); ++v) {
    double best = 1e300;
    for (const Vec3& c : corners)
      best = std::min(best, (Vec3(at[3 * v], at[3 * v + 1], at[3 * v + 2]) - (c + kPropAt)).norm());
    worst = std::max(worst, best);
  }
  EXPECT_LT(worst, 1e-6) << "the prop where the file places it";

  // The saddle: skinned to the Hip, played as the glTF creature's Hip moves.
  int saddle = -1;
  for (std::size_t n = 0; n < out.nodes.size(); ++n)
    if (out.nodes[n].name == "Saddle" && out.nodes[n].mesh >= 0) saddle = static_cast<int>(n);
  ASSERT_GE(saddle, 0) << "the saddle's node, showing its mesh";
  EXPECT_EQ(out.nodes[static_cast<std::size_t>(saddle)].skin, 0);
  const tinygltf::Primitive& s =
      out.meshes[static_cast<std::size_t>(out.nodes[static_cast<std::size_t>(saddle)].mesh)].primitives[0];
  const std::vector<double> bind = numbers(out, s.attributes.at("POSITION"));
  const std::vector<double> joints = numbers(out, s.attributes.at("JOINTS_0"));
  const std::vector<double> weights = numbers(out, s.attributes.at("WEIGHTS_0"));
  ASSERT_EQ(bind.size(), 24u);
  const int hip = model.joint_of_node(model.find_node("Hip"));
  const int baked = find_animation(out, "sweep bake");
  ASSERT_GE(baked, 0);
  double worst_saddle = 0, moved = 0;
  for (const int k : {0, 6, 15, 24}) {  // (the Hip is keyed linearly, so any frame, not only a key's)
    const std::vector<Mat4> played_joints = joints_at(out, baked, static_cast<std::size_t>(k));
    const std::vector<Mat4> expected = assets::joint_matrices(
        model, assets::world_transforms(model, model.find_clip("Walk"), std::fmod(k / 30.0, 1.0)));
    for (std::size_t v = 0; v < 8; ++v) {
      const Vec3 b(bind[3 * v], bind[3 * v + 1], bind[3 * v + 2]);
      Mat4 skinning = Mat4::Zero();
      for (int e = 0; e < 4; ++e)
        skinning += weights[4 * v + e] * played_joints[static_cast<std::size_t>(joints[4 * v + e])];
      const Vec3 shown = (skinning * b.homogeneous()).head<3>();
      const Vec3 want = (expected[static_cast<std::size_t>(hip)] * b.homogeneous()).head<3>();
      worst_saddle = std::max(worst_saddle, (shown - want).norm());
      moved = std::max(moved, (want - b).norm());
    }
  }
  EXPECT_LT(worst_saddle, 1e-5) << "the saddle rides the Hip as the creature's clip moves it";
  EXPECT_GT(moved, 0.01) << "the Hip hardly moved: the check above could not fail";
}

}  // namespace
}  // namespace sweep::test
