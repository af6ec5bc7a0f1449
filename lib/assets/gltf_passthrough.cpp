// The passthrough .glb: the input glTF document plus the bake (gltf_passthrough.h says what is kept,
// what is added and what is refused).
#include "sweep/assets/gltf_passthrough.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>

#include "sweep/assets/gltf_character_joints.h"
#include "sweep/assets/gltf_codes_detail.h"
#include "sweep/assets/gltf_document.h"
#include "sweep/assets/gltf_skin.h"
#include "sweep/assets/obj_gltf.h"
#include "sweep/assets/skin_gltf.h"
#include "sweep/assets/skinned_clip.h"
#include "sweep/assets/smooth_normals.h"
#include "sweep/core/error.h"
#include "sweep/core/text.h"
#include "sweep/io/mesh_names.h"
#include "sweep/io/read_file.h"

using sweep::io::read_file;

namespace sweep::assets::detail {

// A node's rest transform as translation, rotation and scale (a "matrix" decomposed; `exact`
// false when the matrix is not a rotation times a positive diagonal scale plus a translation).
// Not file-local: GltfPassthrough::State, declared in the header, holds one.
struct NodeTrs {
  Vec3 t = Vec3::Zero();
  Eigen::Quaterniond r = Eigen::Quaterniond::Identity();
  Vec3 s = Vec3::Ones();
  bool from_matrix = false, exact = true;
  Eigen::Affine3d affine() const {
    Eigen::Affine3d a = Eigen::Affine3d::Identity();
    a.translate(t);
    a.rotate(r);
    a.scale(s);
    return a;
  }
};

namespace {

using namespace gltf_codes;

using Json = nlohmann::json;
using Affine = Eigen::Affine3d;
using Mat3 = Eigen::Matrix3d;
namespace fs = std::filesystem;

NodeTrs node_trs(const Json& node) {
  NodeTrs out;
  if (const auto m = node.find("matrix"); m != node.end() && m->is_array() && m->size() == 16) {
    Eigen::Matrix4d matrix;
    for (int k = 0; k < 16; ++k) matrix(k % 4, k / 4) = (*m)[k].is_number() ? (*m)[k].get<double>() : 0.0;
    out.from_matrix = true;
    out.t = matrix.block<3, 1>(0, 3);
    const Mat3 lin = matrix.block<3, 3>(0, 0);
    for (int c = 0; c < 3; ++c) out.s[c] = lin.col(c).norm();
    Mat3 rot = lin;
    for (int c = 0; c < 3; ++c) rot.col(c) /= out.s[c] > 0 ? out.s[c] : 1.0;
    if (rot.determinant() < 0) {  // a mirror: a negative scale on x
      out.s[0] = -out.s[0];
      rot.col(0) = -rot.col(0);
    }
    out.exact = (rot.transpose() * rot - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-6 &&
                out.s.cwiseAbs().minCoeff() > 0 && matrix.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1));
    out.r = Eigen::Quaterniond(rot).normalized();
    return out;
  }
  auto vec = [&](const char* key, int n, std::array<double, 4> fallback) {
    if (const auto v = node.find(key); v != node.end() && v->is_array() && static_cast<int>(v->size()) == n) {
      for (int i = 0; i < n; ++i) fallback[i] = (*v)[i].is_number() ? (*v)[i].get<double>() : fallback[i];
    }
    return fallback;
  };
  const auto t = vec("translation", 3, {0, 0, 0, 0});
  const auto r = vec("rotation", 4, {0, 0, 0, 1});
  const auto sc = vec("scale", 3, {1, 1, 1, 0});
  out.t = Vec3(t[0], t[1], t[2]);
  out.r = Eigen::Quaterniond(r[3], r[0], r[1], r[2]).normalized();
  out.s = Vec3(sc[0], sc[1], sc[2]);
  return out;
}

std::string percent_decoded(const std::string& uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// The bytes behind a URI: a base64 data URI (and its media type) or a file beside the glTF.
struct UriBytes {
  std::optional<std::string> bytes;
  std::string media_type;
};
UriBytes uri_bytes(const std::string& uri, const fs::path& dir) {
  UriBytes out;
  if (uri.rfind("data:", 0) == 0) {
    const std::size_t comma = uri.find(";base64,");
    if (comma == std::string::npos) return out;
    out.media_type = uri.substr(5, comma - 5);
    out.bytes = decode_base64(std::string_view(uri).substr(comma + 8));
    return out;
  }
  try {
    out.bytes = read_file(dir / percent_decoded(uri));
  } catch (const Error&) {
  }
  return out;
}

std::string image_media_type(const std::string& bytes, const std::string& declared, const std::string& uri) {
  if (bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0) return "image/png";
  if (bytes.compare(0, 3, "\xFF\xD8\xFF") == 0) return "image/jpeg";
  if (bytes.size() >= 12 && bytes.compare(0, 4, "RIFF") == 0 && bytes.compare(8, 4, "WEBP") == 0) return "image/webp";
  if (bytes.compare(0, 12, "\xABKTX 20\xBB\r\n\x1a\n") == 0) return "image/ktx2";
  if (!declared.empty()) return declared;
  const std::string ext = lower_extension(fs::path(uri));
  if (ext == "png") return "image/png";
  if (ext == "jpg" || ext == "jpeg") return "image/jpeg";
  return "";
}

Json vec3_json(const Eigen::Vector3f& v) {
  return Json::array({v.x(), v.y(), v.z()});
}

}  // namespace

bool is_passthrough_source(const fs::path& source) {
  // Every format but those of one nameless mesh and no materials (OFF, PLY, STL: the plain .glb).
  const std::string ext = lower_extension(source);
  return !ext.empty() && ext != "off" && ext != "ply" && ext != "stl";
}

struct GltfPassthrough::State {
  fs::path source, out;
  std::string where;  // "source: "
  GltfDocument doc;
  int frames = 0;
  double fps = 24;
  bool body_moves = false;

  // One primitive of the input, in the importer's vertex order.
  struct Primitive {
    std::size_t mesh = 0, index = 0;
    std::uint32_t count = 0;
    std::vector<std::uint32_t> source;  // each vertex's vertex in the mesh as read
    // An earlier primitive with the same POSITION accessor (and so the same vertices): its targets
    // serve this one too.
    int same_as = -1;
    bool deformed = false;
    std::vector<float> normals, tangents;  // the input's (3 and 4 a vertex), when present
    bool normals_repaired = false;         // some were not finite or zero: written anew (repair_normals)
    Mat3 to_local = Mat3::Identity(), normal_to_world = Mat3::Identity(), to_world = Mat3::Identity();
    std::vector<std::uint32_t> listed;  // local vertices whose position or normal can change
    BinBlock listed_block;
    std::vector<BinBlock> positions, normals_blocks, tangents_blocks;
    std::vector<Eigen::Vector3f> lo, hi;
  };
  std::vector<Primitive> primitives;
  // A document made from another format (an OBJ's): each primitive's vertices' sources.
  std::vector<std::vector<std::uint32_t>> given_sources;
  // The primitives the mesh as read is made of (BakeSource::parts), counted over the meshes in
  // order; empty = all of them.
  std::vector<unsigned> parts;
  std::vector<std::size_t> deformed_meshes;
  // A rig of several meshes (BakeSource::mesh_name a list): its meshes that do not bend still
  // follow a moving body, as the .pc2 shows them (their nodes keyed, no targets).
  bool carry_still_meshes = false;

  // A node showing a deformed mesh: its weights are animated, and with a moving body its transform.
  struct Shown {
    std::size_t node = 0;
    Affine parent = Affine::Identity();
    NodeTrs local;
    std::vector<std::size_t> ancestors;
    // Below another node that shows a deformed mesh: it follows that node's body motion and gets
    // no keys of its own (else the body would move it twice).
    bool follows_parent = false;
    bool morphs = true;  // false: a still mesh of a rig of several, carried by the body alone
    std::vector<float> translations, rotations;
    BinBlock translation_block, rotation_block;
  };
  std::vector<Shown> shown;

  // A skinned character's clip drove the bake (BakeInfo::skinned): the targets go under its skin,
  // and the clip's channels are resampled at the frame times into the new animation.
  const SkinnedClip* skin = nullptr;
  // ... and with the parts' joints added to its skeleton (no targets then).
  const CharacterJoints* joints = nullptr;
  int next_frame = 0;
  struct Resampled {
    int node = 0;
    ChannelPath path = ChannelPath::translation;
    const ClipChannel* channel = nullptr;  // the clip's (the last one on this node and path)
    std::vector<float> values;             // 3 or 4 a frame
    BinBlock block;
  };
  std::vector<Resampled> resampled;
  std::vector<Eigen::Vector3f> keyed;  // one frame's skinned pose (no part motion), world
  std::vector<Eigen::Vector3f> keyed_normals;

  // The mesh, welded by rest position, for the smooth normals that turn the input's.
  std::vector<Vec3> rest_world;
  std::vector<Eigen::Vector3f> rest_f;
  std::vector<std::uint32_t> rep, welded_triangles;
  std::vector<char> animated;
  std::vector<Eigen::Vector3f> rest_normals, frame_normals;

  // The input's bytes: buffers (base offsets in the BIN chunk) and images to embed.
  std::vector<std::string> buffer_bytes;
  std::vector<std::uint64_t> buffer_base;
  struct Image {
    std::size_t index = 0;
    std::string bytes, media_type;
    BinBlock block;
  };
  std::vector<Image> images;
  std::uint64_t size = 0;  // BIN bytes so far
  BinBlock times, weight_indices, weight_values;
  float last_time = 0;

  [[noreturn]] void refuse(const std::string& what) const { fail(ErrorCategory::unsupported, where + what); }
  [[noreturn]] void bad(const std::string& what) const { fail(ErrorCategory::bad_input, where + what); }

  std::string mesh_name(std::size_t m) const {
    const Json& mesh = doc.json["meshes"][m];
    return "mesh " + std::to_string(m) +
           (mesh.contains("name") && mesh["name"].is_string() ? " ('" + mesh["name"].get<std::string>() + "')" : "");
  }
  std::string node_name(std::size_t n) const {
    const Json& node = doc.json["nodes"][n];
    return "node " + std::to_string(n) +
           (node.contains("name") && node["name"].is_string() ? " ('" + node["name"].get<std::string>() + "')" : "");
  }

  BinBlock put(const AppendBin& append, const void* data, std::size_t bytes, std::uint64_t align = 4) {
    static const char zeros[16] = {};
    if (const std::uint64_t pad = (align - size % align) % align; pad > 0) {
      append(zeros, static_cast<std::size_t>(pad));
      size += pad;
    }
    const BinBlock b = append(data, bytes);
    size += bytes;
    return b;
  }
};

namespace {

using State = GltfPassthrough::State;

const Json& array_of(const Json& doc, const char* key) {
  static const Json empty = Json::array();
  const auto it = doc.find(key);
  return it != doc.end() && it->is_array() ? *it : empty;
}

// Every node of the default scene, depth first, with its world transform and parent's; the first
// node showing each mesh is where the importer placed it.
struct Visit {
  std::size_t node;
  Affine parent, world;
  std::vector<std::size_t> ancestors;  // root first
};
void visit(const Json& nodes, std::size_t n, const Affine& parent, std::vector<Visit>& out,
           std::vector<std::size_t>& ancestors) {
  if (n >= nodes.size() || !nodes[n].is_object() || ancestors.size() > 1000) return;
  const Affine world = parent * node_trs(nodes[n]).affine();
  out.push_back({n, parent, world, ancestors});
  ancestors.push_back(n);
  for (const Json& c : array_of(nodes[n], "children")) {
    if (c.is_number_unsigned()) visit(nodes, c.get<std::size_t>(), world, out, ancestors);
  }
  ancestors.pop_back();
}

void check_compression(const State& s) {
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    for (const Json& e : array_of(s.doc.json, key)) {
      if (!e.is_string()) continue;
      const std::string name = e.get<std::string>();
      if (name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression" ||
          name == "KHR_meshopt_compression") {
        s.refuse("uses " + name +
                 ": the .glb bake copies the file and adds morph targets to its "
                 "primitives, which it cannot do to compressed geometry; save the file without "
                 "compression, or bake to .pc2");
      }
    }
  }
}

// Reads the bytes of every buffer and of every image given by a URI.
void read_bytes(State& s) {
  const fs::path dir = s.source.parent_path();
  const Json& buffers = array_of(s.doc.json, "buffers");
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    std::optional<std::string> bytes;
    if (b < s.doc.buffers.size()) bytes = s.doc.buffers[b];
    if (!bytes && buffers[b].is_object() && buffers[b].contains("uri") && buffers[b]["uri"].is_string()) {
      bytes = uri_bytes(buffers[b]["uri"].get<std::string>(), dir).bytes;
    }
    const std::uint64_t length = gltf_unsigned(buffers[b], "byteLength", 0);
    if (!bytes || bytes->size() < length) {
      s.bad("buffer " + std::to_string(b) +
            (buffers[b].contains("uri") && buffers[b]["uri"].is_string()
                 ? " ('" + buffers[b]["uri"].get<std::string>().substr(0, 80) + "')"
                 : "") +
            ": cannot read its " + std::to_string(length) + " bytes, which the .glb bake copies");
    }
    bytes->resize(length);
    s.buffer_bytes.push_back(std::move(*bytes));
  }
  const Json& images = array_of(s.doc.json, "images");
  for (std::size_t i = 0; i < images.size(); ++i) {
    if (!images[i].is_object() || !images[i].contains("uri") || !images[i]["uri"].is_string()) continue;
    const std::string uri = images[i]["uri"].get<std::string>();
    const UriBytes got = uri_bytes(uri, dir);
    const std::string shown = uri.rfind("data:", 0) == 0 ? "a data URI" : "'" + uri + "'";
    if (!got.bytes)
      s.bad("image " + std::to_string(i) + " (" + shown + "): cannot read it, and the .glb bake embeds it");
    const std::string type = image_media_type(*got.bytes, got.media_type, uri);
    if (type.empty())
      s.refuse("image " + std::to_string(i) + " (" + shown +
               "): not PNG, JPEG, WebP or KTX2, so it cannot be embedded in the .glb");
    s.images.push_back({i, *got.bytes, type, {}});
  }
}

// The importer's vertex order: glTF meshes in order, their primitives in order, placed by the first
// node showing the mesh. Marks the meshes the bake deforms and checks what they must be.
void map_primitives(State& s, const Mesh& rest, const std::vector<std::uint32_t>& animated) {
  const Json& json = s.doc.json;
  const Json& nodes = array_of(json, "nodes");
  const Json& meshes = array_of(json, "meshes");
  std::vector<Visit> visits;
  const Json& scenes = array_of(json, "scenes");
  const std::size_t scene = gltf_unsigned(json, "scene", 0);
  if (scene < scenes.size()) {
    for (const Json& n : array_of(scenes[scene], "nodes")) {
      std::vector<std::size_t> ancestors;
      if (n.is_number_unsigned()) visit(nodes, n.get<std::size_t>(), Affine::Identity(), visits, ancestors);
    }
  }
  std::vector<std::vector<const Visit*>> showing(meshes.size());
  for (const Visit& v : visits) {
    const std::uint64_t m = gltf_unsigned(nodes[v.node], "mesh", meshes.size());
    if (m < meshes.size()) showing[m].push_back(&v);
  }
  std::uint64_t base = 0;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const Json& prims = array_of(meshes[m], "primitives");
    for (std::size_t p = 0; p < prims.size(); ++p) {
      State::Primitive prim;
      prim.mesh = m;
      prim.index = p;
      const Json* position = prims[p].contains("attributes") && prims[p]["attributes"].contains("POSITION")
                                 ? gltf_element(json, "accessors", prims[p]["attributes"]["POSITION"])
                                 : nullptr;
      const std::uint64_t count = position ? gltf_unsigned(*position, "count", 0) : 0;
      prim.count = static_cast<std::uint32_t>(count);
      const std::size_t k = s.primitives.size();
      for (std::size_t e = 0; e < k && position; ++e) {
        const State::Primitive& earlier = s.primitives[e];
        if (earlier.mesh != m || prim.same_as >= 0) continue;
        const Json& a = prims[earlier.index].value("attributes", Json::object());
        const Json& b = prims[p].value("attributes", Json::object());
        bool same = a.is_object() && b.is_object();
        for (const char* key : {"POSITION", "NORMAL", "TANGENT"})
          same = same && a.value(key, Json()) == b.value(key, Json());
        if (same) prim.same_as = static_cast<int>(e);
      }
      if (k < s.given_sources.size()) prim.source = s.given_sources[k];
      s.primitives.push_back(std::move(prim));
    }
  }
  // The mesh as read is the primitives `parts` names, in that order (all of them, in order, for
  // the whole file): their vertices one after another. The others are not the bake's.
  if (s.given_sources.empty()) {
    std::vector<std::size_t> taken;
    for (std::size_t k = 0; k < s.primitives.size(); ++k) taken.push_back(k);
    if (!s.parts.empty()) taken.assign(s.parts.begin(), s.parts.end());
    for (const std::size_t k : taken) {
      if (k >= s.primitives.size() || !s.primitives[k].source.empty()) {
        s.refuse("the mesh was read from primitive " + std::to_string(k) +
                 " (counted over its meshes), which "
                 "the file does not have once; the .glb bake cannot tell which primitive a vertex belongs to "
                 "(bake to .pc2)");
      }
      State::Primitive& prim = s.primitives[k];
      for (std::uint64_t i = 0; i < prim.count; ++i) prim.source.push_back(static_cast<std::uint32_t>(base + i));
      base += prim.count;
    }
    if (base != rest.vertex_count()) {
      s.refuse("its primitives hold " + std::to_string(base) + " vertices but the mesh was read with " +
               std::to_string(rest.vertex_count()) +
               "; the .glb bake cannot tell which primitive a vertex "
               "belongs to (bake to .pc2)");
    }
  }
  std::vector<char> moving(rest.vertex_count(), 0);
  for (const std::uint32_t v : animated) moving[v] = 1;
  for (State::Primitive& prim : s.primitives) {
    for (std::size_t i = 0; i < prim.source.size() && !prim.deformed; ++i) prim.deformed = moving[prim.source[i]] != 0;
  }
  const bool any_deformed =
      std::any_of(s.primitives.begin(), s.primitives.end(), [](const State::Primitive& p) { return p.deformed; });
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    bool deformed = false, read = false;
    for (const State::Primitive& prim : s.primitives) {
      deformed = deformed || (prim.mesh == m && prim.deformed);
      read = read || (prim.mesh == m && !prim.source.empty());
    }
    const bool carried = !deformed && read && any_deformed && s.body_moves && s.carry_still_meshes;
    if (!deformed && !carried) continue;
    if (deformed) s.deformed_meshes.push_back(m);
    const std::string what = s.mesh_name(m);
    if (showing[m].empty()) s.refuse(what + " moves but no node of the scene shows it");
    const Affine& world = showing[m].front()->world;
    for (const Visit* v : showing[m]) {
      if (!v->world.matrix().isApprox(world.matrix(), 1e-9) &&
          (v->world.matrix() - world.matrix()).cwiseAbs().maxCoeff() > 1e-9) {
        s.refuse(what + " moves, and " + s.node_name(showing[m].front()->node) + " and " + s.node_name(v->node) +
                 " show it with different transforms; morph targets would move both copies alike. "
                 "Give each node its own mesh");
      }
      if (const Json& node = nodes[v->node]; node.contains("extensions") && node["extensions"].is_object() &&
                                             node["extensions"].contains("EXT_mesh_gpu_instancing")) {
        s.refuse(what + " moves and " + s.node_name(v->node) +
                 " draws it many times (EXT_mesh_gpu_instancing); morph targets would move every "
                 "copy alike (bake to .pc2)");
      }
      if (nodes[v->node].contains("skin") &&
          (s.skin == nullptr || static_cast<int>(v->node) != s.skin->model().mesh_node)) {
        s.refuse(what + " moves and is skinned by " + s.node_name(v->node) +
                 ", but no clip of its skin drives the bake; the .glb bake puts morph targets under a "
                 "skin only when the scene's body plays its clip (bake to .pc2)");
      }
      State::Shown shown;
      shown.morphs = deformed;
      shown.node = v->node;
      shown.parent = v->parent;
      shown.local = node_trs(nodes[v->node]);
      shown.ancestors = v->ancestors;
      if (!shown.local.exact) {
        s.refuse(what + " moves, and " + s.node_name(v->node) +
                 " shows it by a matrix that is not a "
                 "translation, rotation and scale; glTF animates (even the morph weights of) a node "
                 "only by those; bake to .pc2");
      }
      if (s.body_moves) {
        const Mat3 pl = v->parent.linear();
        const Mat3 gram = pl.transpose() * pl;
        const double scale2 = gram.trace() / 3;
        if (!shown.local.exact || (gram - scale2 * Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-6 * scale2 ||
            pl.determinant() <= 0) {
          s.refuse(what + ": the body moves " + s.node_name(v->node) +
                   ", whose parent's world transform (or own matrix) is not a rotation, a uniform "
                   "scale and a translation, so its motion cannot be written as its translation "
                   "and rotation; bake to .pc2");
        }
      }
      s.shown.push_back(std::move(shown));
    }
    if (!deformed) continue;
    const Mat3 lin = world.linear();
    if (std::abs(lin.determinant()) < 1e-300) s.refuse(what + ": its node's transform is singular");
    for (State::Primitive& prim : s.primitives) {
      if (prim.mesh != m) continue;
      const Json& pj = meshes[m]["primitives"][prim.index];
      const std::string where = what + " primitive " + std::to_string(prim.index);
      if (pj.contains("targets")) {
        s.refuse(where +
                 " already has morph targets; the .glb bake adds one a frame and cannot "
                 "combine them with the file's own (bake to .pc2)");
      }
      const Json& attributes = pj["attributes"];
      const auto positions = read_float_accessor(s.doc, attributes["POSITION"], 3);
      if (!positions || positions->size() != 3u * prim.count) {
        s.refuse(where +
                 ": its POSITION is not a plain float accessor (sparse or quantized), "
                 "which the .glb bake cannot map its targets onto");
      }
      for (const auto& [name, width, out] :
           {std::tuple{"NORMAL", 3, &prim.normals}, std::tuple{"TANGENT", 4, &prim.tangents}}) {
        if (!attributes.contains(name)) continue;
        auto values = read_float_accessor(s.doc, attributes[name], width);
        if (!values || values->size() != static_cast<std::size_t>(width) * prim.count) {
          s.refuse(where + ": its " + name +
                   " is not a plain float accessor (sparse or quantized), "
                   "which the .glb bake cannot turn with the bend");
        }
        *out = std::move(*values);
      }
      prim.to_world = lin;
      prim.to_local = lin.inverse();
      prim.normal_to_world = prim.to_local.transpose();
      // A primitive of a deformed mesh that the mesh as read does not hold (assimp numbers a glTF's
      // meshes in the order its scene reaches them, not the file's): refused, never indexed.
      if (prim.source.size() != prim.count) {
        s.refuse(where +
                 ": the mesh was read without this primitive's vertices (assimp's mesh order "
                 "differs from the file's); the .glb bake cannot tell which primitive a vertex belongs "
                 "to (bake to .pc2)");
      }
      // The importer's world positions must be these, placed by this node: else the order differs.
      for (std::uint32_t i = 0; i < prim.count; ++i) {
        const Vec3 local((*positions)[3 * i], (*positions)[3 * i + 1], (*positions)[3 * i + 2]);
        const Vec3 expected = world * local;
        const Vec3& got = rest.positions[prim.source[i]];
        if ((expected - got).norm() > 1e-5 * (1 + expected.norm() + got.norm())) {
          s.refuse(where + " vertex " + std::to_string(i) + " is at (" + format_number(expected.x()) + ", " +
                   format_number(expected.y()) + ", " + format_number(expected.z()) +
                   ") in world space, "
                   "but the mesh as read has vertex " +
                   std::to_string(prim.source[i]) +
                   " elsewhere; the "
                   ".glb bake cannot map its targets (bake to .pc2)");
        }
      }
    }
  }
  for (State::Shown& shown : s.shown) {
    for (const State::Shown& other : s.shown) {
      shown.follows_parent = shown.follows_parent || std::find(shown.ancestors.begin(), shown.ancestors.end(),
                                                               other.node) != shown.ancestors.end();
    }
  }
}

// Smooth normals over the welded triangles, for the welded representatives.
void weld(State& s, const Mesh& rest) {
  std::map<std::array<double, 3>, std::uint32_t> first;
  s.rep.resize(rest.vertex_count());
  for (std::uint32_t v = 0; v < rest.vertex_count(); ++v) {
    const Vec3& p = rest.positions[v];
    const std::array<double, 3> key{p.x() == 0 ? 0.0 : p.x(), p.y() == 0 ? 0.0 : p.y(), p.z() == 0 ? 0.0 : p.z()};
    s.rep[v] = first.try_emplace(key, v).first->second;
  }
  s.welded_triangles = rest.triangles();
  for (std::uint32_t& v : s.welded_triangles) v = s.rep[v];
}

}  // namespace

namespace {

// A normal that is not finite or has no length (`vn nan 0 1`, `vn 0 0 0`, a NaN in a glTF's
// NORMAL) would make every target's normal delta NaN, and the file's own accessor invalid: it is
// replaced by the surface's own normal there (area-weighted over the faces round the vertex, the
// one the bend turns), in the primitive's space, and the accessor is written anew with the others
// (finish). A warning says how many and the first.
void repair_normals(State& s, const std::function<void(const std::string&)>& warn) {
  for (State::Primitive& p : s.primitives) {
    if (p.same_as >= 0) continue;  // its vertices are an earlier primitive's, repaired there
    std::size_t repaired = 0;
    std::string first;
    for (std::uint32_t i = 0; i < p.count && 3u * i + 2 < p.normals.size(); ++i) {
      float* n = &p.normals[3 * i];
      const double length = Vec3(n[0], n[1], n[2]).norm();
      if (std::isfinite(length) && length > 0) continue;
      if (repaired++ == 0) {
        first = "vertex " + std::to_string(i) + " (" + format_exact(n[0]) + ", " + format_exact(n[1]) + ", " +
                format_exact(n[2]) + ")";
      }
      const Vec3 world = s.rest_normals[s.rep[p.source[i]]].cast<double>();
      Vec3 local = p.to_world.transpose() * world;
      local = local.norm() > 0 && std::isfinite(local.norm()) ? Vec3(local.normalized()) : Vec3::UnitY();
      for (int c = 0; c < 3; ++c) n[c] = static_cast<float>(local[c]);
    }
    if (repaired == 0) continue;
    p.normals_repaired = true;
    if (warn) {
      warn(s.where + "mesh " + std::to_string(p.mesh) + " primitive " + std::to_string(p.index) + ": " +
           std::to_string(repaired) + (repaired == 1 ? " normal is" : " normals are") +
           " not finite or of no length (first: " + first +
           "); recomputed from the faces round each vertex (area-weighted)");
    }
  }
}

}  // namespace

namespace {

// The clip's channels, one a node and path (the last, as world_transforms takes it), to be keyed
// at the frame times.
void resample_clip(State& s) {
  const SkinClip& clip = s.skin->model().clips[static_cast<std::size_t>(s.skin->clip())];
  for (const ClipChannel& c : clip.channels) {
    auto same = std::find_if(s.resampled.begin(), s.resampled.end(),
                             [&](const State::Resampled& r) { return r.node == c.node && r.path == c.path; });
    if (same == s.resampled.end()) {
      State::Resampled r;
      r.node = c.node;
      r.path = c.path;
      same = s.resampled.insert(s.resampled.end(), std::move(r));
    }
    same->channel = &c;
    same->values.reserve(static_cast<std::size_t>(c.width()) * static_cast<std::size_t>(s.frames));
  }
}

// One frame of a skinned clip's bake. glTF applies morph targets before skinning: a vertex with
// skinning matrix S = Σ w_i J_i shows at S (b + d) = S b + A d (A the 3×3 linear part of S, b its
// POSITION), so the target that puts it at the baked world position p is d = A⁻¹ (p − S b): the
// part's motion taken back through the vertex's own skinning matrix. Normals and tangents are
// skinned by A too: the input's, as the clip alone shows them (A n), are turned by the rotation
// that takes the clip's pose's smooth normal to the bake's, and taken back by A⁻¹.
void resample_frame(State& s);

void frame_under_skin(State& s, std::span<const Eigen::Vector3f> positions, const AppendBin& append) {
  const SkinModel& model = s.skin->model();
  const double time = s.next_frame / s.fps;
  const std::vector<Eigen::Matrix4d> joints = s.skin->joint_matrices_at(time);
  s.keyed.resize(positions.size());
  for (std::size_t v = 0; v < positions.size(); ++v) s.keyed[v] = skin_vertex(model, joints, v).cast<float>();
  s.keyed_normals = smooth_normals(s.keyed, s.welded_triangles);
  s.frame_normals = smooth_normals(positions, s.welded_triangles);
  std::vector<Eigen::Vector3f> d, n, t;
  for (State::Primitive& p : s.primitives) {
    if (!p.deformed || p.same_as >= 0) continue;
    d.assign(p.listed.size(), Eigen::Vector3f::Zero());
    n.assign(p.normals.empty() ? 0 : p.listed.size(), Eigen::Vector3f::Zero());
    t.assign(p.tangents.empty() ? 0 : p.listed.size(), Eigen::Vector3f::Zero());
    const float inf = std::numeric_limits<float>::infinity();
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(inf), hi = Eigen::Vector3f::Constant(-inf);
    if (p.listed.size() < p.count) lo = hi = Eigen::Vector3f::Zero();
    for (std::size_t k = 0; k < p.listed.size(); ++k) {
      const std::uint32_t i = p.listed[k], v = p.source[i];
      Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
      for (int e = 0; e < 4; ++e) {
        const double w = model.vertex_weights[v][e];
        if (w != 0) m += w * joints[model.vertex_joints[v][e]];
      }
      const Mat3 a = m.topLeftCorner<3, 3>();
      const double det = a.determinant();
      if (!(std::abs(det) > 1e-12 * std::pow(a.cwiseAbs().maxCoeff(), 3))) {
        s.refuse("mesh " + std::to_string(p.mesh) + " primitive " + std::to_string(p.index) + " vertex " +
                 std::to_string(i) + ": its skinning matrix at " + format_number(time) + " s (frame " +
                 std::to_string(s.next_frame) +
                 ") is singular (its joints' weighted rotations cancel), "
                 "so no morph target under the skin can move it; bake to .pc2");
      }
      const Mat3 a_inv = a.inverse();
      if (s.animated[v]) {
        const Vec3 keyed = (m * model.bind_positions[v].homogeneous()).head<3>();
        d[k] = (a_inv * (positions[v].cast<double>() - keyed)).cast<float>();
      }
      lo = lo.cwiseMin(d[k]);
      hi = hi.cwiseMax(d[k]);
      const Eigen::Vector3f& n0 = s.keyed_normals[s.rep[v]];
      const Eigen::Vector3f& n1 = s.frame_normals[s.rep[v]];
      if (n0 == n1) continue;
      const Eigen::Quaterniond turn = Eigen::Quaterniond::FromTwoVectors(n0.cast<double>(), n1.cast<double>());
      if (!p.normals.empty()) {
        const Vec3 local(p.normals[3 * i], p.normals[3 * i + 1], p.normals[3 * i + 2]);
        const Vec3 turned = (a_inv * (turn * (a * local).normalized())).normalized();
        n[k] = (turned - local).cast<float>();
      }
      if (!p.tangents.empty()) {
        const Vec3 local(p.tangents[4 * i], p.tangents[4 * i + 1], p.tangents[4 * i + 2]);
        const Vec3 turned = (a_inv * (turn * (a * local))).normalized();
        t[k] = (turned - local).cast<float>();
      }
    }
    p.lo.push_back(lo);
    p.hi.push_back(hi);
    if (p.listed.empty()) continue;
    p.positions.push_back(s.put(append, d.data(), d.size() * sizeof(Eigen::Vector3f)));
    if (!n.empty()) p.normals_blocks.push_back(s.put(append, n.data(), n.size() * sizeof(Eigen::Vector3f)));
    if (!t.empty()) p.tangents_blocks.push_back(s.put(append, t.data(), t.size() * sizeof(Eigen::Vector3f)));
  }
  resample_frame(s);
}

// The clip's channels at this frame's clip time (looped or held as the bake played it).
void resample_frame(State& s) {
  const double clip_time = s.skin->clip_time(s.next_frame / s.fps);
  for (State::Resampled& r : s.resampled) {
    Eigen::Vector4d value = channel_value(*r.channel, clip_time);
    const int width = r.channel->width();
    const std::size_t at = r.values.size();
    if (width == 4 && at >= 4) {  // on the side of the key before, so that slerp takes the short way
      double dot = 0;
      for (int c = 0; c < 4; ++c) dot += value[c] * r.values[at - 4 + c];
      if (dot < 0) value = -value;
    }
    for (int c = 0; c < width; ++c) r.values.push_back(static_cast<float>(value[c]));
  }
}

}  // namespace

GltfPassthrough::GltfPassthrough(const fs::path& source, const fs::path& out, const Mesh& rest,
                                 const std::vector<std::uint32_t>& animated, const BakeInfo& info)
    : s_(std::make_unique<State>()) {
  State& s = *s_;
  s.source = source;
  s.out = out;
  s.where = source.string() + ": ";
  s.frames = info.frame_count;
  s.fps = info.fps;
  s.body_moves = info.body_moves;
  s.skin = info.skinned;
  s.joints = info.skinned != nullptr ? info.character_joints : nullptr;
  if (const std::string ext = lower_extension(source); ext != "gltf" && ext != "glb") {
    // Any other format assimp reads: every mesh of the file, each on a node of its own (the rig's
    // carry the bake, the others stay where they are).
    std::optional<SurfaceGltf> converted =
        ext == "obj" ? obj_as_gltf(source, rest, info.warn)
                     : scene_as_gltf(read_scene_surface(source, info.source.mesh_name, info.warn), rest, source);
    if (!converted) fail(ErrorCategory::internal, s.where + "no surface to carry");
    // A skinned character read through assimp: made a glTF character, skeleton, skin and clips.
    if (s.skin != nullptr) add_skin(*converted, s.skin->model(), info.source.to_world);
    s.doc = std::move(converted->doc);
    s.given_sources = std::move(converted->sources);
    // The rig's meshes that do not bend follow a moving body with the ones that do, as the .pc2 shows.
    s.carry_still_meshes = ext != "obj";
  } else {
    s.doc = read_gltf_document(source);
    s.parts = info.source.parts;
    s.carry_still_meshes = io::several_mesh_names(info.source.mesh_name);
  }
  if (!s.doc.json.is_object()) s.bad("not a glTF document (its JSON is not an object)");
  check_compression(s);
  read_bytes(s);
  map_primitives(s, rest, animated);
  if (s.skin != nullptr) resample_clip(s);

  s.rest_world = rest.positions;
  s.rest_f.resize(rest.vertex_count());
  for (std::size_t v = 0; v < rest.vertex_count(); ++v) s.rest_f[v] = rest.positions[v].cast<float>();
  s.animated.assign(rest.vertex_count(), 0);
  for (const std::uint32_t v : animated) s.animated[v] = 1;
  weld(s, rest);
  s.rest_normals = smooth_normals(s.rest_f, s.welded_triangles);
  repair_normals(s, info.warn);
  // The vertices whose normal can change: on a welded face with a moving vertex.
  std::vector<char> moving_rep(rest.vertex_count(), 0), near(rest.vertex_count(), 0);
  for (const std::uint32_t v : animated) moving_rep[s.rep[v]] = 1;
  const auto& t = s.welded_triangles;
  for (std::size_t k = 0; k + 2 < t.size(); k += 3) {
    if (moving_rep[t[k]] || moving_rep[t[k + 1]] || moving_rep[t[k + 2]])
      near[t[k]] = near[t[k + 1]] = near[t[k + 2]] = 1;
  }
  // Every primitive of a deformed mesh gets targets (glTF: the same count on each); those of a
  // primitive where nothing moves are zeros.
  for (const std::size_t m : s.deformed_meshes) {
    for (State::Primitive& prim : s.primitives) {
      if (prim.mesh != m) continue;
      prim.deformed = true;
      for (std::uint32_t i = 0; i < prim.count; ++i) {
        const std::uint32_t v = prim.source[i];
        if (s.animated[v] || near[s.rep[v]]) prim.listed.push_back(i);
      }
    }
  }
}

GltfPassthrough::~GltfPassthrough() = default;

std::unique_ptr<GltfPassthrough> GltfPassthrough::open(const fs::path& source, const fs::path& out, const Mesh& rest,
                                                       const std::vector<std::uint32_t>& animated,
                                                       const BakeInfo& info) {
  if (!is_passthrough_source(source) && info.skinned == nullptr) return nullptr;
  if (lower_extension(source) == "obj") {
    // Only an OBJ with something to carry: a plain one keeps the plain .glb (vertex order as read).
    const std::string text = read_file(source);
    bool surface = false;
    std::istringstream in(text);
    for (std::string line; !surface && std::getline(in, line);) {
      std::istringstream words(line);
      std::string first, word;
      words >> first;
      int count = 1;
      while (count < 7 && words >> word) ++count;
      // UVs, normals, materials, or a vertex colour (`v x y z r g b`): what obj_as_gltf carries.
      surface = first == "vt" || first == "vn" || first == "usemtl" || (first == "v" && count >= 7);
    }
    if (!surface) return nullptr;
  }
  return std::make_unique<GltfPassthrough>(source, out, rest, animated, info);
}

std::size_t GltfPassthrough::deformed_primitives() const {
  return static_cast<std::size_t>(std::count_if(s_->primitives.begin(), s_->primitives.end(),
                                                [](const State::Primitive& p) { return p.deformed && p.same_as < 0; }));
}

std::uint64_t GltfPassthrough::fixed_bytes() const {
  std::uint64_t bytes = 0;
  for (const std::string& b : s_->buffer_bytes) bytes += b.size() + 16;
  for (const State::Image& i : s_->images) bytes += i.bytes.size() + 4;
  for (const State::Primitive& p : s_->primitives)
    bytes += 4 * p.listed.size() + (p.normals_repaired ? 4 * p.normals.size() : 0);
  const std::uint64_t f = static_cast<std::uint64_t>(s_->frames);
  for (const State::Resampled& r : s_->resampled) bytes += 4 * r.channel->width() * f;
  if (s_->joints != nullptr) bytes += 40 * f * s_->joints->joints().size();  // their keys, at most
  return bytes + 12 * f + 28 * f * s_->shown.size();
}

std::uint64_t GltfPassthrough::json_bytes() const {
  return s_->doc.json.dump().size();
}

std::uint64_t GltfPassthrough::bytes_per_frame() const {
  std::uint64_t bytes = 0;
  for (const State::Primitive& p : s_->primitives) {
    if (!p.deformed || p.same_as >= 0) continue;
    bytes += 12 * p.listed.size() * (1 + !p.normals.empty() + !p.tangents.empty());
  }
  return bytes;
}

void GltfPassthrough::start(const AppendBin& append) {
  State& s = *s_;
  for (const std::string& b : s.buffer_bytes) s.buffer_base.push_back(s.put(append, b.data(), b.size(), 16).offset);
  for (State::Image& i : s.images) i.block = s.put(append, i.bytes.data(), i.bytes.size());
  const std::uint64_t frames = static_cast<std::uint64_t>(s.frames);
  std::vector<float> times(frames);
  for (std::uint64_t k = 0; k < frames; ++k) {
    times[k] = static_cast<float>(static_cast<double>(k) / s.fps);
    if (k > 0 && !(times[k] > times[k - 1])) {
      fail(ErrorCategory::unsupported, s.out.string() + ": frame " + std::to_string(k) + " at " +
                                           std::to_string(s.fps) +
                                           " frames/s has the same float32 time as the frame before it");
    }
  }
  s.last_time = times.back();
  s.times = s.put(append, times.data(), frames * 4);
  std::vector<std::uint32_t> at(frames);
  for (std::uint64_t k = 0; k < frames; ++k) at[k] = static_cast<std::uint32_t>(k * frames + k);
  s.weight_indices = s.put(append, at.data(), frames * 4);
  const std::vector<float> ones(frames, 1.0f);
  s.weight_values = s.put(append, ones.data(), frames * 4);
  for (State::Primitive& p : s.primitives) {
    if (p.deformed && p.same_as < 0 && !p.listed.empty())
      p.listed_block = s.put(append, p.listed.data(), 4 * p.listed.size());
  }
}

void GltfPassthrough::frame(std::span<const Eigen::Vector3f> positions, const BodyPose& body, const AppendBin& append) {
  State& s = *s_;
  if (s.joints != nullptr) {
    resample_frame(s);
    ++s.next_frame;
    return;
  }
  if (s.skin != nullptr) {
    frame_under_skin(s, positions, append);
    ++s.next_frame;
    return;
  }
  s.frame_normals = smooth_normals(positions, s.welded_triangles);
  std::vector<Eigen::Vector3f> d, n, t;
  for (State::Primitive& p : s.primitives) {
    if (!p.deformed || p.same_as >= 0) continue;
    d.assign(p.listed.size(), Eigen::Vector3f::Zero());
    n.assign(p.normals.empty() ? 0 : p.listed.size(), Eigen::Vector3f::Zero());
    t.assign(p.tangents.empty() ? 0 : p.listed.size(), Eigen::Vector3f::Zero());
    // The bounds of the deltas the accessor holds: the listed ones, and zero for the vertices the
    // sparse accessor leaves out (none when every vertex is listed: then zero is no bound).
    const float inf = std::numeric_limits<float>::infinity();
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(inf), hi = Eigen::Vector3f::Constant(-inf);
    if (p.listed.size() < p.count) lo = hi = Eigen::Vector3f::Zero();
    for (std::size_t k = 0; k < p.listed.size(); ++k) {
      const std::uint32_t i = p.listed[k], v = p.source[i];
      if (s.animated[v] && positions[v] != s.rest_f[v]) {
        d[k] = (p.to_local * (positions[v].cast<double>() - s.rest_world[v])).cast<float>();
      }
      lo = lo.cwiseMin(d[k]);
      hi = hi.cwiseMax(d[k]);
      const Eigen::Vector3f& n0 = s.rest_normals[s.rep[v]];
      const Eigen::Vector3f& n1 = s.frame_normals[s.rep[v]];
      if (n0 == n1) continue;
      const Eigen::Quaterniond turn = Eigen::Quaterniond::FromTwoVectors(n0.cast<double>(), n1.cast<double>());
      if (!p.normals.empty()) {
        const Vec3 local(p.normals[3 * i], p.normals[3 * i + 1], p.normals[3 * i + 2]);
        const Vec3 world = (p.normal_to_world * local).normalized();
        const Vec3 turned = (p.to_world.transpose() * (turn * world)).normalized();
        n[k] = (turned - local).cast<float>();
      }
      if (!p.tangents.empty()) {
        const Vec3 local(p.tangents[4 * i], p.tangents[4 * i + 1], p.tangents[4 * i + 2]);
        const Vec3 turned = (p.to_local * (turn * (p.to_world * local))).normalized();
        t[k] = (turned - local).cast<float>();
      }
    }
    p.lo.push_back(lo);
    p.hi.push_back(hi);
    if (p.listed.empty()) continue;
    p.positions.push_back(s.put(append, d.data(), d.size() * sizeof(Eigen::Vector3f)));
    if (!n.empty()) p.normals_blocks.push_back(s.put(append, n.data(), n.size() * sizeof(Eigen::Vector3f)));
    if (!t.empty()) p.tangents_blocks.push_back(s.put(append, t.data(), t.size() * sizeof(Eigen::Vector3f)));
  }
  if (!s.body_moves) return;
  Affine b = Affine::Identity();
  b.translate(body.translation);
  b.rotate(body.rotation.normalized());
  for (State::Shown& shown : s.shown) {
    if (shown.follows_parent) continue;
    // L(t) = P⁻¹ · B · P · L: P⁻¹ B P is rigid (P a similarity), so L(t) keeps L's scale.
    const Affine m = shown.parent.inverse() * b * shown.parent;
    Eigen::JacobiSVD<Mat3> svd(m.linear(), Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Mat3 rot = svd.matrixU() * svd.matrixV().transpose();  // the rotation, rounding removed
    Eigen::Quaterniond q = (Eigen::Quaterniond(rot) * shown.local.r).normalized();
    const Vec3 tr = m * shown.local.t;
    if (!shown.rotations.empty()) {
      const std::size_t at = shown.rotations.size() - 4;
      const double dot = q.x() * shown.rotations[at] + q.y() * shown.rotations[at + 1] +
                         q.z() * shown.rotations[at + 2] + q.w() * shown.rotations[at + 3];
      if (dot < 0) q.coeffs() *= -1;
    }
    for (int c = 0; c < 3; ++c) shown.translations.push_back(static_cast<float>(tr[c]));
    for (const double c : {q.x(), q.y(), q.z(), q.w()}) shown.rotations.push_back(static_cast<float>(c));
  }
}

Json GltfPassthrough::finish(const AppendBin& append) {
  State& s = *s_;
  for (State::Shown& shown : s.shown) {
    if (!s.body_moves) break;
    if (shown.follows_parent) continue;
    shown.translation_block = s.put(append, shown.translations.data(), shown.translations.size() * 4);
    shown.rotation_block = s.put(append, shown.rotations.data(), shown.rotations.size() * 4);
  }
  for (State::Resampled& r : s.resampled) r.block = s.put(append, r.values.data(), r.values.size() * 4);
  Json json = s.doc.json;
  for (const char* key : {"bufferViews", "accessors", "animations", "meshes", "nodes"}) {
    if (!json.contains(key) || !json[key].is_array()) json[key] = Json::array();
  }
  // The input's bytes: every view re-pointed into the one buffer; images from files embedded.
  for (Json& view : json["bufferViews"]) {
    const std::uint64_t b = gltf_unsigned(view, "buffer", 0);
    view["buffer"] = 0;
    view["byteOffset"] = s.buffer_base.at(b) + gltf_unsigned(view, "byteOffset", 0);
  }
  auto add_view = [&](const BinBlock& block) {
    json["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", block.offset}, {"byteLength", block.length}});
    return json["bufferViews"].size() - 1;
  };
  auto add_accessor = [&](Json accessor) {
    json["accessors"].push_back(std::move(accessor));
    return json["accessors"].size() - 1;
  };
  for (const State::Image& i : s.images) {
    Json& image = json["images"][i.index];
    image.erase("uri");
    image["bufferView"] = add_view(i.block);
    image["mimeType"] = i.media_type;
  }
  // Repaired normals (repair_normals): the primitive's NORMAL accessor re-pointed at them, so no
  // accessor of the file holds the bad ones.
  for (State::Primitive& p : s.primitives) {
    if (!p.normals_repaired) continue;
    const Json& index = json["meshes"][p.mesh]["primitives"][p.index]["attributes"]["NORMAL"];
    Json& accessor = json["accessors"][index.get<std::size_t>()];
    accessor["bufferView"] = add_view(s.put(append, p.normals.data(), p.normals.size() * sizeof(float)));
    accessor.erase("byteOffset");
    accessor.erase("sparse");
    if (accessor.contains("min") || accessor.contains("max")) {
      Eigen::Vector3f lo = Eigen::Vector3f::Constant(1), hi = Eigen::Vector3f::Constant(-1);
      for (std::size_t i = 0; i + 2 < p.normals.size(); i += 3) {
        const Eigen::Vector3f n(p.normals[i], p.normals[i + 1], p.normals[i + 2]);
        lo = lo.cwiseMin(n);
        hi = hi.cwiseMax(n);
      }
      accessor["min"] = vec3_json(lo);
      accessor["max"] = vec3_json(hi);
    }
  }
  if (s.joints != nullptr) {
    std::vector<ResampledChannel> resampled;
    for (const State::Resampled& r : s.resampled) resampled.push_back({r.node, r.path, r.block});
    std::vector<PrimitiveSource> primitives;
    for (const State::Primitive& p : s.primitives)
      if (p.source.size() == p.count) primitives.push_back({p.mesh, p.index, &p.source});
    const AppendBin put = [&](const void* data, std::size_t bytes) { return s.put(append, data, bytes); };
    add_character_joints(json, *s.joints, resampled, {s.frames, s.fps, s.times, s.last_time}, primitives, put, s.where);
    return json;
  }
  if (s.shown.empty()) return json;  // nothing moves: the input as it was
  const std::size_t frames = static_cast<std::size_t>(s.frames);
  const std::size_t times = add_accessor({{"bufferView", add_view(s.times)},
                                          {"componentType", kFloat},
                                          {"count", frames},
                                          {"type", "SCALAR"},
                                          {"min", Json::array({0.0})},
                                          {"max", Json::array({double{s.last_time}})}});
  const std::size_t weights =
      add_accessor({{"componentType", kFloat},
                    {"count", frames * frames},
                    {"type", "SCALAR"},
                    {"sparse",
                     {{"count", frames},
                      {"indices", {{"bufferView", add_view(s.weight_indices)}, {"componentType", kUint}}},
                      {"values", {{"bufferView", add_view(s.weight_values)}}}}}});

  Json names = Json::array();
  for (std::size_t k = 0; k < frames; ++k)
    names.push_back(obj_sequence_path("frame", static_cast<int>(k), s.frames).stem().string());
  for (State::Primitive& p : s.primitives) {
    if (!p.deformed) continue;
    if (p.same_as >= 0) {
      const State::Primitive& e = s.primitives[static_cast<std::size_t>(p.same_as)];
      json["meshes"][p.mesh]["primitives"][p.index]["targets"] =
          json["meshes"][e.mesh]["primitives"][e.index]["targets"];
      continue;
    }
    const std::size_t listed_view = p.listed.empty() ? 0 : add_view(p.listed_block);
    auto target = [&](const std::vector<BinBlock>& blocks, std::size_t k) {
      Json a = {{"componentType", kFloat}, {"count", p.count}, {"type", "VEC3"}};
      if (!p.listed.empty()) {
        a["sparse"] = {{"count", p.listed.size()},
                       {"indices", {{"bufferView", listed_view}, {"componentType", kUint}}},
                       {"values", {{"bufferView", add_view(blocks[k])}}}};
      }
      return a;
    };
    Json targets = Json::array();
    for (std::size_t k = 0; k < frames; ++k) {
      Json position = target(p.positions, k);
      position["min"] = vec3_json(p.lo[k]);
      position["max"] = vec3_json(p.hi[k]);
      Json one = {{"POSITION", add_accessor(std::move(position))}};
      if (!p.normals.empty()) one["NORMAL"] = add_accessor(target(p.normals_blocks, k));
      if (!p.tangents.empty()) one["TANGENT"] = add_accessor(target(p.tangents_blocks, k));
      targets.push_back(std::move(one));
    }
    json["meshes"][p.mesh]["primitives"][p.index]["targets"] = std::move(targets);
  }
  for (const std::size_t m : s.deformed_meshes) {
    Json& mesh = json["meshes"][m];
    mesh["weights"] = std::vector<double>(frames, 0.0);
    if (!mesh.contains("extras")) mesh["extras"] = Json::object();
    if (mesh["extras"].is_object()) mesh["extras"]["targetNames"] = names;
  }

  Json animation = {{"samplers", Json::array({{{"input", times}, {"output", weights}, {"interpolation", "LINEAR"}}})},
                    {"channels", Json::array()}};
  for (const State::Shown& shown : s.shown) {
    if (shown.morphs)
      animation["channels"].push_back({{"sampler", 0}, {"target", {{"node", shown.node}, {"path", "weights"}}}});
    // An animated node (its weights too) may not have a matrix: given as translation, rotation
    // and scale (exact, or refused in map_primitives).
    Json& node = json["nodes"][shown.node];
    if (shown.local.from_matrix) {
      node.erase("matrix");
      node["translation"] = {shown.local.t.x(), shown.local.t.y(), shown.local.t.z()};
      node["rotation"] = {shown.local.r.x(), shown.local.r.y(), shown.local.r.z(), shown.local.r.w()};
      node["scale"] = {shown.local.s.x(), shown.local.s.y(), shown.local.s.z()};
    }
    if (!s.body_moves || shown.follows_parent) continue;
    const std::size_t tr = add_accessor({{"bufferView", add_view(shown.translation_block)},
                                         {"componentType", kFloat},
                                         {"count", frames},
                                         {"type", "VEC3"}});
    const std::size_t rot = add_accessor({{"bufferView", add_view(shown.rotation_block)},
                                          {"componentType", kFloat},
                                          {"count", frames},
                                          {"type", "VEC4"}});
    for (const auto& [accessor, path] : {std::pair{tr, "translation"}, std::pair{rot, "rotation"}}) {
      animation["samplers"].push_back({{"input", times}, {"output", accessor}, {"interpolation", "LINEAR"}});
      animation["channels"].push_back(
          {{"sampler", animation["samplers"].size() - 1}, {"target", {{"node", shown.node}, {"path", path}}}});
    }
  }
  for (const State::Resampled& r : s.resampled) {
    const bool rotation = r.path == ChannelPath::rotation;
    const std::size_t values = add_accessor({{"bufferView", add_view(r.block)},
                                             {"componentType", kFloat},
                                             {"count", frames},
                                             {"type", rotation ? "VEC4" : "VEC3"}});
    animation["samplers"].push_back({{"input", times}, {"output", values}, {"interpolation", "LINEAR"}});
    const char* path = rotation ? "rotation" : r.path == ChannelPath::scale ? "scale" : "translation";
    animation["channels"].push_back(
        {{"sampler", animation["samplers"].size() - 1}, {"target", {{"node", r.node}, {"path", path}}}});
  }
  std::string name = "sweep bake";
  for (int k = 2;; ++k) {
    bool taken = false;
    for (const Json& a : json["animations"]) taken = taken || (a.is_object() && a.value("name", "") == name);
    if (!taken) break;
    name = "sweep bake " + std::to_string(k);
  }
  animation["name"] = name;
  json["animations"].push_back(std::move(animation));
  return json;
}

}  // namespace sweep::assets::detail
