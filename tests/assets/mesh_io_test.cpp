// Mesh reading and writing: the vertex order each format keeps, exact positions per index, the
// faces, and one clear error per kind of bad file.
#include "sweep/assets/mesh_io.h"

#include <assimp/material.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <tiny_gltf.h>
#include <unistd.h>

#include <assimp/Exporter.hpp>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "fp_guard.h"
#include "sweep/core/error.h"
#include "sweep/io/atomic_file.h"
#include "sweep/io/read_file.h"

using sweep::io::read_file;

namespace sweep::assets {
namespace {

namespace fs = std::filesystem;
using Faces = std::vector<std::vector<std::uint32_t>>;

// A fresh folder per test, removed afterwards.
class MeshIo : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("sweep_test_io_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& bytes) {
    const fs::path p = dir_ / name;
    std::ofstream out(p, std::ios::binary);
    out << bytes;
    return p;
  }
  fs::path dir_;
};

Faces faces_of(const Mesh& m) {
  Faces out;
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    out.emplace_back(m.face_vertices.begin() + m.face_offsets[f], m.face_vertices.begin() + m.face_offsets[f + 1]);
  }
  return out;
}

void expect_positions(const Mesh& m, const std::vector<Vec3>& expected) {
  ASSERT_EQ(m.vertex_count(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(m.positions[i], expected[i]) << "vertex " << i;
  }
}

// What a file's number becomes in single precision (assimp's formats).
Vec3 f32(double x, double y, double z) {
  return Vec3(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
}

// Runs read_mesh expecting an Error; returns it for the caller's checks.
Error read_error(const fs::path& p) {
  try {
    read_mesh(p);
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << p << " was read without an error";
  return Error(ErrorCategory::internal, "");
}

void expect_bad(const fs::path& p, ErrorCategory category, const std::string& what) {
  const Error e = read_error(p);
  const std::string msg = e.what();
  EXPECT_EQ(e.category(), category) << msg;
  EXPECT_EQ(msg.rfind(p.string() + ": ", 0), 0u) << "message must start with the path: " << msg;
  EXPECT_NE(msg.find(what), std::string::npos) << "expected '" << what << "' in: " << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << "message must be one line: " << msg;
}

// ---- OFF ----

// The quad is listed against the vertex order, and the triangle uses the last vertex first:
//   3---2
//   |   |   4 (off the plane)
//   0---1
TEST_F(MeshIo, OffKeepsFileOrderExactlyAndPolygons) {
  const fs::path p = write("a.off",
                           "OFF\n# a comment\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                           "0.1 0.2 0.30000000000000004\n4 3 2 1 0\n3 4 0 1\n");
  const Mesh m = read_mesh(p);
  expect_positions(m, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.1, 0.2, 0.30000000000000004}});
  EXPECT_EQ(faces_of(m), (Faces{{3, 2, 1, 0}, {4, 0, 1}}));
}

TEST_F(MeshIo, OffAcceptsCountsOnTheHeaderLineColoursAndLeadingComments) {
  const fs::path p = write("c.off",
                           "# Output of a tool\n\nCOFF 4 1 0\n"
                           "1 2 3 255 0 0 255\n-4 5e-1 +6 0 255 0 255\n7 8 9 0 0 255 255\n"
                           "0 0 0 1 1 1 1\n3 2 0 1 0.5 0.5 0.5\n");
  const Mesh m = read_mesh(p);
  expect_positions(m, {{1, 2, 3}, {-4, 0.5, 6}, {7, 8, 9}, {0, 0, 0}});
  EXPECT_EQ(faces_of(m), (Faces{{2, 0, 1}}));
}

// ---- PLY (assimp, no post-processing) ----

TEST_F(MeshIo, PlyKeepsFileOrderAndPolygons) {
  const fs::path p = write("a.ply",
                           "ply\nformat ascii 1.0\ncomment test\nelement vertex 5\n"
                           "property float x\nproperty float y\nproperty float z\n"
                           "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.1 0.2 0.3\n4 3 2 1 0\n3 4 0 1\n");
  const Mesh m = read_mesh(p);
  expect_positions(m, {f32(0, 0, 0), f32(1, 0, 0), f32(1, 1, 0), f32(0, 1, 0), f32(0.1, 0.2, 0.3)});
  EXPECT_EQ(faces_of(m), (Faces{{3, 2, 1, 0}, {4, 0, 1}}));
}

TEST_F(MeshIo, PlyHeaderFreeTextIsSkippedWhereTheBodyIsChecked) {
  // Blender 2.4 wrote "Created by Blender3D ..." into the header (assimp's models/PLY/Wuson.ply); assimp
  // skips such a line. In an ASCII file the body check sees any layout a misspelt line would change.
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const std::string header =
      "ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: \nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  const Mesh m = read_mesh(write("created.ply", header + body));
  expect_positions(m, {f32(0, 0, 0), f32(1, 0, 0), f32(0, 1, 0)});
  EXPECT_EQ(faces_of(m), (Faces{{0, 1, 2}}));
  // A misspelt element line is such a line too: its property then lands in the vertex element, whose
  // lines no longer match it.
  std::string misspelt = header;
  misspelt.replace(misspelt.find("element face 1"), 14, "elemnt face 1");
  expect_bad(write("misspelt.ply", misspelt + body), ErrorCategory::bad_input,
             "line 11: vertex 0: expected a list length");
  // A binary body is not checked: there the line is refused, naming it.
  std::string binary = header;
  binary.replace(binary.find("ascii"), 5, "binary_little_endian");
  expect_bad(write("created_binary.ply", binary), ErrorCategory::bad_input,
             "line 3: unknown header line 'Created' (a binary PLY's header may hold only");
}

TEST_F(MeshIo, PlyWrittenByUsReadsBackInOrderAtSinglePrecision) {
  Mesh in;
  in.positions = {{0.1, -2.5, 3}, {1e-3, 7, -0.0}, {4, 5, 6}, {-1, -1, -1}};
  in.add_face({3, 1, 0});
  in.add_face({0, 1, 2, 3});
  const fs::path p = dir_ / "w.ply";
  write_ply(p, in);
  const Mesh m = read_mesh(p);
  ASSERT_EQ(m.vertex_count(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(m.positions[i], in.positions[i].cast<float>().cast<double>()) << i;
  }
  EXPECT_EQ(faces_of(m), faces_of(in));
}

// ---- OBJ (tinyobjloader for faces, exact `v` coordinates) ----

// Faces reference the `v` array out of order, with v/vt/vn and negative (relative) indices, in
// groups; the vertex order stays the `v` order.
TEST_F(MeshIo, ObjKeepsVArrayOrderWhenFacesReferenceOutOfOrder) {
  const fs::path p = write("a.obj",
                           "# test\nmtllib missing.mtl\nv 0 0 0\nv 1 0 0\n"
                           "vt 0 0\nvn 0 0 1\ng first\nv 1 1 0\nv 0 1 0\n"
                           "f 4/1/1 3/1/1 2/1/1 1/1/1\nv 0.1 0.2 0.30000000000000004\n"
                           "g second\nf -1 1 2\nf 5 4 3\nl 1 2\n");
  const Mesh m = read_mesh(p);
  expect_positions(m, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.1, 0.2, 0.30000000000000004}});
  EXPECT_EQ(faces_of(m), (Faces{{3, 2, 1, 0}, {4, 0, 1}, {4, 3, 2}}));
}

TEST_F(MeshIo, ObjReadsCoordinatesExactlyWhereTinyobjWouldRound) {
  // Needs all 17 digits: tinyobjloader's own parser is not correctly rounded for such values.
  const fs::path p = write("exact.obj",
                           "v 0.1 0.7000000000000001 -1.2345678901234567e-300\n"
                           "v 5e-324 1.7976931348623157e308 -0\nv 3 3 3\nf 1 2 3\n");
  const Mesh m = read_mesh(p);
  expect_positions(
      m, {{0.1, 0.7000000000000001, -1.2345678901234567e-300}, {5e-324, 1.7976931348623157e308, -0.0}, {3, 3, 3}});
}

// A UTF-8 byte order mark before the first line is not content. Each text format reads
// the same mesh with and without one (the OBJ reader used to skip the first `v`, shifting every
// face by one vertex).
TEST_F(MeshIo, ByteOrderMarkIsSkippedByEveryTextReader) {
  Mesh in;
  in.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5}, {0, 1, 0.25}};
  in.face_vertices = {0, 1, 2, 0, 2, 3};
  in.face_offsets = {0, 3, 6};
  const std::string bom = "\xEF\xBB\xBF";
  for (const auto& [name, bytes] :
       {std::pair{std::string("m.obj"), obj_bytes(in)}, std::pair{std::string("m.off"), off_bytes(in)},
        std::pair{std::string("m.ply"), ply_bytes(in)}}) {
    SCOPED_TRACE(name);
    const Mesh plain = read_mesh(write("plain-" + name, bytes));
    const Mesh marked = read_mesh(write("bom-" + name, bom + bytes));
    ASSERT_EQ(marked.vertex_count(), 4u);
    EXPECT_EQ(marked.positions, plain.positions);
    EXPECT_EQ(faces_of(marked), faces_of(plain));
    EXPECT_EQ(faces_of(marked), faces_of(in));
  }
}

// ---- glTF / glb (assimp, no post-processing), written with tinygltf ----

// One mesh with two primitives (assimp: two meshes), under a node translated by (10, 0, 0).
tinygltf::Model two_primitive_model() {
  const std::vector<float> pos0 = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0.5f};
  const std::vector<std::uint16_t> idx0 = {3, 2, 1, 1, 0, 3};
  const std::vector<float> pos1 = {2, 0, 0, 2, 1, 0.25f, 3, 0, 0};
  const std::vector<std::uint16_t> idx1 = {2, 0, 1};
  tinygltf::Model model;
  tinygltf::Buffer buffer;
  auto append = [&](const void* data, std::size_t bytes) {
    const std::size_t offset = buffer.data.size();
    const auto* b = static_cast<const unsigned char*>(data);
    buffer.data.insert(buffer.data.end(), b, b + bytes);
    while (buffer.data.size() % 4) buffer.data.push_back(0);
    return offset;
  };
  auto add_view = [&](std::size_t offset, std::size_t bytes, int target) {
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = offset;
    v.byteLength = bytes;
    v.target = target;
    model.bufferViews.push_back(v);
    return static_cast<int>(model.bufferViews.size() - 1);
  };
  auto add_accessor = [&](int view, int component, int type, std::size_t count, std::vector<double> mn,
                          std::vector<double> mx) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = component;
    a.type = type;
    a.count = count;
    a.minValues = std::move(mn);
    a.maxValues = std::move(mx);
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size() - 1);
  };
  tinygltf::Mesh mesh;
  auto add_primitive = [&](const std::vector<float>& pos, const std::vector<std::uint16_t>& idx, std::vector<double> mn,
                           std::vector<double> mx) {
    const int pv = add_view(append(pos.data(), pos.size() * 4), pos.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER);
    const int iv = add_view(append(idx.data(), idx.size() * 2), idx.size() * 2, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    tinygltf::Primitive prim;
    prim.attributes["POSITION"] =
        add_accessor(pv, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, pos.size() / 3, mn, mx);
    prim.indices = add_accessor(iv, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR, idx.size(), {}, {});
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    mesh.primitives.push_back(prim);
  };
  add_primitive(pos0, idx0, {0, 0, 0}, {1, 1, 0.5});
  add_primitive(pos1, idx1, {2, 0, 0}, {3, 1, 0.25});
  model.buffers.push_back(buffer);
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.translation = {10, 0, 0};
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  model.asset.version = "2.0";
  return model;
}

void check_two_primitive_mesh(const Mesh& m) {
  // Primitive order, then each primitive's accessor order; the node's translation applied.
  expect_positions(m, {{10, 0, 0},
                       {11, 0, 0},
                       {11, 1, 0},
                       {10, 1, 0.5},  // primitive 0
                       {12, 0, 0},
                       {12, 1, 0.25},
                       {13, 0, 0}});  // primitive 1
  EXPECT_EQ(faces_of(m), (Faces{{3, 2, 1}, {1, 0, 3}, {6, 4, 5}}));
}

TEST_F(MeshIo, GltfAndGlbKeepAccessorOrderAndConcatenatePrimitivesInOrder) {
  tinygltf::Model model = two_primitive_model();
  tinygltf::TinyGLTF writer;
  const fs::path gltf = dir_ / "a.gltf", glb = dir_ / "a.GLB";
  ASSERT_TRUE(writer.WriteGltfSceneToFile(&model, gltf.string(), true, true, true, false));
  ASSERT_TRUE(writer.WriteGltfSceneToFile(&model, glb.string(), true, true, false, true));
  check_two_primitive_mesh(read_mesh(gltf));
  check_two_primitive_mesh(read_mesh(glb));
}

// ---- STL and FBX: welded by exact position, in first-use order ----
// Rule (mesh_io.h): walk the faces in file order and each face's corners in order; a position not
// seen before gets the next index. So the expected order below is read straight off the corners.

//  corners: (0,0,0) (1,0,0) (1,1,0) | (0,0,0) (1,1,0) (0,1,0) | (1,1,0) (1,0,0) (2,0.5,-0)
//  indices:    0       1       2    |    0       2       3    |    2       1       4
const std::vector<std::array<float, 9>> kStlTriangles = {
    {0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 0, 1, 1, 0, 0, 1, 0}, {1, 1, 0, 1, 0, 0, 2, 0.5f, -0.0f}};
const std::vector<Vec3> kStlWelded = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0.5, 0}};
const Faces kStlFaces = {{0, 1, 2}, {0, 2, 3}, {2, 1, 4}};

TEST_F(MeshIo, AsciiStlIsWeldedInFirstUseOrder) {
  std::ostringstream s;
  s << "solid test\n";
  for (const auto& t : kStlTriangles) {
    s << "facet normal 0 0 1\nouter loop\n";
    for (int c = 0; c < 3; ++c) s << "vertex " << t[3 * c] << ' ' << t[3 * c + 1] << ' ' << t[3 * c + 2] << '\n';
    s << "endloop\nendfacet\n";
  }
  s << "endsolid test\n";
  const Mesh m = read_mesh(write("a.stl", s.str()));
  expect_positions(m, kStlWelded);
  EXPECT_EQ(faces_of(m), kStlFaces);
}

TEST_F(MeshIo, BinaryStlIsWeldedInFirstUseOrder) {
  std::string bytes(80, ' ');
  auto put = [&](const void* p, std::size_t n) { bytes.append(static_cast<const char*>(p), n); };
  const auto count = static_cast<std::uint32_t>(kStlTriangles.size());
  put(&count, 4);
  for (const auto& t : kStlTriangles) {
    const float normal[3] = {0, 0, 1};
    const std::uint16_t attributes = 0;
    put(normal, 12);
    put(t.data(), 36);
    put(&attributes, 2);
  }
  const Mesh m = read_mesh(write("b.stl", bytes));
  expect_positions(m, kStlWelded);
  EXPECT_EQ(faces_of(m), kStlFaces);
}

// An assimp scene: one child node per mesh, each with its own transform.
struct SceneMesh {
  std::vector<aiVector3D> vertices;
  Faces faces;
  aiMatrix4x4 transform;
};
std::unique_ptr<aiScene> make_scene(const std::vector<SceneMesh>& meshes) {
  auto scene = std::make_unique<aiScene>();
  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial* [1] { new aiMaterial() };
  scene->mNumMeshes = static_cast<unsigned>(meshes.size());
  scene->mMeshes = new aiMesh*[meshes.size()];
  scene->mRootNode = new aiNode("root");
  scene->mRootNode->mNumChildren = scene->mNumMeshes;
  scene->mRootNode->mChildren = new aiNode*[meshes.size()];
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    auto* m = new aiMesh();
    m->mMaterialIndex = 0;
    m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON;
    m->mNumVertices = static_cast<unsigned>(meshes[i].vertices.size());
    m->mVertices = new aiVector3D[m->mNumVertices];
    std::copy(meshes[i].vertices.begin(), meshes[i].vertices.end(), m->mVertices);
    m->mNumFaces = static_cast<unsigned>(meshes[i].faces.size());
    m->mFaces = new aiFace[m->mNumFaces];
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const auto& src = meshes[i].faces[f];
      m->mFaces[f].mNumIndices = static_cast<unsigned>(src.size());
      m->mFaces[f].mIndices = new unsigned[src.size()];
      std::copy(src.begin(), src.end(), m->mFaces[f].mIndices);
    }
    m->mName = "mesh" + std::to_string(i);
    scene->mMeshes[i] = m;
    auto* node = new aiNode("node" + std::to_string(i));
    node->mParent = scene->mRootNode;
    node->mTransformation = meshes[i].transform;
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{static_cast<unsigned>(i)};
    scene->mRootNode->mChildren[i] = node;
  }
  return scene;
}

// Two meshes: a quad + triangle stored with shared vertices listed in an order that first use does
// not follow, and a triangle under a node translated by (0, 0, 8) and scaled by 2.
TEST_F(MeshIo, FbxIsWeldedInFirstUseOrderPerMeshWithNodeTransformsBaked) {
  aiMatrix4x4 moved;
  aiMatrix4x4::Translation(aiVector3D(0, 0, 8), moved);
  aiMatrix4x4 scaled;
  aiMatrix4x4::Scaling(aiVector3D(2, 2, 2), scaled);
  const auto scene = make_scene({
      {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 1}}, {{3, 2, 1, 0}, {4, 0, 1}}, {}},
      {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{2, 0, 1}}, moved * scaled},
  });
  const fs::path p = dir_ / "a.fbx";
  {
    Assimp::Exporter exporter;
    ASSERT_EQ(exporter.Export(scene.get(), "fbxa", p.string()), aiReturn_SUCCESS) << exporter.GetErrorString();
  }
  const Mesh m = read_mesh(p);
  // Mesh 0, first use: (0,1,0) (1,1,0) (1,0,0) (0,0,0) | (0.5,0.5,1) (0,0,0)* (1,0,0)*
  // Mesh 1 (welded separately, so (0,0,8) is new even though mesh 0 has nothing there):
  //   (0,2,8) (0,0,8) (2,0,8)
  expect_positions(m, {{0, 1, 0}, {1, 1, 0}, {1, 0, 0}, {0, 0, 0}, {0.5, 0.5, 1}, {0, 2, 8}, {0, 0, 8}, {2, 0, 8}});
  EXPECT_EQ(faces_of(m), (Faces{{0, 1, 2, 3}, {4, 3, 2}, {5, 6, 7}}));
}

// ---- Write then read ----

TEST_F(MeshIo, WriteObjThenReadIsExact) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Mesh in;
  in.positions = {{0.1, 0.2, 0.3},
                  {-0.0, 5e-324, std::numeric_limits<double>::max()},
                  {std::numeric_limits<double>::min(), -1e300, 1.0 / 3.0},
                  {123456789.123456789, -7, 2.5e-8}};
  for (int i = 0; i < 200; ++i) {
    in.positions.emplace_back(uniform(rng), uniform(rng) * 1e5, std::ldexp(uniform(rng), i - 100));
  }
  for (std::uint32_t i = 0; i + 3 < in.positions.size(); i += 3) in.add_face({i + 3, i, i + 1});
  in.add_face({0, 1, 2, 3});
  in.add_face({203, 100, 7, 50, 1});
  const fs::path p = dir_ / "rt.obj";
  write_obj(p, in);
  const Mesh m = read_mesh(p);
  ASSERT_EQ(m.vertex_count(), in.vertex_count());
  for (std::size_t i = 0; i < in.vertex_count(); ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(std::bit_cast<std::uint64_t>(m.positions[i][k]), std::bit_cast<std::uint64_t>(in.positions[i][k]))
          << "vertex " << i << " coordinate " << k;
    }
  }
  EXPECT_EQ(m.face_offsets, in.face_offsets);
  EXPECT_EQ(m.face_vertices, in.face_vertices);
  // Same mesh, same bytes.
  write_obj(dir_ / "rt2.obj", m);
  EXPECT_EQ(read_file(p), read_file(dir_ / "rt2.obj"));
}

TEST_F(MeshIo, WriteOffThenReadIsExact) {
  Mesh in;
  in.positions = {{0.1, 0.7000000000000001, -0.0}, {1e-300, 2, 3}, {4, 5, 6.02214076e23}, {1, 1, 1}};
  in.add_face({0, 1, 2, 3});
  in.add_face({3, 2, 1});
  const fs::path p = dir_ / "rt.off";
  write_off(p, in);
  const Mesh m = read_mesh(p);
  expect_positions(m, in.positions);
  EXPECT_EQ(faces_of(m), faces_of(in));
}

TEST_F(MeshIo, ObjBytesAreExactlyAsDocumented) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 0.1, -0.0}};
  m.add_face({0, 1, 2});
  EXPECT_EQ(obj_bytes(m), "# sweep mesh 1: 3 vertices, 1 faces\nv 0 0 0\nv 1 0 0\nv 0.5 0.1 -0\nf 1 2 3\n");
  EXPECT_EQ(off_bytes(m), "OFF\n# sweep mesh 1\n3 1 0\n0 0 0\n1 0 0\n0.5 0.1 -0\n3 0 1 2\n");
}

TEST_F(MeshIo, WritersRefuseNonFiniteAndLeaveNoFile) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.add_face({0, 1, 2});
  {
    test::FpTrapsOff traps_off;
    m.positions[2].x() = std::numeric_limits<double>::quiet_NaN();
  }
  for (const char* name : {"n.obj", "n.off", "n.ply"}) {
    const fs::path p = dir_ / name;
    try {
      write_mesh(p, m);
      ADD_FAILURE() << name << " was written";
    } catch (const Error& e) {
      EXPECT_EQ(e.category(), ErrorCategory::output);
      EXPECT_NE(std::string(e.what()).find("vertex 2"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(p));
  }
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(MeshIo, WriteMeshRejectsUnknownExtension) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.add_face({0, 1, 2});
  try {
    write_mesh(dir_ / "a.stl", m);
    FAIL() << "written";
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::unsupported);
  }
}

// ---- Bad input ----

TEST_F(MeshIo, MissingFile) {
  expect_bad(dir_ / "nothing.obj", ErrorCategory::bad_input, "no such file");
}

TEST_F(MeshIo, DirectoryIsNotAFile) {
  fs::create_directory(dir_ / "d.off");
  expect_bad(dir_ / "d.off", ErrorCategory::bad_input, "is a directory");
}

TEST_F(MeshIo, EmptyFileInEveryFormat) {
  for (const char* name : {"e.off", "e.obj", "e.ply", "e.stl", "e.glb", "e.fbx"}) {
    expect_bad(write(name, ""), ErrorCategory::bad_input, "empty file");
  }
}

TEST_F(MeshIo, GarbageBytes) {
  std::string garbage;
  std::mt19937 rng(7);
  for (int i = 0; i < 600; ++i) garbage += static_cast<char>(rng() % 256);
  garbage[0] = 'Z';  // no accidental magic number
  expect_bad(write("g.off", garbage), ErrorCategory::bad_input, "not an OFF file");
  expect_bad(write("g.ply", garbage), ErrorCategory::bad_input, "line 1: not a PLY file");
  expect_bad(write("g.glb", garbage), ErrorCategory::bad_input, "cannot parse: ");
  expect_bad(write("g.gltf", garbage), ErrorCategory::bad_input, "cannot parse: ");
  expect_bad(write("g.fbx", garbage), ErrorCategory::bad_input, "cannot parse: ");
  // Garbage with no `v` line is, to an OBJ reader, a file with nothing in it.
  std::string no_v = garbage;
  for (char& c : no_v)
    if (c == 'v' || c == '\n') c = 'x';
  expect_bad(write("g.obj", no_v), ErrorCategory::bad_input, "no vertices");
}

TEST_F(MeshIo, NanCoordinateInOffNamesTheVertex) {
  test::FpTrapsOff traps_off;
  expect_bad(write("nan.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 nan 0\n0 1 0\n4 0 1 2 3\n"), ErrorCategory::bad_input,
             "line 5: vertex 2 has a non-finite coordinate (1, nan, 0)");
  expect_bad(write("inf.off", "OFF\n3 1 0\n0 0 0\n1e999 0 0\n0 1 0\n3 0 1 2\n"), ErrorCategory::bad_input,
             "vertex 1 has a non-finite coordinate (inf, 0, 0)");
}

TEST_F(MeshIo, NanCoordinateInObjNamesTheVertex) {
  test::FpTrapsOff traps_off;
  expect_bad(write("nan.obj", "v 0 0 0\nv 1 0 0\n# c\nv 0 -nan 0\nf 1 2 3\n"), ErrorCategory::bad_input,
             "line 4: vertex 2 has a non-finite coordinate (0, -nan, 0)");
  expect_bad(write("inf.obj", "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n"), ErrorCategory::bad_input,
             "vertex 1 has a non-finite coordinate (inf, 0, 0)");
}

TEST_F(MeshIo, NanCoordinateInPlyNamesTheVertex) {
  test::FpTrapsOff traps_off;
  expect_bad(write("nan.ply",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                   "end_header\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n"),
             ErrorCategory::bad_input, "vertex 2 has a non-finite coordinate");
}

TEST_F(MeshIo, NonNumericCoordinate) {
  expect_bad(write("abc.off", "OFF\n3 1 0\n0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n"), ErrorCategory::bad_input,
             "line 4: vertex 1: 'abc' is not a number");
  expect_bad(write("abc.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n"), ErrorCategory::bad_input,
             "line 2: vertex 1: expected 3 coordinates");
  // One leading '+' is a sign; a sign after it is not.
  expect_bad(write("pm.off", "OFF\n3 1 0\n0 0 0\n1 +-5 0\n0 1 0\n3 0 1 2\n"), ErrorCategory::bad_input,
             "line 4: vertex 1: '+-5' is not a number");
  expect_bad(write("pp.off", "OFF\n3 1 0\n0 0 0\n1 ++5 0\n0 1 0\n3 0 1 2\n"), ErrorCategory::bad_input,
             "line 4: vertex 1: '++5' is not a number");
  expect_bad(write("p.off", "OFF\n3 1 0\n0 0 0\n1 + 0\n0 1 0\n3 0 1 2\n"), ErrorCategory::bad_input,
             "line 4: vertex 1: '+' is not a number");
  const Mesh plus = read_mesh(write("plus.off", "OFF\n3 1 0\n+0 0 0\n+1.5 0 0\n0 +.5 0\n3 0 1 2\n"));
  EXPECT_EQ(plus.positions[1], Vec3(1.5, 0, 0));
  EXPECT_EQ(plus.positions[2], Vec3(0, 0.5, 0));
}

TEST_F(MeshIo, PlyValuesMustFitTheirTypes) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property int z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  // assimp would read 0.5 in an int property as 0, and a coordinate past the float range as
  // some finite value: both refused, naming the line.
  expect_bad(write("frac.ply", header + "0 0 0\n1 0 0\n0 1 0.5\n3 0 1 2\n"), ErrorCategory::bad_input,
             "line 12: vertex 2: '0.5' is not a whole number");
  expect_bad(write("huge.ply", header + "0 0 0\n1 1e39 0\n0 1 0\n3 0 1 2\n"), ErrorCategory::bad_input,
             "line 11: vertex 1: '1e39' is not a number within the range");
  std::string uchar_items = header;
  uchar_items.replace(uchar_items.find("uchar int"), 9, "uchar uchar");
  expect_bad(write("uchar.ply", uchar_items + "0 0 0\n1 0 0\n0 1 0\n3 0 1 256\n"), ErrorCategory::bad_input,
             "line 13: face 0: '256' is not a whole number");
  expect_bad(write("digits.ply", header + "0 0 0\n1 020000000000000000000000 0\n0 1 0\n3 0 1 2\n"),
             ErrorCategory::bad_input, "line 11: vertex 1: '020000000000000000000000' is not a number");
  // A vertical tab is a blank to some readers and part of a number to assimp: refused.
  expect_bad(write("vtab.ply", header + "0 0 0\n1\v 0 0\n0 1 0\n3 0 1 2\n"), ErrorCategory::bad_input,
             "line 11: a control character (byte 11)");
  // Names must be plain (assimp reads "4vertex" partly as a count), and a vertex element present.
  std::string odd_name = header;
  odd_name.replace(odd_name.find("vertex 3"), 8, "4vertex 3");
  expect_bad(write("name.ply", odd_name + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), ErrorCategory::bad_input,
             "line 3: element name '4vertex' is not a plain name");
  expect_bad(write("novertex.ply", "ply\nformat ascii 1.0\nelement point 1\nproperty float x\nend_header\n0\n"),
             ErrorCategory::bad_input, "the header has no vertex element");
  std::string blank_line = header;
  blank_line.replace(blank_line.find("property float y\n"), 17, "property float y\n\n");
  expect_bad(write("blank.ply", blank_line + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), ErrorCategory::bad_input,
             "line 6: a blank line in the header");
  // An element or a property named twice: readers differ in which one they keep.
  std::string twice = header;
  twice.replace(twice.find("element vertex 3"), 16,
                "element vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement vertex 3");
  expect_bad(write("twice.ply", twice + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), ErrorCategory::bad_input,
             "line 7: a second element 'vertex' (the first is on line 3)");
  std::string prop_twice = header;
  prop_twice.replace(prop_twice.find("property int z"), 14, "property int z\nproperty float x");
  expect_bad(write("prop_twice.ply", prop_twice + "0 0 0 0\n1 0 0 0\n0 1 0 0\n3 0 1 2\n"), ErrorCategory::bad_input,
             "line 7: a second property 'x' in element 'vertex'");
  const Mesh ok = read_mesh(write("ok.ply", header + "0 0 0\n1 0 0\n0 1 -7\n3 0 1 2\n"));
  EXPECT_EQ(ok.positions[2], Vec3(0, 1, -7));
}

TEST_F(MeshIo, GltfWithAByteOrderMarkIsRefusedWithTheReason) {
  // glTF's JSON is UTF-8 without a BOM; assimp would say only "no suitable reader".
  expect_bad(write("bom.gltf", "\xEF\xBB\xBF{\"asset\": {\"version\": \"2.0\"}}"), ErrorCategory::bad_input,
             "starts with a UTF-8 byte order mark, which glTF does not allow");
}

TEST_F(MeshIo, FaceIndexOutOfRangeNamesTheFace) {
  expect_bad(write("oor.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n4 3 2 1 7\n"), ErrorCategory::bad_input,
             "line 8: face 1 uses vertex 7, out of range (the mesh has 4 vertices)");
  expect_bad(write("oor.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\nf 1 2 9\n"), ErrorCategory::bad_input,
             "face 1 uses vertex 9 (1-based, as in the file), out of range");
  expect_bad(write("neg.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 -7\n"), ErrorCategory::bad_input,
             "face 0 uses vertex -3 (1-based, as in the file), out of range");
  expect_bad(write("oor.ply",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
                   "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 2 1 3\n"),
             ErrorCategory::bad_input, "face 1 uses vertex 3");
}

TEST_F(MeshIo, NoFaces) {
  expect_bad(write("nof.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"), ErrorCategory::bad_input, "no faces");
  expect_bad(write("nof.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), ErrorCategory::bad_input, "no faces");
}

TEST_F(MeshIo, TruncatedOffAndShortFaces) {
  expect_bad(write("t.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n"), ErrorCategory::bad_input,
             "the header announces 4 vertices, the file has 3");
  expect_bad(write("tf.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n"), ErrorCategory::bad_input,
             "the header announces 2 faces, the file has 1");
  expect_bad(write("f2.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n1 1 0\n2 0 1\n"), ErrorCategory::bad_input,
             "face 0 has 2 vertices (a face needs at least 3)");
  expect_bad(write("fi.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n1 1 0\n4 0 1 2\n"), ErrorCategory::bad_input,
             "face 0: expected 4 vertex indices, found 3");
  // A count that overflows n + 1 once read the indices past the end of the line.
  expect_bad(write("huge.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n1 1 0\n18446744073709551615 0 1 2\n"),
             ErrorCategory::bad_input, "face 0: expected 18446744073709551615 vertex indices, found 3");
}

TEST_F(MeshIo, UnknownExtensionIsUnsupported) {
  expect_bad(write("a.xyz123", "whatever"), ErrorCategory::unsupported, "unsupported mesh format '.xyz123'");
  expect_bad(write("noext", "whatever"), ErrorCategory::unsupported, "no file extension");
  expect_bad(write("b.off", "OFF BINARY\n"), ErrorCategory::unsupported, "binary OFF");
  expect_bad(write("c.off", "4OFF\n1 1 0\n0 0 0 1\n"), ErrorCategory::unsupported, "4OFF");
}

TEST(ValidateMesh, NamesTheFaultAndTheSource) {
  Mesh m;
  auto message = [&] {
    try {
      validate_mesh(m, "src");
    } catch (const Error& e) {
      EXPECT_EQ(e.category(), ErrorCategory::bad_input);
      return std::string(e.what());
    }
    return std::string("(valid)");
  };
  EXPECT_EQ(message(), "src: no vertices");
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_EQ(message(), "src: no faces");
  m.add_face({0, 1, 2});
  EXPECT_EQ(message(), "(valid)");
  m.add_face({0, 1});
  EXPECT_EQ(message(), "src: face 1 has 2 vertices (a face needs at least 3)");
  m = Mesh{};
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.add_face({0, 1, 2});
  m.add_face({2, 1, 3});
  EXPECT_EQ(message(), "src: face 1 uses vertex 3, out of range (the mesh has 3 vertices)");
  m.face_vertices.back() = 0;
  {
    test::FpTrapsOff traps_off;
    m.positions[1].y() = -std::numeric_limits<double>::infinity();
  }
  EXPECT_EQ(message(), "src: vertex 1 has a non-finite coordinate (1, -inf, 0)");
  m.positions[1].y() = 0;
  m.face_offsets.back() = 99;
  EXPECT_EQ(message(), "src: malformed face table");
}

// ---- CGAL's sample meshes (meshes/cgal/, unpacked by tools/setup-deps.sh) ----

const fs::path kCgal = fs::path(SWEEP_SOURCE_DIR) / "meshes" / "cgal";

Vec3 parse_line(const std::string& line) {
  std::istringstream in(line);
  std::string tok[3];
  in >> tok[0] >> tok[1] >> tok[2];
  Vec3 p;
  for (int k = 0; k < 3; ++k) std::from_chars(tok[k].data(), tok[k].data() + tok[k].size(), p[k]);
  return p;
}

TEST(CgalMeshes, DiplodocusKeepsAll23982VerticesInFileOrder) {
  const fs::path p = kCgal / "diplodocus.off";
  if (!fs::exists(p)) GTEST_SKIP() << p << " missing: run tools/setup-deps.sh";
  const Mesh m = read_mesh(p);
  ASSERT_EQ(m.vertex_count(), 23982u);
  EXPECT_EQ(m.face_count(), 47960u);
  // The file: "OFF", the counts, a blank line, then one vertex per line.
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::size_t first = 2;
  while (lines[first].find_first_not_of(" \t\r") == std::string::npos) ++first;
  EXPECT_EQ(m.positions.front(), parse_line(lines[first])) << lines[first];
  EXPECT_EQ(m.positions.back(), parse_line(lines[first + 23981])) << lines[first + 23981];
  EXPECT_EQ(lines[first], "0.158384 -0.136391 0.170302");
}

// Every sample mesh either loads with the vertex count its header announces (OFF), or fails with a
// sweep::Error: never a crash, never another exception.
TEST(CgalMeshes, EveryOffLoadsOrFailsCleanly) {
  if (!fs::exists(kCgal)) GTEST_SKIP() << kCgal << " missing: run tools/setup-deps.sh";
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(kCgal)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  int loaded = 0, failed = 0;
  for (const fs::path& p : files) {
    try {
      const Mesh m = read_mesh(p);
      ++loaded;
      if (p.extension() == ".off") {
        const std::string text = read_file(p);
        // Counts are the first non-comment numbers after the keyword.
        std::istringstream in(text);
        std::string tok;
        std::size_t nv = 0;
        while (in >> tok) {
          if (tok[0] == '#') {
            std::getline(in, tok);
            continue;
          }
          if (tok.find("OFF") != std::string::npos) continue;
          nv = std::stoul(tok);
          break;
        }
        EXPECT_EQ(m.vertex_count(), nv) << p;
      }
    } catch (const Error& e) {
      ++failed;
      std::cout << "  " << e.what() << "\n";
    }
  }
  std::cout << "  loaded " << loaded << ", refused " << failed << " of " << files.size() << "\n";
  EXPECT_GT(loaded, 100);
}

}  // namespace
}  // namespace sweep::assets
