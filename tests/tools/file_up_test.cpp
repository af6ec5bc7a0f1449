// sweep-fit --list names parts by the file's own up axis when --up is not given. A walker (a body
// and four leg shells) modelled Z up is written by assimp's exporters as an ASCII FBX whose
// GlobalSettings are then made to say so (UpAxis 2: assimp reads it into the scene's metadata and
// leaves the coordinates as they are), and as a Collada file saying <up_axis>Z_UP</up_axis> (which
// assimp's reader applies, turning the scene to +Y up). --list must name four legs in both, say
// which axis it went by and why, and (the FBX) name them otherwise when told another axis with --up.
// A format Z up by its own convention (an .smd written here, a .3ds by assimp's exporter) is named
// by that convention, taken through the reader's own turn.
#include <assimp/material.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <assimp/Exporter.hpp>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "fit/creatures.h"
#include "sweep/assets/mesh_io.h"
#include "tool_runner.h"

namespace sweep::test {
namespace {

// `mesh` as an assimp scene of one node and one mesh, written in `format` ("fbxa", "collada").
void export_mesh(const Mesh& mesh, const fs::path& file, const char* format) {
  aiScene scene;
  scene.mRootNode = new aiNode("Walker");
  scene.mRootNode->mNumMeshes = 1;
  scene.mRootNode->mMeshes = new unsigned[1]{0};
  scene.mNumMaterials = 1;
  scene.mMaterials = new aiMaterial* [1] { new aiMaterial() };
  scene.mNumMeshes = 1;
  scene.mMeshes = new aiMesh* [1] { new aiMesh() };
  aiMesh& m = *scene.mMeshes[0];
  m.mName = "Walker";
  m.mPrimitiveTypes = aiPrimitiveType_POLYGON | aiPrimitiveType_TRIANGLE;
  m.mNumVertices = static_cast<unsigned>(mesh.vertex_count());
  m.mVertices = new aiVector3D[m.mNumVertices];
  for (unsigned v = 0; v < m.mNumVertices; ++v) {
    const Vec3& p = mesh.positions[v];
    m.mVertices[v] = aiVector3D(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  }
  m.mNumFaces = static_cast<unsigned>(mesh.face_count());
  m.mFaces = new aiFace[m.mNumFaces];
  for (unsigned f = 0; f < m.mNumFaces; ++f) {
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    m.mFaces[f].mNumIndices = end - begin;
    m.mFaces[f].mIndices = new unsigned[end - begin];
    for (std::uint32_t k = begin; k < end; ++k) m.mFaces[f].mIndices[k - begin] = mesh.face_vertices[k];
  }
  Assimp::Exporter exporter;
  ASSERT_EQ(exporter.Export(&scene, format, file.string()), aiReturn_SUCCESS) << exporter.GetErrorString();
}

// `text` with its one `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The names --list gives (and its first line), with `extra` options.
std::multiset<std::string> listed_names(const fs::path& file, const std::string& extra, const fs::path& io,
                                        std::string* first_line = nullptr) {
  const ToolRun r = run_tool(SWEEP_FIT_EXE, quoted(file) + " --list --report " + quoted(io / "parts.json") + extra, io);
  EXPECT_EQ(r.code, 0) << r.err;
  if (first_line != nullptr) *first_line = r.out.substr(0, r.out.find('\n'));
  std::multiset<std::string> names;
  const nlohmann::json report = nlohmann::json::parse(slurp(io / "parts.json"));
  for (const nlohmann::json& p : report["parts"]) {
    names.insert(p["name"].get<std::string>().substr(0, 3));
  }
  return names;
}

TEST(FileUp, ListNamesPartsByAZUpFbxOrColladaFilesOwnUpAxis) {
  const fs::path dir = scratch_dir("file-up");
  // The Y-up walker turned so that its up is +Z: (x, y, z) → (x, −z, y).
  Eigen::Matrix3d to_z_up;
  to_z_up << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  const Walker w = make_walker(2, false, to_z_up);
  const std::multiset<std::string> four_legs = {"leg", "leg", "leg", "leg"};

  export_mesh(w.mesh, dir / "exported.fbx", "fbxa");
  spit(dir / "walker.fbx", replaced(slurp(dir / "exported.fbx"), "P: \"UpAxis\", \"int\", \"Integer\", \"\", 1",
                                    "P: \"UpAxis\", \"int\", \"Integer\", \"\", 2"));
  std::string said;
  EXPECT_EQ(listed_names(dir / "walker.fbx", "", dir, &said), four_legs);
  EXPECT_EQ(said,
            "names go by up +Z (the FBX file's GlobalSettings say UpAxis 2, UpAxisSign 1; --up X|Y|Z gives another)");
  EXPECT_EQ(nlohmann::json::parse(slurp(dir / "parts.json"))["up"]["axis"], "+Z");
  EXPECT_NE(listed_names(dir / "walker.fbx", " --up Y", dir, &said), four_legs) << "the file's axis made them legs";
  EXPECT_EQ(said, "names go by up +Y (given by --up; --up X|Y|Z gives another)");

  export_mesh(w.mesh, dir / "exported.dae", "collada");
  spit(dir / "walker.dae", replaced(slurp(dir / "exported.dae"), "<up_axis>Y_UP</up_axis>", "<up_axis>Z_UP</up_axis>"));
  EXPECT_EQ(listed_names(dir / "walker.dae", "", dir, &said), four_legs);
  EXPECT_EQ(said,
            "names go by up +Y (the Collada file's <up_axis> is Z_UP, which the reader turned to +Y with the "
            "scene; --up X|Y|Z gives another)");
}

// `mesh` as a Valve .smd (Source's text format: one bone at rest, triangles fanned from each
// polygon's first corner), its coordinates as they are.
std::string smd_text(const Mesh& mesh) {
  std::string text = "version 1\nnodes\n0 \"root\" -1\nend\nskeleton\ntime 0\n0 0 0 0 0 0 0\nend\ntriangles\n";
  const auto corner = [&](std::uint32_t v) {
    const Vec3& p = mesh.positions[v];
    return "0 " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + " 0 0 1 0 0\n";
  };
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    for (std::uint32_t k = begin + 1; k + 1 < end; ++k) {
      text += "skin\n" + corner(mesh.face_vertices[begin]) + corner(mesh.face_vertices[k]) +
              corner(mesh.face_vertices[k + 1]);
    }
  }
  return text + "end\n";
}

// A format that is Z up by its convention and says nothing in the file: Source's .smd, whose
// reader keeps the coordinates as stored (+Z), and 3ds Max's .3ds, whose reader turns the scene
// to +Y up in its root node (the convention taken through that turn: +Y, not turned twice).
TEST(FileUp, AZUpFormatsConventionIsTakenThroughTheReadersOwnTurn) {
  const fs::path dir = scratch_dir("file-up-format");
  Eigen::Matrix3d to_z_up;
  to_z_up << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  const Walker w = make_walker(2, false, to_z_up);
  const std::multiset<std::string> four_legs = {"leg", "leg", "leg", "leg"};

  spit(dir / "walker.smd", smd_text(w.mesh));
  const assets::SceneMesh smd = assets::read_scene_mesh(dir / "walker.smd", "", assets::MeshPick::only_or_largest);
  EXPECT_TRUE(smd.up.stated);
  EXPECT_EQ(smd.up.direction, Vec3::UnitZ());
  std::string said;
  EXPECT_EQ(listed_names(dir / "walker.smd", "", dir, &said), four_legs);
  EXPECT_EQ(said, "names go by up +Z (Source's .smd is Z up by the engine's convention; --up X|Y|Z gives another)");
  EXPECT_NE(listed_names(dir / "walker.smd", " --up Y", dir), four_legs) << "the format's axis made them legs";

  export_mesh(w.mesh, dir / "walker.3ds", "3ds");
  const assets::SceneMesh max = assets::read_scene_mesh(dir / "walker.3ds", "", assets::MeshPick::only_or_largest);
  EXPECT_TRUE(max.up.stated);
  EXPECT_LT((max.up.direction - Vec3::UnitY()).norm(), 1e-12) << "the reader turned the scene: Z up is now +Y";
  EXPECT_EQ(listed_names(dir / "walker.3ds", "", dir, &said), four_legs);
  EXPECT_EQ(said,
            "names go by up +Y (3ds Max's .3ds is Z up by its convention, which the reader turned to +Y with the "
            "scene; --up X|Y|Z gives another)");
}

}  // namespace
}  // namespace sweep::test
