#pragma once
// What the skinned .glb tests share (skinned_glb_test.cpp, skinned_joints_test.cpp): the creature
// asset written from meshes/skinned_tail.gltf with a textured material, UV sets, normals and
// extras; running sweep-bind and sweep-sim on it; reading the .glb back with tinygltf and playing
// it as an engine does; the .pc2; the Khronos validator.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bind/support.h"
#include "pc2_reader.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/io/binding_file.h"
#include "sweep/io/read_file.h"
#include "sweep/io/rig_json.h"

namespace sweep::test::skinned_glb {

using Json = nlohmann::json;
using Mat4 = Eigen::Matrix4d;

// A folder for the test process: ctest runs this file's tests as parallel processes, each writing
// the same asset and bake, and one rewriting a file another reads tears it. Within a process the
// tests share the folder (and the one bake they make).
inline fs::path here(const std::string& name) {
  static const std::string process_folder = [] {
    const testing::TestInfo* test = testing::UnitTest::GetInstance()->current_test_info();
    return test != nullptr ? std::string(test->name()) : std::string("shared");
  }();
  const fs::path dir = fs::path(SWEEP_BINARY_DIR) / "tests/assets/skinned_glb" / process_folder;
  fs::create_directories(dir);
  return dir / name;
}

// A 2 × 2 RGB PNG.
inline std::string tiny_png() {
  static const char bytes[] =
      "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x02\x00\x00\x00\x02"
      "\x08\x02\x00\x00\x00\xfd\xd4\x9a\x73\x00\x00\x00\x14\x49\x44\x41\x54\x78\x9c\x63\xf8\xcf\xc0\xc0"
      "\x00\xc2\x0c\xff\xff\xff\x67\x00\x00\x1e\xef\x04\xfc\xa3\xc8\xb4\xf7\x00\x00\x00\x00\x49\x45\x4e"
      "\x44\xae\x42\x60\x82";
  return std::string(bytes, sizeof bytes - 1);
}

// The creature with what an artist's asset carries: a textured material (the PNG a file beside
// it), TEXCOORD_0, TEXCOORD_1 and NORMAL (a second buffer, a file), extras on a joint and on the
// asset.
// `edit` changes the document further.
inline void write_asset(const fs::path& gltf, const std::function<void(Json&)>& edit = {}) {
  const fs::path fixture = fs::path(SWEEP_SOURCE_DIR) / "meshes/skinned_tail.gltf";
  Json doc = Json::parse(io::read_file(fixture));
  const std::size_t count = doc["accessors"][0]["count"];
  std::vector<float> uv, normals;
  for (const Vec3& p : assets::read_mesh(fixture).positions) {  // its node is at the origin: POSITION as read
    uv.push_back(static_cast<float>(0.5 + p.x()));
    uv.push_back(static_cast<float>(0.6 - p.z() / 1.6));
    // The tube's radial normals, the caps' axial ones, the box's corners' diagonals.
    const Vec3 n = p.z() < -0.01                     ? Vec3(p - Vec3(0, 0, -0.325)).normalized()
                   : std::hypot(p.x(), p.y()) > 0.05 ? Vec3(p.x(), p.y(), 0).normalized()
                                                     : Vec3(0, 0, p.z() > 0.5 ? 1 : -1);
    normals.insert(normals.end(), {static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())});
  }
  EXPECT_EQ(uv.size(), 2 * count);
  std::ofstream bin(gltf.parent_path() / "uv.bin", std::ios::binary);
  bin.write(reinterpret_cast<const char*>(uv.data()), 4 * uv.size());
  bin.write(reinterpret_cast<const char*>(normals.data()), 4 * normals.size());
  bin.close();
  std::ofstream(gltf.parent_path() / "hide.png", std::ios::binary) << tiny_png();
  doc["buffers"].push_back({{"uri", "uv.bin"}, {"byteLength", 4 * (uv.size() + normals.size())}});
  doc["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 0}, {"byteLength", 4 * uv.size()}, {"byteStride", 8}});
  const std::size_t view = doc["bufferViews"].size() - 1;
  for (int set = 0; set < 2; ++set) {
    doc["accessors"].push_back({{"bufferView", view}, {"componentType", 5126}, {"count", count}, {"type", "VEC2"}});
    doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_" + std::to_string(set)] = doc["accessors"].size() - 1;
  }
  doc["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 4 * uv.size()}, {"byteLength", 4 * normals.size()}});
  doc["accessors"].push_back(
      {{"bufferView", doc["bufferViews"].size() - 1}, {"componentType", 5126}, {"count", count}, {"type", "VEC3"}});
  doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = doc["accessors"].size() - 1;
  doc["images"] = {{{"name", "hide"}, {"uri", "hide.png"}}};
  doc["samplers"] = {{{"magFilter", 9729}, {"minFilter", 9729}}};
  doc["textures"] = {{{"name", "hide texture"}, {"sampler", 0}, {"source", 0}}};
  doc["materials"] = {
      {{"name", "Hide"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 1}}}}}}};
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  doc["nodes"][4]["extras"] = {{"bone", "tail tip"}};
  doc["asset"]["extras"] = {{"author", "test"}};
  if (edit) edit(doc);
  std::ofstream(gltf) << doc.dump(1);
}

struct Asset {
  fs::path gltf, rig, binding;
};

// Which vertices the tail binds.
inline std::vector<char> part_vertices(const Asset& s) {
  const Rig rig = io::read_rig(s.rig);
  const Mesh mesh = assets::read_mesh(s.gltf);
  const bind::Binding binding = io::load_binding(s.binding, mesh, rig);
  std::vector<char> in(mesh.vertex_count(), 0);
  for (const auto& table : binding.sweeps)
    for (const std::uint32_t v : table.vertices) in[v] = 1;
  return in;
}

inline Asset setup(const std::string& name, const std::function<void(Json&)>& edit = {}) {
  Asset s{here(name + ".gltf"), here(name + ".rig.json"), here(name + ".bind")};
  write_asset(s.gltf, edit);
  io::write_rig(s.rig, rig_of({straight_sweep("tail", false)}, s.gltf.filename().string()));
  EXPECT_EQ(std::system(
                (std::string(SWEEP_BIND_EXE) + " -q '" + s.rig.string() + "' -o '" + s.binding.string() + "'").c_str()),
            0);
  return s;
}

inline int run_sim(const Asset& s, const std::string& scene_json, const std::string& outputs, const std::string& name,
                   const std::string& extra = "") {
  const fs::path scene = here(name + ".scene.json");
  std::ofstream(scene) << scene_json;
  const std::string cmd = std::string(SWEEP_SIM_EXE) + " -q '" + s.rig.string() + "' --scene '" + scene.string() +
                          "' -b '" + s.binding.string() + "' " + outputs + " " + extra + " 2> '" +
                          here(name + ".err").string() + "'";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline bool no_images(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                      void*) {
  return true;  // the bytes are compared as they are; nothing here needs the pixels
}

inline tinygltf::Model load(const fs::path& path) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(no_images, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = path.extension() == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                                             : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
  EXPECT_TRUE(ok) << err;
  return model;
}

inline double component(const unsigned char* at, int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, at, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return *at;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t v;
      std::memcpy(&v, at, 2);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      std::uint32_t v;
      std::memcpy(&v, at, 4);
      return v;
    }
    default:
      ADD_FAILURE() << "component type " << type;
      return 0;
  }
}

// An accessor's numbers, dense or sparse (glTF 2.0 "Sparse accessors": zeros where no view).
inline std::vector<double> numbers(const tinygltf::Model& m, int index) {
  const tinygltf::Accessor& a = m.accessors.at(static_cast<std::size_t>(index));
  const int width = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  std::vector<double> out(a.count * static_cast<std::size_t>(width), 0.0);
  auto base = [&](int view, std::size_t offset) {
    const tinygltf::BufferView& v = m.bufferViews.at(static_cast<std::size_t>(view));
    return m.buffers.at(static_cast<std::size_t>(v.buffer)).data.data() + v.byteOffset + offset;
  };
  if (a.bufferView >= 0) {
    const int stride = a.ByteStride(m.bufferViews[static_cast<std::size_t>(a.bufferView)]);
    const unsigned char* at = base(a.bufferView, a.byteOffset);
    for (std::size_t i = 0; i < a.count; ++i)
      for (int c = 0; c < width; ++c) out[i * width + c] = component(at + i * stride + c * size, a.componentType);
  }
  if (a.sparse.isSparse) {
    const unsigned char* indices =
        base(a.sparse.indices.bufferView, static_cast<std::size_t>(a.sparse.indices.byteOffset));
    const unsigned char* values =
        base(a.sparse.values.bufferView, static_cast<std::size_t>(a.sparse.values.byteOffset));
    const int index_size =
        tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.sparse.indices.componentType));
    for (int k = 0; k < a.sparse.count; ++k) {
      const auto i = static_cast<std::size_t>(component(indices + k * index_size, a.sparse.indices.componentType));
      for (int c = 0; c < width; ++c) out[i * width + c] = component(values + (k * width + c) * size, a.componentType);
    }
  }
  return out;
}

inline int find_animation(const tinygltf::Model& m, const std::string& name) {
  for (std::size_t a = 0; a < m.animations.size(); ++a)
    if (m.animations[a].name == name) return static_cast<int>(a);
  return -1;
}

// Every node's rest translation, rotation and scale (the file's, or glTF's defaults).
struct NodePoses {
  std::vector<Vec3> t, s;
  std::vector<Quat> r;
};
inline NodePoses rest_poses(const tinygltf::Model& m) {
  const std::size_t nodes = m.nodes.size();
  NodePoses p{std::vector<Vec3>(nodes, Vec3::Zero()), std::vector<Vec3>(nodes, Vec3::Ones()),
              std::vector<Quat>(nodes, Quat::Identity())};
  for (std::size_t n = 0; n < nodes; ++n) {
    const tinygltf::Node& node = m.nodes[n];
    if (node.translation.size() == 3) p.t[n] = Vec3(node.translation[0], node.translation[1], node.translation[2]);
    if (node.rotation.size() == 4)
      p.r[n] = Quat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
    if (node.scale.size() == 3) p.s[n] = Vec3(node.scale[0], node.scale[1], node.scale[2]);
  }
  return p;
}
// The first skin's joint matrices, World(joint) · inverse bind matrix, with the nodes posed so.
inline std::vector<Mat4> skin_joint_matrices(const tinygltf::Model& m, const NodePoses& pose) {
  const std::size_t nodes = m.nodes.size();
  std::vector<int> parent(nodes, -1);
  for (std::size_t n = 0; n < nodes; ++n)
    for (int c : m.nodes[n].children) parent[static_cast<std::size_t>(c)] = static_cast<int>(n);
  std::function<Mat4(int)> world = [&](int n) -> Mat4 {
    Mat4 local = Mat4::Identity();
    local.topLeftCorner<3, 3>() = pose.r[n].normalized().toRotationMatrix() * pose.s[n].asDiagonal();
    local.topRightCorner<3, 1>() = pose.t[n];
    return parent[n] < 0 ? local : Mat4(world(parent[n]) * local);
  };
  const tinygltf::Skin& skin = m.skins[0];
  const std::vector<double> ibm = numbers(m, skin.inverseBindMatrices);
  std::vector<Mat4> joint;
  for (std::size_t j = 0; j < skin.joints.size(); ++j) {
    Mat4 inverse;
    for (int e = 0; e < 16; ++e) inverse(e % 4, e / 4) = ibm[16 * j + e];
    joint.push_back(world(skin.joints[j]) * inverse);
  }
  return joint;
}

// The file played as an engine plays animation `animation` at its key k (every channel keyed at
// the same times): each node's local transform from its key, else its own; the mesh's morph
// weights from its key; then morph targets added to POSITION and NORMAL, and linear blend
// skinning (normals by the skinning matrix's 3×3 part, then made unit). Without `morph` the
// targets are left out: the clip's skinning alone. `base` (x, y, z a vertex) in place of POSITION
// when given.
struct Shown {
  std::vector<Vec3> positions, normals;
};
inline Shown played(const tinygltf::Model& m, int animation, std::size_t k, bool morph = true,
                    const std::vector<double>* base = nullptr) {
  for (const tinygltf::Node& node : m.nodes) EXPECT_TRUE(node.matrix.empty());
  NodePoses pose = rest_poses(m);
  std::vector<Vec3>&t = pose.t, &s = pose.s;
  std::vector<Quat>& r = pose.r;
  const tinygltf::Mesh& mesh = m.meshes[0];
  std::vector<double> weights = mesh.weights;
  for (const tinygltf::AnimationChannel& ch : m.animations[static_cast<std::size_t>(animation)].channels) {
    const tinygltf::AnimationSampler& sampler =
        m.animations[static_cast<std::size_t>(animation)].samplers[static_cast<std::size_t>(ch.sampler)];
    const std::vector<double> v = numbers(m, sampler.output);
    const auto n = static_cast<std::size_t>(ch.target_node);
    if (ch.target_path == "translation") t[n] = Vec3(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
    if (ch.target_path == "scale") s[n] = Vec3(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
    if (ch.target_path == "rotation") r[n] = Quat(v[4 * k + 3], v[4 * k], v[4 * k + 1], v[4 * k + 2]);
    if (ch.target_path == "weights")
      weights.assign(v.begin() + k * weights.size(), v.begin() + (k + 1) * weights.size());
  }
  const std::vector<Mat4> joint = skin_joint_matrices(m, pose);
  const tinygltf::Primitive& p = mesh.primitives[0];
  const std::vector<double> position = base != nullptr ? *base : numbers(m, p.attributes.at("POSITION"));
  const std::vector<double> joints = numbers(m, p.attributes.at("JOINTS_0"));
  const std::vector<double> weight = numbers(m, p.attributes.at("WEIGHTS_0"));
  Shown out;
  std::vector<double> morphed = position;
  std::vector<double> normal =
      p.attributes.contains("NORMAL") ? numbers(m, p.attributes.at("NORMAL")) : std::vector<double>();
  for (std::size_t target = 0; target < p.targets.size(); ++target) {
    if (!morph || weights[target] == 0) continue;
    const std::vector<double> d = numbers(m, p.targets[target].at("POSITION"));
    for (std::size_t i = 0; i < d.size(); ++i) morphed[i] += weights[target] * d[i];
    if (normal.empty()) continue;
    const std::vector<double> dn = numbers(m, p.targets[target].at("NORMAL"));
    for (std::size_t i = 0; i < dn.size(); ++i) normal[i] += weights[target] * dn[i];
  }
  for (std::size_t v = 0; v < position.size() / 3; ++v) {
    Mat4 skinning = Mat4::Zero();
    for (int e = 0; e < 4; ++e) skinning += weight[4 * v + e] * joint[static_cast<std::size_t>(joints[4 * v + e])];
    out.positions.push_back(
        (skinning * Vec3(morphed[3 * v], morphed[3 * v + 1], morphed[3 * v + 2]).homogeneous()).head<3>());
    if (!normal.empty())
      out.normals.push_back(
          (skinning.topLeftCorner<3, 3>() * Vec3(normal[3 * v], normal[3 * v + 1], normal[3 * v + 2])).normalized());
  }
  return out;
}

inline std::string validate(const fs::path& glb, int* code) {
  const std::string cmd = "node '" + (fs::path(SWEEP_SOURCE_DIR) / "tests/gltf-validator/validate.js").string() +
                          "' '" + glb.string() + "' 2>&1";
  std::string report;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (pipe == nullptr) return report;
  char buf[4096];
  for (std::size_t got; (got = std::fread(buf, 1, sizeof buf, pipe)) > 0;) report.append(buf, got);
  const int status = ::pclose(pipe);
  *code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return report;
}

// A looping walk after a preroll of half a clip (simulated before frame 0), so that frame k plays clip time k/30 mod 1.
inline const char* const kWalk = R"({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 30, "forces": [],
  "body": {"node": "Hip", "animation": "Walk", "loop": true, "preroll": 0.5}})";

}  // namespace sweep::test::skinned_glb
