// A skin and its clip read through assimp (FBX, Collada, ...: assimp_skin.h), on a Collada file the
// test writes: a strip along z whose lower half is skinned to a root joint and upper half to a
// joint "Tip" at z = 0.5, the row between them half to each, and a clip that turns Tip by 90°
// about z over one second (two matrix keys). Linear blend skinning then has a closed form: a vertex
// (x, 0, z) on Tip alone turns about the z axis by θ(t) = 90° · t, to (x cos θ, x sin θ, z); one
// on the root stays; the middle row goes halfway between the two.
#include "sweep/assets/assimp_skin.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "sweep/assets/gltf_skin.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/core/error.h"

namespace fs = std::filesystem;
using namespace sweep;

namespace {

constexpr int kRows = 5;  // z = 0, 0.25, 0.5, 0.75, 1; two vertices a row, x = ±0.1
double row_z(int r) {
  return 0.25 * r;
}

// `weightless_row` ≥ 0: that row's vertices get no weight (a malformed skin).
fs::path write_collada(const std::string& name, int weightless_row = -1) {
  const fs::path dir = fs::path(SWEEP_BINARY_DIR) / "tests/assets/assimp_skin" / std::to_string(::getpid());
  fs::create_directories(dir);
  const fs::path dae = dir / name;
  std::ostringstream pos, tris, vcount, v, weights;
  int weight_count = 0;
  for (int r = 0; r < kRows; ++r) {
    for (const double x : {-0.1, 0.1}) {
      pos << x << " 0 " << row_z(r) << " ";
      const int vertex_joints = r == weightless_row ? 0 : r == 2 ? 2 : 1;
      vcount << vertex_joints << " ";
      if (vertex_joints == 2) {
        v << "0 " << weight_count << " 1 " << weight_count + 1 << " ";
        weights << "0.5 0.5 ";
        weight_count += 2;
      } else if (vertex_joints == 1) {
        v << (r < 2 ? 0 : 1) << " " << weight_count << " ";
        weights << "1 ";
        weight_count += 1;
      }
    }
    if (r + 1 < kRows) {
      const int a = 2 * r;
      tris << a << " " << a + 1 << " " << a + 3 << " " << a << " " << a + 3 << " " << a + 2 << " ";
    }
  }
  const double c = std::cos(std::numbers::pi / 2), s = std::sin(std::numbers::pi / 2);
  std::ostringstream turned;  // Tip's transform at t = 1: translate (0, 0, 0.5), turn 90° about z
  turned << c << " " << -s << " 0 0 " << s << " " << c << " 0 0 0 0 1 0.5 0 0 0 1";
  std::ofstream out(dae);
  out << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries>
    <geometry id="strip-mesh" name="strip"><mesh>
      <source id="strip-positions"><float_array id="strip-positions-array" count=")"
      << 6 * kRows << R"(">)" << pos.str() << R"(</float_array>
        <technique_common><accessor source="#strip-positions-array" count=")"
      << 2 * kRows << R"(" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
      <vertices id="strip-vertices"><input semantic="POSITION" source="#strip-positions"/></vertices>
      <triangles count=")"
      << 2 * (kRows - 1) << R"("><input semantic="VERTEX" source="#strip-vertices" offset="0"/><p>)" << tris.str()
      << R"(</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_controllers>
    <controller id="skin" name="skin"><skin source="#strip-mesh">
      <bind_shape_matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</bind_shape_matrix>
      <source id="skin-joints"><Name_array id="skin-joints-array" count="2">Root Tip</Name_array>
        <technique_common><accessor source="#skin-joints-array" count="2" stride="1"><param name="JOINT" type="name"/></accessor></technique_common></source>
      <source id="skin-poses"><float_array id="skin-poses-array" count="32">1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 1 0 0 0 0 1 0 0 0 0 1 -0.5 0 0 0 1</float_array>
        <technique_common><accessor source="#skin-poses-array" count="2" stride="16"><param name="TRANSFORM" type="float4x4"/></accessor></technique_common></source>
      <source id="skin-weights"><float_array id="skin-weights-array" count=")"
      << weight_count << R"(">)" << weights.str() << R"(</float_array>
        <technique_common><accessor source="#skin-weights-array" count=")"
      << weight_count << R"(" stride="1"><param name="WEIGHT" type="float"/></accessor></technique_common></source>
      <joints><input semantic="JOINT" source="#skin-joints"/><input semantic="INV_BIND_MATRIX" source="#skin-poses"/></joints>
      <vertex_weights count=")"
      << 2 * kRows
      << R"("><input semantic="JOINT" source="#skin-joints" offset="0"/><input semantic="WEIGHT" source="#skin-weights" offset="1"/>
        <vcount>)"
      << vcount.str() << "</vcount><v>" << v.str() << R"(</v></vertex_weights>
    </skin></controller>
  </library_controllers>
  <library_animations>
    <animation id="turn" name="Turn">
      <source id="turn-time"><float_array id="turn-time-array" count="2">0 1</float_array>
        <technique_common><accessor source="#turn-time-array" count="2" stride="1"><param name="TIME" type="float"/></accessor></technique_common></source>
      <source id="turn-matrix"><float_array id="turn-matrix-array" count="32">1 0 0 0 0 1 0 0 0 0 1 0.5 0 0 0 1 )"
      << turned.str() << R"(</float_array>
        <technique_common><accessor source="#turn-matrix-array" count="2" stride="16"><param name="TRANSFORM" type="float4x4"/></accessor></technique_common></source>
      <sampler id="turn-sampler"><input semantic="INPUT" source="#turn-time"/><input semantic="OUTPUT" source="#turn-matrix"/></sampler>
      <channel source="#turn-sampler" target="Tip/transform"/>
    </animation>
  </library_animations>
  <library_visual_scenes>
    <visual_scene id="Scene" name="Scene">
      <node id="Root" name="Root" sid="Root" type="JOINT"><matrix sid="transform">1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix>
        <node id="Tip" name="Tip" sid="Tip" type="JOINT"><matrix sid="transform">1 0 0 0 0 1 0 0 0 0 1 0.5 0 0 0 1</matrix></node>
      </node>
      <node id="strip" name="strip" type="NODE"><instance_controller url="#skin"><skeleton>#Root</skeleton></instance_controller></node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";
  return dae;
}

}  // namespace

TEST(AssimpSkin, AColladaJointTurningItsHalfOfAStripSkinsToTheClosedForm) {
  const fs::path dae = write_collada("strip.dae");
  const assets::SceneMesh read = assets::read_scene_mesh(dae, "", assets::MeshPick::whole_file);
  ASSERT_EQ(read.mesh.positions.size(), static_cast<std::size_t>(2 * kRows));
  const auto model = assets::read_assimp_skin(dae, read.mesh.positions, read.to_world);
  ASSERT_TRUE(model.has_value());
  ASSERT_EQ(model->joints.size(), 2u);
  int clip = -1;
  for (std::size_t c = 0; c < model->clips.size(); ++c)
    if (!model->clips[c].channels.empty()) clip = static_cast<int>(c);
  ASSERT_GE(clip, 0) << model->clip_names();
  EXPECT_DOUBLE_EQ(model->clips[clip].end - model->clips[clip].start, 1.0);
  for (const double t : {0.0, 0.25, 0.5, 1.0}) {
    const double theta = std::numbers::pi / 2 * t;
    const auto joints = assets::joint_matrices(*model, assets::world_transforms(*model, clip, t));
    for (std::size_t v = 0; v < read.mesh.positions.size(); ++v) {
      const Vec3 p = read.mesh.positions[v];
      const Vec3 turned(p.x() * std::cos(theta), p.x() * std::sin(theta), p.z());
      const int row = static_cast<int>(std::lround(p.z() / 0.25));
      const Vec3 expected = row < 2 ? p : row > 2 ? turned : Vec3(0.5 * (p + turned));
      EXPECT_LE((assets::skin_vertex(*model, joints, v) - expected).norm(), 1e-6) << "vertex " << v << ", t = " << t;
    }
  }
}

TEST(AssimpSkin, AVertexNoBoneWeighsIsRefusedNamingTheFile) {
  const fs::path dae = write_collada("weightless.dae", 3);
  const assets::SceneMesh read = assets::read_scene_mesh(dae, "", assets::MeshPick::whole_file);
  try {
    (void)assets::read_assimp_skin(dae, read.mesh.positions, read.to_world);
    FAIL() << "a vertex with no bone weight must be refused";
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::bad_input);
    EXPECT_NE(std::string(e.what()).find("has no bone weight"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(dae.string()), std::string::npos) << e.what();
  }
}
