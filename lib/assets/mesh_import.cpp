// The import of mesh_io.h: read_scene_mesh and read_mesh (check the file, then choose the reader by
// extension), and assimp for PLY, glTF/glb and every other format it reads, welded by exact
// position where the format has no shared vertex list; one mesh of a scene of several taken by its
// node (NodeMeshes), the same way for read_scene_surface. The only file that sees assimp.
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <assimp/Importer.hpp>
#include <bit>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "sweep/assets/assimp_placement.h"
#include "sweep/assets/gltf_document.h"
#include "sweep/assets/mesh_checks.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/assets/mesh_io_detail.h"
#include "sweep/assets/mesh_surface.h"
#include "sweep/core/error.h"
#include "sweep/core/fp_environment.h"
#include "sweep/core/hash.h"
#include "sweep/core/text.h"
#include "sweep/io/mesh_names.h"
#include "sweep/io/read_file.h"

using sweep::io::read_file;

namespace sweep::assets {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using detail::bad;

// One line of text for an error message: libraries report with embedded newlines.
std::string one_line(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      out += c;
    }
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// Missing, not a regular file, unreadable or empty: each gets its own message.
void check_input_file(const fs::path& path) {
  const std::string source = path.string();
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) bad(source, "no such file");
  if (fs::is_directory(st)) bad(source, "is a directory, not a file");
  // A FIFO or a device would block the reader forever or never end: only regular files are read.
  if (!fs::is_regular_file(st)) bad(source, "is not a regular file (a FIFO, a device or a socket)");
  std::ifstream in(path, std::ios::binary);
  if (!in) bad(source, std::string("cannot open: ") + std::strerror(errno));
  if (in.peek() == std::ifstream::traits_type::eof()) bad(source, "empty file");
}

// ---- assimp: PLY, glTF/glb (kept as stored) and everything else (welded) ----

using detail::apply;
using detail::key_of;
using detail::PositionKey;
using detail::PositionKeyHash;
using detail::to_transform;
using detail::Transform;

// World transform of each mesh: that of the first node referring to it in depth-first order
// (identity when no node does). Instances (one mesh under several nodes) are not duplicated.
void collect_transforms(const aiNode* node, const Transform& parent, std::vector<Transform>& transforms,
                        std::vector<bool>& seen) {
  const Transform world = parent * to_transform(node->mTransformation);
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    const unsigned m = node->mMeshes[i];
    if (m < transforms.size() && !seen[m]) {
      transforms[m] = world;
      seen[m] = true;
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) {
    collect_transforms(node->mChildren[c], world, transforms, seen);
  }
}

// One mesh of the scene as the tools name it: a node showing importer meshes.
struct NodeMeshes {
  std::string name, mesh_name;
  Transform world;
  std::vector<unsigned> parts;
};

// The name of a node's mesh: its parts' common name, or the glTF mesh's name behind its
// primitives' ("Tail-0", "Tail-1" → "Tail"); "" when they differ.
std::string common_mesh_name(const aiScene* scene, const std::vector<unsigned>& parts) {
  auto name_of = [&](unsigned m, bool strip) {
    std::string n = scene->mMeshes[m]->mName.C_Str();
    const std::size_t dash = n.rfind('-');
    if (strip && dash != std::string::npos && dash + 1 < n.size() &&
        n.find_first_not_of("0123456789", dash + 1) == std::string::npos) {
      n.resize(dash);
    }
    return n;
  };
  for (const bool strip : {false, true}) {
    const std::string first = name_of(parts.front(), strip);
    bool same = true;
    for (const unsigned m : parts) same = same && name_of(m, strip) == first;
    if (same && (!strip || parts.size() > 1)) return first;
  }
  return "";
}

void collect_nodes(const aiScene* scene, const aiNode* node, const Transform& parent, std::vector<NodeMeshes>& out) {
  const Transform world = parent * to_transform(node->mTransformation);
  NodeMeshes here{node->mName.C_Str(), "", world, {}};
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    if (node->mMeshes[i] < scene->mNumMeshes) here.parts.push_back(node->mMeshes[i]);
  }
  if (!here.parts.empty()) {
    here.mesh_name = common_mesh_name(scene, here.parts);
    out.push_back(std::move(here));
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) collect_nodes(scene, node->mChildren[c], world, out);
}

// An importer mesh and where it goes.
struct Placed {
  unsigned mesh;
  Transform transform;
};

// The whole file: every importer mesh in order, placed by the first node showing it.
std::vector<Placed> whole_file(const aiScene* scene) {
  std::vector<Transform> transforms(scene->mNumMeshes, Transform::Identity());
  std::vector<bool> seen(scene->mNumMeshes, false);
  if (scene->mRootNode != nullptr) {
    collect_transforms(scene->mRootNode, Transform::Identity(), transforms, seen);
  }
  std::vector<Placed> placed;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) placed.push_back({m, transforms[m]});
  return placed;
}

std::vector<Placed> placed_of(const NodeMeshes& node) {
  std::vector<Placed> placed;
  for (const unsigned m : node.parts) placed.push_back({m, node.world});
  return placed;
}

// `bytes` given: the file's content already in memory (PLY, read from there so that a byte order
// mark can be skipped and the body checked first), with `hint` its extension; else the file
// `source` is read by assimp itself (glTF may refer to other files beside it).
const aiScene* import_scene(Assimp::Importer& importer, const std::string& source, std::string_view bytes = {},
                            const char* hint = "") {
  // No post-processing: it keeps the stored vertices, their order and count, and the polygons.
  const aiScene* scene = nullptr;
  {
    const QuietFpEnvironment quiet;
    scene =
        bytes.empty() ? importer.ReadFile(source, 0) : importer.ReadFileFromMemory(bytes.data(), bytes.size(), 0, hint);
  }
  if (scene == nullptr) bad(source, "cannot parse: " + one_line(importer.GetErrorString()));
  if (scene->mNumMeshes == 0 || scene->mMeshes == nullptr) bad(source, "no vertices");
  return scene;
}

// The importer meshes `placed`, concatenated: their vertices as stored (`weld` false) or welded by
// exact position per importer mesh.
Mesh assemble(const aiScene* scene, const std::vector<Placed>& placed, bool weld, const std::string& source) {
  Mesh mesh;
  std::size_t face = 0;
  for (const auto& [m, t] : placed) {
    const aiMesh* am = scene->mMeshes[m];
    const std::size_t base = mesh.positions.size();
    if (!weld) {
      for (unsigned i = 0; i < am->mNumVertices; ++i) mesh.positions.push_back(apply(t, am->mVertices[i]));
    }
    std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> welded;
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& af = am->mFaces[f];
      if (af.mNumIndices < 3) continue;  // points and lines are not surface
      for (unsigned k = 0; k < af.mNumIndices; ++k) {
        const unsigned v = af.mIndices[k];
        if (v >= am->mNumVertices) {
          bad(source, "face " + std::to_string(face) + " uses vertex " + std::to_string(v) + " of mesh " +
                          std::to_string(m) + ", out of range (that mesh has " + std::to_string(am->mNumVertices) +
                          " vertices)");
        }
        if (!weld) {
          mesh.face_vertices.push_back(static_cast<std::uint32_t>(base + v));
          continue;
        }
        const Vec3 p = apply(t, am->mVertices[v]);
        const auto [it, inserted] = welded.try_emplace(key_of(p), static_cast<std::uint32_t>(mesh.positions.size()));
        if (inserted) mesh.positions.push_back(p);
        mesh.face_vertices.push_back(it->second);
      }
      mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_vertices.size()));
      ++face;
    }
  }
  return mesh;
}

// The vertex count assemble gives, without building the mesh: listing a file's meshes (and picking
// the largest) must not hold a copy of every one.
std::size_t assembled_vertex_count(const aiScene* scene, const std::vector<Placed>& placed, bool weld) {
  std::size_t count = 0;
  for (const auto& [m, t] : placed) {
    const aiMesh* am = scene->mMeshes[m];
    if (!weld) {
      count += am->mNumVertices;
      continue;
    }
    std::unordered_set<PositionKey, PositionKeyHash> welded;
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& af = am->mFaces[f];
      if (af.mNumIndices < 3) continue;
      for (unsigned k = 0; k < af.mNumIndices; ++k) {
        if (af.mIndices[k] < am->mNumVertices) welded.insert(key_of(apply(t, am->mVertices[af.mIndices[k]])));
      }
    }
    count += welded.size();
  }
  return count;
}

// The node `name` names (its own name first, else its mesh's), or -1; Error(bad_input) when it
// names several. `list` says the file's meshes for the message.
int find_named(const std::vector<NodeMeshes>& nodes, const std::string& name, const std::string& source,
               const std::function<std::string()>& list) {
  for (const bool by_node : {true, false}) {
    std::vector<int> hits;
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      if ((by_node ? nodes[k].name : nodes[k].mesh_name) == name) hits.push_back(static_cast<int>(k));
    }
    if (hits.size() > 1) {
      bad(source, std::to_string(hits.size()) + (by_node ? " nodes are named '" : " nodes show the mesh '") + name +
                      "', so it does not say which mesh to take (rename one); its meshes: " + list());
    }
    if (!hits.empty()) return hits.front();
  }
  return -1;
}

// The nodes a list of names takes (mesh_io.h: several meshes as one), or every node for kAllMeshes:
// each name found as find_named finds one, no node twice, each node's own name finding it again
// (the rig records those names); in the order named, or with `file_order` in the file's.
std::vector<int> several_nodes(const std::vector<NodeMeshes>& nodes, const std::string& joined, bool file_order,
                               const std::string& source, const std::function<std::string()>& list) {
  std::vector<int> chosen;
  if (joined == kAllMeshes) {
    for (std::size_t k = 0; k < nodes.size(); ++k) chosen.push_back(static_cast<int>(k));
  } else {
    const std::vector<std::string> names = io::split_mesh_names(joined);
    for (const std::string& name : names) {
      const int k = find_named(nodes, name, source, list);
      if (k < 0) {
        bad(source, "no mesh is named '" + name + "' (one of the " + std::to_string(names.size()) +
                        " meshes asked for: " + io::quoted_mesh_names(joined) + "); its meshes: " + list());
      }
      for (std::size_t e = 0; e < chosen.size(); ++e) {
        if (chosen[e] == k) {
          bad(source, "'" + names[e] + "' and '" + name + "' name the same mesh (node '" +
                          nodes[static_cast<std::size_t>(k)].name + "'); name each mesh once");
        }
      }
      chosen.push_back(k);
    }
  }
  for (const int k : chosen) {
    if (find_named(nodes, nodes[static_cast<std::size_t>(k)].name, source, list) != k) {
      bad(source, "the mesh taken, '" + nodes[static_cast<std::size_t>(k)].name +
                      "', has a name that another mesh's node or mesh has; rename one");
    }
  }
  if (file_order) std::sort(chosen.begin(), chosen.end());
  return chosen;
}

MeshUnit unit_of(const aiScene* scene) {
  MeshUnit unit;
  const aiMetadata* meta = scene->mMetaData;
  for (unsigned k = 0; meta != nullptr && k < meta->mNumProperties; ++k) {
    const std::string key = meta->mKeys[k].C_Str();
    const aiMetadataEntry& e = meta->mValues[k];
    double value = 0;
    if (e.mType == AI_DOUBLE)
      value = *static_cast<const double*>(e.mData);
    else if (e.mType == AI_FLOAT)
      value = *static_cast<const float*>(e.mData);
    else
      continue;
    if (key == "UnitScaleFactor") unit.unit_scale_factor = value;
    if (key == "OriginalUnitScaleFactor") unit.original_unit_scale_factor = value;
  }
  return unit;
}

// The metadata entry `key` of the scene as a whole number (FBX's UpAxis is an int32), or nullopt.
std::optional<long long> metadata_integer(const aiScene* scene, const char* key) {
  const aiMetadata* meta = scene->mMetaData;
  for (unsigned k = 0; meta != nullptr && k < meta->mNumProperties; ++k) {
    if (std::string_view(meta->mKeys[k].C_Str()) != key) continue;
    const aiMetadataEntry& e = meta->mValues[k];
    if (e.mType == AI_INT32) return *static_cast<const std::int32_t*>(e.mData);
    if (e.mType == AI_UINT64) return static_cast<long long>(*static_cast<const std::uint64_t*>(e.mData));
  }
  return std::nullopt;
}

// A Collada file's <asset><up_axis> (X_UP, Y_UP or Z_UP), from its text; "" when it has none.
std::string collada_up_axis(const fs::path& path) {
  const std::string text = read_file(path);
  const std::size_t open = text.find("<up_axis>");
  if (open == std::string::npos) return "";
  const std::size_t begin = open + 9, close = text.find("</up_axis>", begin);
  if (close == std::string::npos || close - begin > 64) return "";
  std::string axis = text.substr(begin, close - begin);
  std::erase_if(axis, [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; });
  return axis == "X_UP" || axis == "Y_UP" || axis == "Z_UP" ? axis : "";
}

// The formats that are Z up by their own convention (the program or engine they come from), with
// the words a person reads. Some of assimp's readers leave the coordinates as stored (Blender's,
// Source's .smd, trueSpace's .cob), others turn the whole scene to +Y up in its root node (the
// Quake family's .md2, .md3, .mdc, .mdl, .md5mesh, .iqm and 3ds Max's .3ds, .ase): taken through
// the root transform, as file_up does, the convention gives the right up either way, never a turn
// twice.
struct FormatUp {
  const char* ext;
  const char* why;
};
constexpr FormatUp kZUpFormats[] = {
    {"blend", "Blender files are Z up by Blender's convention"},
    {"smd", "Source's .smd is Z up by the engine's convention"},
    {"cob", "trueSpace's .cob is Z up by its convention"},
    {"scn", "trueSpace's .scn is Z up by its convention"},
    {"md2", "Quake II's .md2 is Z up by the engine's convention"},
    {"md3", "Quake III's .md3 is Z up by the engine's convention"},
    {"mdc", "Return to Castle Wolfenstein's .mdc is Z up by the engine's convention"},
    {"mdl", "an .mdl (Quake, Half-Life, 3D GameStudio) is Z up by the engine's convention"},
    {"md5mesh", "Doom 3's .md5mesh is Z up by the engine's convention"},
    {"iqm", "Inter-Quake's .iqm is Z up by the Quake convention"},
    {"3ds", "3ds Max's .3ds is Z up by its convention"},
    {"ase", "3ds Max's .ase is Z up by its convention"},
};

// The file's up direction in world space (mesh_io.h: FileUp). The scene's root transform holds the
// reader's own axis turn (Collada's, the Quake formats'), so the file's stated axis, or its
// format's, is taken through it.
FileUp file_up(const aiScene* scene, const std::string& ext, const fs::path& path) {
  FileUp up;
  if (ext == "gltf" || ext == "glb") {
    up.stated = true;
    up.why = "glTF is +Y up by its specification";
    return up;
  }
  Vec3 file_axis = Vec3::Zero();
  if (const std::optional<long long> axis = metadata_integer(scene, "UpAxis"); axis && *axis >= 0 && *axis <= 2) {
    const long long sign = metadata_integer(scene, "UpAxisSign").value_or(1) < 0 ? -1 : 1;
    file_axis = static_cast<double>(sign) * Vec3::Unit(static_cast<int>(*axis));
    up.why = std::string(ext == "fbx" ? "the FBX file's GlobalSettings say" : "the file says") + " UpAxis " +
             std::to_string(*axis) + ", UpAxisSign " + (sign > 0 ? "1" : "-1");
  } else if (ext == "dae") {
    const std::string stated = collada_up_axis(path);
    file_axis = Vec3::Unit(stated.empty() ? 1 : stated[0] - 'X');
    up.why = stated.empty() ? "the Collada file has no <up_axis>, which is then Y_UP by its specification"
                            : "the Collada file's <up_axis> is " + stated;
  } else {
    const auto* format =
        std::find_if(std::begin(kZUpFormats), std::end(kZUpFormats), [&](const FormatUp& f) { return ext == f.ext; });
    if (format == std::end(kZUpFormats)) return up;
    file_axis = Vec3::UnitZ();
    up.why = format->why;
  }
  up.stated = true;
  const Transform root =
      scene->mRootNode != nullptr ? to_transform(scene->mRootNode->mTransformation) : Transform::Identity();
  const Vec3 world = root.block<3, 3>(0, 0) * file_axis;
  if (!(world.norm() > 0) || !world.allFinite()) {
    up = FileUp{};
    up.why = "the file's up axis does not survive its root transform: +Y taken";
    return up;
  }
  up.direction = world.normalized();
  if (!root.block<3, 3>(0, 0).isIdentity(1e-12)) {
    up.why += ", which the reader turned to " + direction_name(up.direction) + " with the scene";
  }
  return up;
}

// assimp numbers a glTF's importer meshes (one a primitive) in the order its scene reaches the
// meshes, not the file's: a mesh listed second but shown first is its mesh 0. This gives each
// importer mesh the file's number, its primitive counted over the file's meshes in order (what the
// .glb passthrough indexes), by walking the file's scene and assimp's node tree side by side:
// assimp keeps the scene's nodes and their children in the file's order, and gives a node its
// mesh's primitives in order. Empty when the two do not line up (the passthrough's own position
// check then refuses what it cannot map).
constexpr unsigned kUnnumbered = UINT_MAX;
std::vector<unsigned> gltf_primitive_numbers(const aiScene* scene, const nlohmann::json& doc) {
  const auto array = [](const Json& obj, const char* key) -> const Json* {
    const auto it = obj.is_object() ? obj.find(key) : obj.end();
    return obj.is_object() && it != obj.end() && it->is_array() ? &*it : nullptr;
  };
  const Json* meshes = array(doc, "meshes");
  const Json* scenes = array(doc, "scenes");
  if (meshes == nullptr || scenes == nullptr || scene->mRootNode == nullptr) return {};
  std::vector<unsigned> first;  // each file mesh's first primitive's number
  unsigned count = 0;
  for (const Json& m : *meshes) {
    first.push_back(count);
    const Json* primitives = array(m, "primitives");
    count += primitives != nullptr ? static_cast<unsigned>(primitives->size()) : 0;
  }
  const std::uint64_t which = detail::gltf_unsigned(doc, "scene", 0);
  const Json* roots = which < scenes->size() ? array((*scenes)[which], "nodes") : nullptr;
  if (roots == nullptr) return {};
  std::vector<unsigned> number(scene->mNumMeshes, kUnnumbered);
  bool lined_up = true;
  std::function<void(const Json&, const aiNode*)> pair = [&](const Json& index, const aiNode* ai) {
    const Json* node = detail::gltf_element(doc, "nodes", index);
    const Json* mesh =
        node != nullptr && node->contains("mesh") ? detail::gltf_element(doc, "meshes", (*node)["mesh"]) : nullptr;
    const Json* primitives = mesh != nullptr ? array(*mesh, "primitives") : nullptr;
    const Json* children = node != nullptr ? array(*node, "children") : nullptr;
    lined_up = lined_up && node != nullptr && ai->mNumMeshes == (primitives != nullptr ? primitives->size() : 0) &&
               ai->mNumChildren == (children != nullptr ? children->size() : 0);
    if (!lined_up) return;
    for (unsigned k = 0; k < ai->mNumMeshes; ++k) {
      const unsigned n = first[(*node)["mesh"].get<std::size_t>()] + k;
      lined_up = lined_up && ai->mMeshes[k] < number.size() &&
                 (number[ai->mMeshes[k]] == kUnnumbered || number[ai->mMeshes[k]] == n);
      if (lined_up) number[ai->mMeshes[k]] = n;
    }
    for (unsigned c = 0; c < ai->mNumChildren && lined_up; ++c) pair((*children)[c], ai->mChildren[c]);
  };
  // One root node is assimp's root; several hang under a root of its own.
  if (roots->size() == 1) {
    pair((*roots)[0], scene->mRootNode);
  } else if (roots->size() == scene->mRootNode->mNumChildren && scene->mRootNode->mNumMeshes == 0) {
    for (unsigned c = 0; c < scene->mRootNode->mNumChildren; ++c) pair((*roots)[c], scene->mRootNode->mChildren[c]);
  } else {
    lined_up = false;
  }
  if (!lined_up || std::find(number.begin(), number.end(), kUnnumbered) != number.end()) return {};
  return number;
}

// `parts` (importer meshes) by the file's numbers, or as they are when there are none.
std::vector<unsigned> renumbered(std::vector<unsigned> parts, const std::vector<unsigned>& numbers) {
  if (!numbers.empty())
    for (unsigned& p : parts) p = numbers[p];
  return parts;
}

// The formats read through assimp whose meshes have no names of their own: one mesh.
bool names_meshes(const std::string& ext) {
  return ext != "ply" && ext != "stl";
}

// `gltf`: a glTF's JSON, whose numbering SceneMesh::parts then follows (else assimp's).
SceneMesh read_with_assimp(const std::string& source, bool weld, const std::string& name, MeshPick pick,
                           bool named_format, std::string_view bytes = {}, const char* hint = "",
                           const nlohmann::json* gltf = nullptr, bool file_order = false) {
  const fs::path source_path = bytes.empty() ? fs::path(source) : fs::path();  // PLY from memory states no up
  Assimp::Importer importer;
  const aiScene* scene = import_scene(importer, source, bytes, hint);
  const std::vector<unsigned> numbers =
      gltf != nullptr ? gltf_primitive_numbers(scene, *gltf) : std::vector<unsigned>{};
  SceneMesh out;
  out.unit = unit_of(scene);
  if (!source_path.empty()) out.up = file_up(scene, lower_extension(source_path), source_path);
  std::vector<NodeMeshes> nodes;
  if (named_format && scene->mRootNode != nullptr) collect_nodes(scene, scene->mRootNode, Transform::Identity(), nodes);
  if (!named_format && !name.empty()) {
    bad(source, "holds one mesh with no name (the format has none), so there is no " + asked_meshes(name) + " to take");
  }
  for (const NodeMeshes& n : nodes) {
    out.meshes.push_back({n.name, n.mesh_name, assembled_vertex_count(scene, placed_of(n), weld)});
  }
  if (nodes.empty() || (name.empty() && pick == MeshPick::whole_file)) {
    if (!name.empty()) bad(source, "no node shows a mesh, so there is no " + asked_meshes(name) + " to take");
    // (The meshes are listed all the same: a tool says the whole file was read, of which meshes,
    // and refuses points in "the" mesh's own space.)
    const std::vector<Placed> placed = whole_file(scene);
    out.mesh = assemble(scene, placed, weld, source);
    if (!numbers.empty()) {  // assimp's order, by the file's numbers
      for (const Placed& p : placed) out.parts.push_back(numbers[p.mesh]);
    }
    return out;
  }
  const auto list = [&] { return list_scene_meshes(out.meshes); };
  // (Every mesh as kAllMeshes takes them, in the file's order; only when each node's name finds it
  // again, as a rig records them: else the largest, as before.)
  const bool every =
      name.empty() && pick == MeshPick::every_mesh && nodes.size() > 1 &&
      std::all_of(nodes.begin(), nodes.end(), [&](const NodeMeshes& n) {
        return std::count_if(nodes.begin(), nodes.end(), [&](const NodeMeshes& o) { return o.name == n.name; }) == 1;
      });
  if (every || io::several_mesh_names(name) || (name == kAllMeshes && find_named(nodes, name, source, list) < 0)) {
    const std::vector<int> chosen =
        several_nodes(nodes, every ? std::string(kAllMeshes) : name, every || file_order, source, list);
    std::vector<Placed> placed;
    std::vector<std::string> names;
    for (const int k : chosen) {
      const NodeMeshes& n = nodes[static_cast<std::size_t>(k)];
      for (const unsigned m : n.parts) placed.push_back({m, n.world});
      names.push_back(n.name);
      const std::vector<unsigned> parts = renumbered(n.parts, numbers);
      out.parts.insert(out.parts.end(), parts.begin(), parts.end());
    }
    out.mesh = assemble(scene, placed, weld, source);
    out.name = io::join_mesh_names(names);  // world space: to_world stays the identity
    out.every = every;
    return out;
  }
  int chosen = 0;
  if (!name.empty()) {
    chosen = find_named(nodes, name, source, list);
    if (chosen < 0) bad(source, "no mesh is named '" + name + "'; its meshes: " + list());
  } else {
    for (std::size_t k = 1; k < out.meshes.size(); ++k) {
      if (out.meshes[k].vertex_count > out.meshes[static_cast<std::size_t>(chosen)].vertex_count)
        chosen = static_cast<int>(k);
    }
    out.largest = out.meshes.size() > 1;
    // The name must find this mesh again (a rig records it).
    if (find_named(nodes, nodes[static_cast<std::size_t>(chosen)].name, source, list) != chosen) {
      bad(source, "the mesh taken, '" + nodes[static_cast<std::size_t>(chosen)].name +
                      "', has a name that another mesh's node or mesh has; rename one");
    }
  }
  const NodeMeshes& n = nodes[static_cast<std::size_t>(chosen)];
  out.mesh = assemble(scene, placed_of(n), weld, source);
  out.name = n.name;
  out.to_world.matrix() = n.world;
  out.parts = renumbered(n.parts, numbers);
  return out;
}

}  // namespace

namespace {

// The importer meshes the mesh `mesh_name` takes, as read_with_assimp places them ("" = the whole file).
std::vector<Placed> placed_for(const aiScene* scene, const std::vector<NodeMeshes>& nodes, const std::string& mesh_name,
                               const std::string& source) {
  if (mesh_name.empty()) return whole_file(scene);
  const auto list = [] { return std::string("(see sweep-fit -v)"); };
  std::vector<int> chosen;
  if (io::several_mesh_names(mesh_name) ||
      (mesh_name == kAllMeshes && find_named(nodes, mesh_name, source, list) < 0)) {
    chosen = several_nodes(nodes, mesh_name, false, source, list);
  } else {
    chosen.push_back(find_named(nodes, mesh_name, source, list));
    if (chosen[0] < 0) bad(source, "no mesh is named '" + mesh_name + "' (the rig's mesh_name)");
  }
  std::vector<Placed> placed;
  for (const int k : chosen) {
    for (const Placed& p : placed_of(nodes[static_cast<std::size_t>(k)])) placed.push_back(p);
  }
  return placed;
}

// The file's materials as the surface gives them, each the first time a primitive uses it.
class SurfaceMaterials {
 public:
  SurfaceMaterials(const aiScene* scene, const fs::path& path, std::vector<SurfaceMaterial>& out,
                   const std::function<void(const std::string&)>& warn)
      : scene_(scene), path_(path), out_(out), slot_(scene->mNumMaterials, -1), warn_(warn) {}
  int operator()(unsigned index) {
    if (index >= scene_->mNumMaterials) return -1;
    if (slot_[index] >= 0) return slot_[index];
    const aiMaterial* m = scene_->mMaterials[index];
    SurfaceMaterial sm;
    aiString name;
    if (m->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) sm.name = name.C_Str();
    aiColor4D c(1, 1, 1, 1);
    if (m->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS) sm.colour = {c.r, c.g, c.b, 1};
    float opacity = 1;
    if (m->Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS) sm.colour[3] = opacity;
    aiString texture;
    if (m->GetTexture(aiTextureType_DIFFUSE, 0, &texture) == AI_SUCCESS && texture.length > 0) {
      std::string file = texture.C_Str();
      std::replace(file.begin(), file.end(), '\\', '/');
      sm.texture_name = file;
      if (const aiTexture* embedded = scene_->GetEmbeddedTexture(texture.C_Str()); embedded != nullptr) {
        if (embedded->mHeight == 0)
          sm.texture.assign(reinterpret_cast<const char*>(embedded->pcData), embedded->mWidth);
      } else {
        for (const fs::path& p : {path_.parent_path() / file, path_.parent_path() / fs::path(file).filename()}) {
          std::error_code ec;
          if (sm.texture.empty() && fs::is_regular_file(p, ec)) {
            sm.texture = read_file(p);
            sm.texture_name = p.string();
          }
        }
        if (sm.texture.empty()) {  // the material kept with its base colour, as an OBJ's
          const std::string what =
              "material '" + sm.name + "' names the texture '" + file + "', which is neither in the file nor beside it";
          if (!warn_) bad(path_.string(), what + "; the .glb bake embeds it");
          warn_(path_.string() + ": " + what + "; the .glb keeps the material's base colour only");
          sm.texture_name.clear();
        }
      }
    }
    slot_[index] = static_cast<int>(out_.size());
    out_.push_back(std::move(sm));
    return slot_[index];
  }

 private:
  const aiScene* scene_;
  fs::path path_;
  std::vector<SurfaceMaterial>& out_;
  std::vector<int> slot_;
  std::function<void(const std::string&)> warn_;
};

// One importer mesh placed by `t` as a surface primitive (no material yet): its corners' welded
// vertices numbered from `next` on, as assemble numbers them (faces in order, corners in order, by
// exact position), each new one's position appended to `positions` when given.
SurfacePrimitive surface_primitive(const aiMesh* am, const Transform& t, std::uint32_t& next,
                                   std::vector<Vec3>* positions, const std::string& source,
                                   std::vector<unsigned>* first_corner = nullptr) {
  const Eigen::Matrix3d normal_matrix = t.block<3, 3>(0, 0).inverse().transpose();
  std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> welded;
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> corners;  // welded vertex → its glTF vertices
  std::vector<std::array<float, 6>> corner_attributes;
  std::vector<Vec3> corner_normals;
  SurfacePrimitive prim;
  for (unsigned f = 0; f < am->mNumFaces; ++f) {
    const aiFace& af = am->mFaces[f];
    if (af.mNumIndices < 3) continue;
    std::vector<std::uint32_t> ids;
    for (unsigned k = 0; k < af.mNumIndices; ++k) {
      const unsigned v = af.mIndices[k];
      if (v >= am->mNumVertices) bad(source, "a face uses a vertex out of range");
      const Vec3 p = apply(t, am->mVertices[v]);
      const auto [it, inserted] = welded.try_emplace(key_of(p), next);
      if (inserted) {
        ++next;
        if (positions != nullptr) positions->push_back(p);
        if (first_corner != nullptr) first_corner->push_back(v);
      }
      // One glTF vertex a distinct (vertex, UV, colour, normal); normals within 0.01° are one
      // (exporters write a normal per corner, rounded apart).
      std::array<float, 6> attributes{};  // u, v, r, g, b, a
      if (am->mTextureCoords[0])
        attributes[0] = am->mTextureCoords[0][v].x, attributes[1] = 1 - am->mTextureCoords[0][v].y;
      if (am->mColors[0]) {
        const aiColor4D& col = am->mColors[0][v];
        attributes[2] = col.r, attributes[3] = col.g, attributes[4] = col.b, attributes[5] = col.a;
      }
      Vec3 n = Vec3::UnitZ();
      if (am->mNormals) {
        n = (normal_matrix * Vec3(am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z)).normalized();
        // A normal of no length or not finite (a file's "0 0 0"): the face's own, so the .glb validates.
        if (!n.allFinite()) {
          const auto at = [&](unsigned c) { return apply(t, am->mVertices[af.mIndices[c] % am->mNumVertices]); };
          const Vec3 face = (at(1) - at(0)).cross(at(2) - at(0));
          n = face.norm() > 0 && face.allFinite() ? Vec3(face.normalized()) : Vec3::UnitY();
        }
      }
      std::vector<std::uint32_t>& same = corners[it->second];
      std::uint32_t found = UINT32_MAX;
      for (const std::uint32_t o : same) {
        if (corner_attributes[o] == attributes && corner_normals[o].dot(n) > std::cos(1e-2 * 3.14159265358979 / 180))
          found = o;
      }
      if (found == UINT32_MAX) {
        found = static_cast<std::uint32_t>(prim.source.size());
        same.push_back(found);
        corner_attributes.push_back(attributes);
        corner_normals.push_back(n);
        prim.source.push_back(it->second);
        if (am->mTextureCoords[0]) prim.uv.insert(prim.uv.end(), {attributes[0], attributes[1]});
        if (am->mColors[0]) prim.colour.insert(prim.colour.end(), attributes.begin() + 2, attributes.end());
        if (am->mNormals)
          prim.normal.insert(prim.normal.end(),
                             {static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())});
      }
      ids.push_back(found);
    }
    for (std::size_t k = 1; k + 1 < ids.size(); ++k)
      prim.triangles.insert(prim.triangles.end(), {ids[0], ids[k], ids[k + 1]});
  }
  return prim;
}

// An importer mesh's bones, for its welded vertices (each by its first corner, `first_corner`).
void add_bones(const aiMesh& am, const std::vector<unsigned>& first_corner, SurfaceSkin& skin) {
  std::vector<std::vector<std::pair<std::uint32_t, double>>> influences(am.mNumVertices);
  for (unsigned b = 0; b < am.mNumBones; ++b) {
    const aiBone* bone = am.mBones[b];
    const std::string name = bone->mName.C_Str();
    const auto at = std::find(skin.bones.begin(), skin.bones.end(), name);
    const auto index = static_cast<std::uint32_t>(at - skin.bones.begin());
    if (at == skin.bones.end()) skin.bones.push_back(name);
    for (unsigned w = 0; w < bone->mNumWeights; ++w) {
      const aiVertexWeight& vw = bone->mWeights[w];
      if (vw.mVertexId < am.mNumVertices && std::isfinite(vw.mWeight) && vw.mWeight > 0)
        influences[vw.mVertexId].emplace_back(index, vw.mWeight);
    }
  }
  for (const unsigned v : first_corner) {
    skin.bind.emplace_back(am.mVertices[v].x, am.mVertices[v].y, am.mVertices[v].z);
    skin.influences.push_back(influences[v]);
  }
}

std::vector<NodeMeshes> scene_nodes(const aiScene* scene) {
  std::vector<NodeMeshes> nodes;
  if (scene->mRootNode != nullptr) collect_nodes(scene, scene->mRootNode, Transform::Identity(), nodes);
  return nodes;
}

}  // namespace

SceneSurface read_scene_surface(const fs::path& path, const std::string& mesh_name,
                                const std::function<void(const std::string&)>& warn) {
  const std::string source = path.string();
  Assimp::Importer importer;
  const aiScene* scene = import_scene(importer, source);
  const std::vector<NodeMeshes> nodes = scene_nodes(scene);
  // Where each importer mesh of the mesh read starts in its numbering.
  const std::vector<Placed> read = placed_for(scene, nodes, mesh_name, source);
  std::vector<std::uint32_t> read_base;
  std::uint32_t count = 0;
  for (const Placed& p : read) {
    read_base.push_back(count);
    count += static_cast<std::uint32_t>(assembled_vertex_count(scene, {p}, /*weld=*/true));
  }
  std::vector<char> claimed(read.size(), 0);
  SceneSurface out;
  SurfaceMaterials material(scene, path, out.materials, warn);
  for (const NodeMeshes& n : nodes) {
    SurfaceNode node{n.name, n.mesh_name, {}, {}, {}, std::nullopt, n.world.block<3, 3>(0, 0)};
    const bool skinned =
        std::all_of(n.parts.begin(), n.parts.end(), [&](unsigned m) { return scene->mMeshes[m]->mNumBones > 0; });
    if (skinned) node.skin.emplace();
    for (const unsigned m : n.parts) {
      std::size_t e = 0;
      while (e < read.size() && (claimed[e] || read[e].mesh != m || read[e].transform != n.world)) ++e;
      std::uint32_t next = static_cast<std::uint32_t>(node.positions.size());
      const std::uint32_t first = next;
      std::vector<unsigned> first_corner;
      SurfacePrimitive prim =
          surface_primitive(scene->mMeshes[m], n.world, next, &node.positions, source, &first_corner);
      if (prim.source.empty()) continue;
      if (node.skin) add_bones(*scene->mMeshes[m], first_corner, *node.skin);
      if (e < read.size()) claimed[e] = 1;
      for (std::uint32_t j = first; j < next; ++j)
        node.read_as.push_back(e < read.size() ? read_base[e] + (j - first) : kNotRead);
      prim.material = material(scene->mMeshes[m]->mMaterialIndex);
      node.primitives.push_back(std::move(prim));
    }
    if (!node.primitives.empty()) out.nodes.push_back(std::move(node));
  }
  return out;
}

Mesh parse_ply(std::string_view bytes, const std::string& source) {
  bytes = detail::skip_bom(bytes);
  if (bytes.empty()) bad(source, "empty file");
  detail::check_ascii_ply(bytes, source);
  return read_with_assimp(source, /*weld=*/false, "", MeshPick::whole_file, /*named_format=*/false, bytes, "ply").mesh;
}

SceneMesh read_scene_mesh(const fs::path& path, const std::string& name, MeshPick pick, bool file_order) {
  const std::string source = path.string();
  check_input_file(path);
  const std::string ext = lower_extension(path);
  SceneMesh out;
  if (ext == "off" || ext == "obj" || ext == "ply") {
    if (!name.empty()) {
      bad(source,
          "holds one mesh with no name (" +
              std::string(ext == "obj" ? "an OBJ's o and g groups share one vertex list" : "the format has none") +
              "), so there is no " + asked_meshes(name) + " to take");
    }
    const std::string bytes = read_file(path);
    out.mesh = ext == "off"   ? parse_off(bytes, source)
               : ext == "obj" ? parse_obj(bytes, source)
                              : parse_ply(bytes, source);
  } else if (ext == "gltf" || ext == "glb") {
    const nlohmann::json doc = detail::check_gltf_indices(path);
    out = read_with_assimp(source, /*weld=*/false, name, pick, /*named_format=*/true, {}, "", &doc, file_order);
  } else {
    if (ext.empty()) {
      fail(ErrorCategory::unsupported, source + ": no file extension, so the format is unknown");
    }
    const Assimp::Importer probe;
    if (!probe.IsExtensionSupported("." + ext)) {
      fail(ErrorCategory::unsupported, source + ": unsupported mesh format '." + ext + "'");
    }
    out = read_with_assimp(source, /*weld=*/true, name, pick, names_meshes(ext), {}, "", nullptr, file_order);
  }
  validate_mesh(out.mesh, source);
  return out;
}

Mesh read_mesh(const fs::path& path) {
  return read_scene_mesh(path, "", MeshPick::whole_file).mesh;
}

std::string direction_name(const Vec3& d) {
  for (int a = 0; a < 3; ++a) {
    for (const double sign : {1.0, -1.0}) {
      if ((d - sign * Vec3::Unit(a)).norm() < 1e-6) return std::string(sign > 0 ? "+" : "-") + "XYZ"[a];
    }
  }
  return "(" + format_number(d.x()) + ", " + format_number(d.y()) + ", " + format_number(d.z()) + ")";
}

std::string asked_meshes(const std::string& name) {
  return (io::several_mesh_names(name) ? "meshes " : "mesh ") + io::quoted_mesh_names(name);
}

std::string list_scene_meshes(const std::vector<SceneMeshEntry>& meshes) {
  std::string out;
  for (const SceneMeshEntry& m : meshes) {
    out += (out.empty() ? "" : ", ") + std::string("'") + m.name + "'";
    if (!m.mesh_name.empty() && m.mesh_name != m.name) out += " (mesh '" + m.mesh_name + "')";
    out += " " + std::to_string(m.vertex_count) + " vertices";
  }
  return out;
}

void validate_mesh(const Mesh& mesh, const std::string& source) {
  if (const std::string why = check_mesh(mesh); !why.empty()) bad(source, why);
}

}  // namespace sweep::assets
