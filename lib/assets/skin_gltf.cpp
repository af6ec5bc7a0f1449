// A skinned character read through assimp as a glTF character (skin_gltf.h).
#include "sweep/assets/skin_gltf.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "sweep/assets/gltf_codes_detail.h"
#include "sweep/core/error.h"

namespace sweep::assets::detail {
namespace {

using namespace gltf_codes;

using Json = nlohmann::json;
using Mat4 = Eigen::Matrix4d;

// Appends to the document's one buffer, as surface_as_gltf lays it out (4-byte aligned views).
struct Bin {
  Json& json;
  std::string& bytes;
  std::size_t accessor(const void* data, std::size_t size, int component, const char* type, std::size_t count,
                       int target = 0) {
    bytes.append((4 - bytes.size() % 4) % 4, '\0');
    Json view = {{"buffer", 0}, {"byteOffset", bytes.size()}, {"byteLength", size}};
    if (target != 0) view["target"] = target;
    bytes.append(static_cast<const char*>(data), size);
    json["bufferViews"].push_back(std::move(view));
    json["accessors"].push_back({{"bufferView", json["bufferViews"].size() - 1},
                                 {"componentType", component},
                                 {"count", count},
                                 {"type", type}});
    return json["accessors"].size() - 1;
  }
  // An accessor's bytes, to be written over in place.
  char* at(std::size_t accessor) {
    const Json& a = json["accessors"][accessor];
    const Json& view = json["bufferViews"][a["bufferView"].get<std::size_t>()];
    return bytes.data() + view["byteOffset"].get<std::size_t>() + a.value("byteOffset", std::size_t{0});
  }
};

Mat4 trs_matrix(const SkinNode& n) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = n.rotation.normalized().toRotationMatrix() * n.scale.asDiagonal();
  m.topRightCorner<3, 1>() = n.translation;
  return m;
}

Json node_json(const SkinNode& n, bool animated) {
  Json node = {{"name", n.name}};
  const bool trs =
      animated || !n.matrix ||
      (trs_matrix(n) - *n.matrix).cwiseAbs().maxCoeff() <= 1e-9 * std::max(1.0, n.matrix->cwiseAbs().maxCoeff());
  if (!trs) {
    Json m = Json::array();
    for (int e = 0; e < 16; ++e) m.push_back((*n.matrix)(e % 4, e / 4));
    node["matrix"] = std::move(m);
    return node;
  }
  if (!n.translation.isZero(0.0)) node["translation"] = {n.translation.x(), n.translation.y(), n.translation.z()};
  const Quat r = n.rotation.normalized();
  if (!r.coeffs().isApprox(Quat::Identity().coeffs(), 0.0)) node["rotation"] = {r.x(), r.y(), r.z(), r.w()};
  if (!n.scale.isOnes(0.0)) node["scale"] = {n.scale.x(), n.scale.y(), n.scale.z()};
  return node;
}

const char* path_name(ChannelPath path) {
  return path == ChannelPath::rotation ? "rotation" : path == ChannelPath::scale ? "scale" : "translation";
}

Json animation_json(const SkinClip& clip, const SkinModel& model, Bin& bin) {
  Json animation = {{"name", clip.name}, {"samplers", Json::array()}, {"channels", Json::array()}};
  // The last channel of each node and path, as world_transforms plays them.
  std::map<std::pair<int, int>, const ClipChannel*> last;
  for (const ClipChannel& c : clip.channels) last[{c.node, static_cast<int>(c.path)}] = &c;
  auto add = [&](int node, ChannelPath path, const std::vector<float>& times, const std::vector<float>& values,
                 const char* interpolation) {
    const std::size_t input = bin.accessor(times.data(), 4 * times.size(), kFloat, "SCALAR", times.size());
    bin.json["accessors"][input]["min"] = Json::array({times.front()});
    bin.json["accessors"][input]["max"] = Json::array({times.back()});
    const int width = path == ChannelPath::rotation ? 4 : 3;
    const std::size_t output = bin.accessor(values.data(), 4 * values.size(), kFloat, width == 4 ? "VEC4" : "VEC3",
                                            values.size() / static_cast<std::size_t>(width));
    animation["samplers"].push_back({{"input", input}, {"output", output}, {"interpolation", interpolation}});
    animation["channels"].push_back(
        {{"sampler", animation["samplers"].size() - 1}, {"target", {{"node", node}, {"path", path_name(path)}}}});
  };
  for (const ClipChannel& c : clip.channels) {
    if (last[{c.node, static_cast<int>(c.path)}] != &c) continue;
    const std::vector<float> times(c.times.begin(), c.times.end());
    const std::vector<float> values(c.values.begin(), c.values.end());
    add(c.node, c.path, times, values,
        c.interpolation == ChannelInterpolation::step    ? "STEP"
        : c.interpolation == ChannelInterpolation::cubic ? "CUBICSPLINE"
                                                         : "LINEAR");
  }
  if (animation["channels"].empty()) {  // glTF wants a channel: the root held at rest
    const Vec3& t = model.nodes.front().translation;
    add(0, ChannelPath::translation, {static_cast<float>(clip.start)},
        {static_cast<float>(t.x()), static_cast<float>(t.y()), static_cast<float>(t.z())}, "LINEAR");
  }
  return animation;
}

// A skinned primitive's POSITION overwritten with its bind positions `p` (3 floats a vertex), its
// bounds lo..hi.
void set_bind_pose(Bin& bin, const Json& attributes, const std::vector<float>& p, const Eigen::Vector3f& lo,
                   const Eigen::Vector3f& hi) {
  const std::size_t position = attributes["POSITION"].get<std::size_t>();
  std::memcpy(bin.at(position), p.data(), 4 * p.size());
  bin.json["accessors"][position]["min"] = {lo.x(), lo.y(), lo.z()};
  bin.json["accessors"][position]["max"] = {hi.x(), hi.y(), hi.z()};
}

// Its NORMAL taken from world space into the bind space `to_world_linear` maps to world: by the
// inverse transpose of that map (its transpose: the map is a rotation).
void turn_normals_to_bind(Bin& bin, const Json& attributes, const Eigen::Matrix3d& to_world_linear, std::size_t count) {
  const Eigen::Matrix3d to_bind = to_world_linear.transpose();
  float* n = reinterpret_cast<float*>(bin.at(attributes["NORMAL"].get<std::size_t>()));
  for (std::size_t i = 0; i < count; ++i) {
    Eigen::Vector3f world;
    std::memcpy(world.data(), n + 3 * i, 12);
    const Eigen::Vector3f turned = (to_bind * world.cast<double>()).normalized().cast<float>();
    std::memcpy(n + 3 * i, turned.data(), 12);
  }
}

// Every primitive of `mesh` given JOINTS_0 (4 joint indices a vertex: unsigned bytes when the skin
// has at most 256 joints, else shorts) and WEIGHTS_0 (4 floats a vertex).
void set_skin_attributes(Bin& bin, std::size_t mesh, std::size_t joint_count, const std::vector<std::uint16_t>& joints,
                         const std::vector<float>& weights) {
  const std::size_t count = weights.size() / 4;
  std::size_t joints_accessor = 0;
  if (joint_count <= 256) {
    const std::vector<std::uint8_t> small(joints.begin(), joints.end());
    joints_accessor = bin.accessor(small.data(), small.size(), kUnsignedByte, "VEC4", count, kArrayBuffer);
  } else {
    joints_accessor = bin.accessor(joints.data(), 2 * joints.size(), kUnsignedShort, "VEC4", count, kArrayBuffer);
  }
  const std::size_t weights_accessor =
      bin.accessor(weights.data(), 4 * weights.size(), kFloat, "VEC4", count, kArrayBuffer);
  for (Json& primitive : bin.json["meshes"][mesh]["primitives"]) {
    primitive["attributes"]["JOINTS_0"] = joints_accessor;
    primitive["attributes"]["WEIGHTS_0"] = weights_accessor;
  }
}

// Another mesh of the file skinned by bones of the character's skeleton (every bone one of the
// model's joints): POSITION its bind positions, NORMAL turned into that space, JOINTS_0 and
// WEIGHTS_0 its 4 largest influences renormalised, so that the skin plays it as the file does.
// False (the mesh left static) when a bone is not a joint of the model.
bool skin_other_mesh(Bin& bin, std::size_t mesh, const SurfaceGltf::Bones& bones, const SkinModel& model) {
  Json& json = bin.json;
  std::vector<int> joint_of_bone;
  for (const std::string& name : bones.skin.bones) {
    const int node = model.find_node(name);
    joint_of_bone.push_back(node < 0 ? -1 : model.joint_of_node(node));
    if (joint_of_bone.back() < 0) return false;
  }
  const std::size_t count = bones.skin.bind.size();
  std::vector<float> p(3 * count), weights(4 * count, 0.0f);
  std::vector<std::uint16_t> joints(4 * count, 0);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3f b = bones.skin.bind[i].cast<float>();
    std::copy_n(b.data(), 3, &p[3 * i]);
    lo = lo.cwiseMin(b);
    hi = hi.cwiseMax(b);
    std::vector<std::pair<std::uint32_t, double>> in = bones.skin.influences[i];
    std::sort(in.begin(), in.end(), [](const auto& a, const auto& c) { return a.second > c.second; });
    if (in.size() > 4) in.resize(4);
    double total = 0;
    for (const auto& [bone, w] : in) total += w;
    if (!(total > 0)) return false;  // a vertex no bone moves: not a skin glTF can play
    for (std::size_t e = 0; e < in.size(); ++e) {
      joints[4 * i + e] = static_cast<std::uint16_t>(joint_of_bone[in[e].first]);
      weights[4 * i + e] = static_cast<float>(in[e].second / total);
    }
  }
  Json& attributes = json["meshes"][mesh]["primitives"][0]["attributes"];
  set_bind_pose(bin, attributes, p, lo, hi);
  if (attributes.contains("NORMAL")) turn_normals_to_bind(bin, attributes, bones.to_world_linear, count);
  set_skin_attributes(bin, mesh, model.joints.size(), joints, weights);
  return true;
}

}  // namespace

void add_skin(SurfaceGltf& gltf, const SkinModel& model, const Eigen::Affine3d& to_world) {
  Json& json = gltf.doc.json;
  if (gltf.sources.empty() || model.nodes.empty() || !gltf.doc.buffers.at(0))
    fail(ErrorCategory::internal, "a skinned character's surface has no primitive");
  Bin bin{json, *gltf.doc.buffers[0]};
  // The skinned mesh: the one whose vertices are the mesh read (every primitive of it shares them);
  // the file's other meshes are kept as they are, static.
  std::size_t first = 0;
  while (first < gltf.sources.size() && gltf.sources[first].empty()) ++first;
  if (first == gltf.sources.size() || gltf.primitive_mesh.size() != gltf.sources.size())
    fail(ErrorCategory::internal, "a skinned character's surface has no primitive of the mesh read");
  const std::size_t skinned_mesh = gltf.primitive_mesh[first];
  const std::vector<std::uint32_t>& source = gltf.sources[first];
  const std::size_t count = source.size();
  for (std::size_t k = 0; k < gltf.sources.size(); ++k) {
    if (!gltf.sources[k].empty() && gltf.primitive_mesh[k] != skinned_mesh)
      fail(ErrorCategory::internal, "a skinned character's mesh read is on several meshes of the document");
  }
  for (const std::uint32_t v : source) {
    if (v >= model.bind_positions.size())
      fail(ErrorCategory::internal, "a skinned character's surface is not its skinned mesh");
  }
  Json& attributes = json["meshes"][skinned_mesh]["primitives"][0]["attributes"];

  // POSITION and NORMAL in the bind space, written over the world ones.
  std::vector<float> p(3 * count);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3f b = model.bind_positions[source[i]].cast<float>();
    std::copy_n(b.data(), 3, &p[3 * i]);
    lo = lo.cwiseMin(b);
    hi = hi.cwiseMax(b);
  }
  set_bind_pose(bin, attributes, p, lo, hi);
  if (attributes.contains("NORMAL") && !to_world.linear().isIdentity(0.0))
    turn_normals_to_bind(bin, attributes, to_world.linear(), count);

  // JOINTS_0 and WEIGHTS_0.
  std::vector<float> weights(4 * count);
  std::vector<std::uint16_t> joints(4 * count);
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t e = 0; e < 4; ++e) {
      joints[4 * i + e] = model.vertex_joints[source[i]][e];
      weights[4 * i + e] = static_cast<float>(model.vertex_weights[source[i]][e]);
    }
  }
  set_skin_attributes(bin, skinned_mesh, model.joints.size(), joints, weights);

  // The skin.
  std::vector<float> ibm;
  for (const Mat4& m : model.inverse_bind) {
    for (int e = 0; e < 16; ++e) {
      const int row = e % 4, column = e / 4;  // the last row exactly (0, 0, 0, 1), as glTF wants
      ibm.push_back(row < 3 ? static_cast<float>(m(row, column)) : column == 3 ? 1.0f : 0.0f);
    }
  }
  const std::size_t ibm_accessor = bin.accessor(ibm.data(), 4 * ibm.size(), kFloat, "MAT4", model.joints.size());
  json["skins"] = Json::array({{{"joints", model.joints}, {"inverseBindMatrices", ibm_accessor}}});

  // The nodes, and the clips.
  std::vector<char> animated(model.nodes.size(), 0);
  for (const SkinClip& clip : model.clips)
    for (const ClipChannel& c : clip.channels) animated[static_cast<std::size_t>(c.node)] = 1;
  Json nodes = Json::array();
  for (std::size_t i = 0; i < model.nodes.size(); ++i) nodes.push_back(node_json(model.nodes[i], animated[i]));
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    const int parent = model.nodes[i].parent;
    if (parent < 0) continue;
    Json& up = nodes[static_cast<std::size_t>(parent)];
    if (!up.contains("children")) up["children"] = Json::array();
    up["children"].push_back(i);
  }
  // glTF skins a mesh by its joints alone, ignoring its node's transform, and importers (Blender's)
  // place a skinned mesh best as a root of no transform: a mesh node that is a leaf, no joint and
  // moved by no clip is made one (the joints' world transforms do not change).
  const auto mesh_node = static_cast<std::size_t>(model.mesh_node);
  const int mesh_parent = model.nodes[mesh_node].parent;
  const bool detach = mesh_parent >= 0 && !animated[mesh_node] && !nodes[mesh_node].contains("children") &&
                      std::find(model.joints.begin(), model.joints.end(), model.mesh_node) == model.joints.end();
  Json& shown = nodes[mesh_node];
  shown["mesh"] = skinned_mesh;
  shown["skin"] = 0;
  if (detach) {
    // Its transform the mesh's space → world, as the bake read it: placed by it, POSITION is the mesh
    // read (the .glb bake maps its vertices so), and glTF's skinning ignores it.
    SkinNode placed;
    placed.matrix = to_world.matrix();
    Eigen::Matrix3d rotation, scaling;
    to_world.computeRotationScaling(&rotation, &scaling);
    placed.translation = to_world.translation();
    placed.rotation = Quat(rotation);
    placed.scale = scaling.diagonal();
    const Json transform = node_json(placed, false);
    for (const char* key : {"matrix", "translation", "rotation", "scale"}) {
      shown.erase(key);
      if (transform.contains(key)) shown[key] = transform[key];
    }
    Json& siblings = nodes[static_cast<std::size_t>(mesh_parent)]["children"];
    siblings.erase(std::find(siblings.begin(), siblings.end(), Json(mesh_node)));
    if (siblings.empty()) nodes[static_cast<std::size_t>(mesh_parent)].erase("children");
  }
  // The surface's other nodes (the file's other meshes, placed in world space): each shown by the
  // model's node that shows it in the file (the same name, in the file's order), made a root of no
  // transform when that node is a leaf, no joint and unanimated; else by a root of its own after
  // the model's. One skinned by bones of the skeleton is skinned by the skin, as the file plays it.
  std::vector<char> made_root(model.nodes.size(), 0);
  std::vector<std::size_t> appended;
  std::size_t from = 0;
  for (const Json& node : json["nodes"]) {
    const std::size_t mesh = node.value("mesh", skinned_mesh);
    if (mesh == skinned_mesh) continue;
    const std::string name = node.value("name", std::string());
    std::size_t at = from;
    while (at < model.nodes.size() && (model.nodes[at].name != name || at == mesh_node)) ++at;
    const bool own = at < model.nodes.size() && !animated[at] && !nodes[at].contains("children") &&
                     !nodes[at].contains("mesh") &&
                     std::find(model.joints.begin(), model.joints.end(), static_cast<int>(at)) == model.joints.end();
    std::size_t shows = nodes.size();
    if (own) {
      from = at + 1;
      shows = at;
      made_root[at] = 1;
      for (const char* key : {"matrix", "translation", "rotation", "scale"}) nodes[at].erase(key);
      if (const int parent = model.nodes[at].parent; parent >= 0) {
        Json& siblings = nodes[static_cast<std::size_t>(parent)]["children"];
        siblings.erase(std::find(siblings.begin(), siblings.end(), Json(at)));
        if (siblings.empty()) nodes[static_cast<std::size_t>(parent)].erase("children");
      }
    } else {
      appended.push_back(shows);
      nodes.push_back({{"name", name}});
    }
    nodes[shows]["mesh"] = mesh;
    if (mesh < gltf.mesh_bones.size() && gltf.mesh_bones[mesh] &&
        skin_other_mesh(bin, mesh, *gltf.mesh_bones[mesh], model))
      nodes[shows]["skin"] = 0;
  }
  json["nodes"] = std::move(nodes);
  Json roots = Json::array();
  for (std::size_t i = 0; i < model.nodes.size(); ++i)
    if (model.nodes[i].parent < 0 || (detach && i == mesh_node) || made_root[i]) roots.push_back(i);
  for (const std::size_t i : appended) roots.push_back(i);
  json["scenes"] = Json::array({{{"nodes", std::move(roots)}}});
  if (!model.clips.empty()) {
    json["animations"] = Json::array();
    for (const SkinClip& clip : model.clips) json["animations"].push_back(animation_json(clip, model, bin));
  }
  bin.bytes.append((4 - bin.bytes.size() % 4) % 4, '\0');
  json["buffers"][0]["byteLength"] = bin.bytes.size();
  json = Json::parse(json.dump());  // numbers as a reader sees them (unsigned where not negative)
}

}  // namespace sweep::assets::detail
