// An OBJ's surface as a glTF document (obj_gltf.h).
#include "sweep/assets/obj_gltf.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <tuple>

#include "sweep/assets/smooth_normals.h"
#include "sweep/core/error.h"
#include "sweep/core/text.h"
#include "sweep/io/read_file.h"

using sweep::io::read_file;

namespace sweep::assets::detail {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

std::vector<std::string> tokens(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line.substr(0, line.find('#')));
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

double number(const std::string& t) {
  return std::strtod(t.c_str(), nullptr);
}

std::string place(const fs::path& file, int line) {
  return file.string() + ": line " + std::to_string(line) + ": ";
}

struct Material {
  std::string name;
  std::array<double, 4> colour{1, 1, 1, 1};
  std::string texture;  // the file, relative to the .mtl
  fs::path dir;
  int texture_line = 0;  // the map_Kd line, for messages
};

std::map<std::string, Material> read_mtl(const fs::path& mtl) {
  std::map<std::string, Material> out;
  std::string text;
  try {
    text = read_file(mtl);
  } catch (const Error&) {
    fail(ErrorCategory::bad_input, mtl.string() +
                                       ": cannot read this material library, which the "
                                       "OBJ names and the .glb bake carries");
  }
  std::istringstream in(text);
  Material* m = nullptr;
  int number_of_line = 0;
  for (std::string line; std::getline(in, line);) {
    ++number_of_line;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string> t = tokens(line);
    if (t.empty()) continue;
    if (t[0] == "newmtl" && t.size() > 1) {
      m = &out[t[1]];
      m->name = t[1];
      m->dir = mtl.parent_path();
    } else if (m && t[0] == "Kd" && t.size() >= 4) {
      // A colour that is not finite would be a NaN base colour, which no viewer draws.
      for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(number(t[c + 1]))) {
          fail(ErrorCategory::bad_input, place(mtl, number_of_line) + "material '" + m->name +
                                             "': Kd must be three finite numbers, got '" + t[1] + " " + t[2] + " " +
                                             t[3] + "'");
        }
        m->colour[c] = std::clamp(number(t[c + 1]), 0.0, 1.0);
      }
    } else if (m && t[0] == "d" && t.size() >= 2) {
      if (!std::isfinite(number(t[1]))) {
        fail(ErrorCategory::bad_input, place(mtl, number_of_line) + "material '" + m->name +
                                           "': d (opacity) must be a finite number, got '" + t[1] + "'");
      }
      m->colour[3] = std::clamp(number(t[1]), 0.0, 1.0);
    } else if (m && t[0] == "map_Kd" && t.size() >= 2) {
      m->texture = t.back();  // options (-s, -o, ...) come before the file name
      // Written on Windows: ".\\textures\\skin.png". A backslash is no part of a file name here.
      std::replace(m->texture.begin(), m->texture.end(), '\\', '/');
      m->texture_line = number_of_line;
    }
  }
  return out;
}

std::string media_type(const std::string& bytes) {
  if (bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0) return "image/png";
  if (bytes.compare(0, 3, "\xFF\xD8\xFF") == 0) return "image/jpeg";
  return "";
}

// A corner: the v, vt and vn it names (0-based; -1 when absent).
struct Corner {
  long long v = -1, vt = -1, vn = -1;
  bool operator<(const Corner& o) const { return std::tie(v, vt, vn) < std::tie(o.v, o.vt, o.vn); }
};

long long index_of(const std::string& t, std::size_t count) {
  if (t.empty()) return -1;
  const long long i = std::strtoll(t.c_str(), nullptr, 10);
  return i > 0 ? i - 1 : static_cast<long long>(count) + i;
}

}  // namespace

std::optional<SurfaceGltf> obj_as_gltf(const fs::path& obj, const Mesh& rest,
                                       const std::function<void(const std::string&)>& warn) {
  const std::string text = read_file(obj);
  std::vector<std::array<float, 2>> uvs;
  std::vector<std::array<float, 3>> normals, colours;
  std::map<std::string, Material> library;
  std::vector<std::string> material_order;                        // in first use
  std::map<std::string, std::vector<std::vector<Corner>>> faces;  // per material
  std::size_t positions = 0, face_count = 0;
  std::string current;
  bool any_surface = false;
  std::istringstream in(text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? text.substr(3) : text);
  int line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string> t = tokens(line);
    if (t.empty()) continue;
    if (t[0] == "v") {
      ++positions;
      if (t.size() >= 7) {
        const std::array<float, 3> c{static_cast<float>(number(t[4])), static_cast<float>(number(t[5])),
                                     static_cast<float>(number(t[6]))};
        if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2])) {
          fail(ErrorCategory::bad_input, place(obj, line_number) + "vertex " + std::to_string(positions - 1) +
                                             " has a colour that is not finite (" + t[4] + ", " + t[5] + ", " + t[6] +
                                             ")");
        }
        colours.push_back(c);
        any_surface = true;
      }
    } else if (t[0] == "vt" && t.size() >= 3) {
      uvs.push_back({static_cast<float>(number(t[1])), static_cast<float>(1 - number(t[2]))});
      if (!std::isfinite(uvs.back()[0]) || !std::isfinite(uvs.back()[1])) {
        fail(ErrorCategory::bad_input, place(obj, line_number) + "texture coordinate " + std::to_string(uvs.size()) +
                                           " (1-based) is not finite (" + t[1] + ", " + t[2] + ")");
      }
      any_surface = true;
    } else if (t[0] == "vn" && t.size() >= 4) {
      Eigen::Vector3d n(number(t[1]), number(t[2]), number(t[3]));
      if (n.norm() > 0) n.normalize();
      normals.push_back({static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())});
      any_surface = true;
    } else if (t[0] == "usemtl" && t.size() > 1) {
      current = t[1];
      any_surface = true;
    } else if (t[0] == "mtllib" && t.size() > 1) {
      for (std::size_t k = 1; k < t.size(); ++k) library.merge(read_mtl(obj.parent_path() / t[k]));
    } else if (t[0] == "f" && t.size() >= 4) {
      std::vector<Corner> face;
      for (std::size_t k = 1; k < t.size(); ++k) {
        std::string parts[3];
        std::size_t at = 0;
        for (int p = 0; p < 3 && at != std::string::npos; ++p) {
          const std::size_t slash = t[k].find('/', at);
          parts[p] = t[k].substr(at, slash == std::string::npos ? std::string::npos : slash - at);
          at = slash == std::string::npos ? slash : slash + 1;
        }
        face.push_back(
            {index_of(parts[0], positions), index_of(parts[1], uvs.size()), index_of(parts[2], normals.size())});
        // A vt or vn named but not there would drop the face's UVs or normals, or index past them.
        const Corner& c = face.back();
        for (const auto& [given, index, count, what] : {std::tuple{parts[1], c.vt, uvs.size(), "texture coordinate"},
                                                        std::tuple{parts[2], c.vn, normals.size(), "normal"}}) {
          if (!given.empty() && (index < 0 || index >= static_cast<long long>(count))) {
            fail(ErrorCategory::bad_input, place(obj, line_number) + "face " + std::to_string(face_count) + " uses " +
                                               what + " " + given + " (as in the file), out of range (the file has " +
                                               std::to_string(count) + " before this line)");
          }
        }
      }
      ++face_count;
      if (!faces.count(current)) material_order.push_back(current);
      faces[current].push_back(std::move(face));
    }
  }
  if (!any_surface) return std::nullopt;
  if (colours.size() != positions) colours.clear();  // only when every vertex has one

  MeshSurface surface;
  std::map<std::string, int> material_slot;
  for (const std::string& name : material_order) {
    std::map<Corner, std::uint32_t> vertex;
    std::vector<Corner> corners;
    SurfacePrimitive prim;
    bool has_uv = true, has_normal = true;
    for (const std::vector<Corner>& face : faces[name]) {
      std::vector<std::uint32_t> ids;
      for (const Corner& c : face) {
        if (c.v < 0 || c.v >= static_cast<long long>(rest.vertex_count())) continue;  // parse_obj refused these
        has_uv = has_uv && c.vt >= 0 && c.vt < static_cast<long long>(uvs.size());
        has_normal = has_normal && c.vn >= 0 && c.vn < static_cast<long long>(normals.size());
        const auto [it, inserted] = vertex.try_emplace(c, static_cast<std::uint32_t>(corners.size()));
        if (inserted) corners.push_back(c);
        ids.push_back(it->second);
      }
      for (std::size_t k = 1; k + 1 < ids.size(); ++k)
        prim.triangles.insert(prim.triangles.end(), {ids[0], ids[k], ids[k + 1]});
    }
    if (corners.empty()) continue;
    for (const Corner& c : corners) {
      prim.source.push_back(static_cast<std::uint32_t>(c.v));
      if (has_uv) prim.uv.insert(prim.uv.end(), uvs[c.vt].begin(), uvs[c.vt].end());
      if (has_normal) prim.normal.insert(prim.normal.end(), normals[c.vn].begin(), normals[c.vn].end());
      if (!colours.empty())
        prim.colour.insert(prim.colour.end(), {colours[c.v][0], colours[c.v][1], colours[c.v][2], 1.0f});
    }
    if (!name.empty()) {
      const auto found = library.find(name);
      const Material m = found != library.end() ? found->second : Material{name, {1, 1, 1, 1}, "", {}};
      SurfaceMaterial sm{name, m.colour, "", ""};
      if (!m.texture.empty()) {
        sm.texture_name = (m.dir / m.texture).string();
        try {
          sm.texture = read_file(m.dir / m.texture);
        } catch (const Error& e) {
          // Files other tools write often name textures that were not sent along: the material is
          // kept with its base colour, and the bake goes on.
          if (warn) {
            warn(sm.texture_name + ": cannot read material '" + name + "''s texture (map_Kd, line " +
                 std::to_string(m.texture_line) + " of its library): " + e.what() +
                 "; the material keeps its base colour only");
          }
          sm.texture_name.clear();
        }
      }
      prim.material = static_cast<int>(surface.materials.size());
      surface.materials.push_back(std::move(sm));
    }
    surface.primitives.push_back(std::move(prim));
  }
  return surface_as_gltf(surface, rest, obj);
}

namespace {

// The document being built: one buffer, 4-byte aligned views, an accessor a view.
struct DocumentBuilder {
  std::string bin;
  Json views = Json::array(), accessors = Json::array();
  Json materials = Json::array(), textures = Json::array(), images = Json::array();

  std::size_t add(const void* data, std::size_t bytes, int component, const char* type, std::size_t count, int target) {
    bin.append((4 - bin.size() % 4) % 4, '\0');
    Json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
    if (target) view["target"] = target;
    bin.append(static_cast<const char*>(data), bytes);
    views.push_back(view);
    if (!type) return views.size() - 1;
    accessors.push_back(
        {{"bufferView", views.size() - 1}, {"componentType", component}, {"count", count}, {"type", type}});
    return accessors.size() - 1;
  }

  void add_materials(const std::vector<SurfaceMaterial>& list) {
    for (const SurfaceMaterial& m : list) {
      Json pbr = {{"baseColorFactor", m.colour}, {"metallicFactor", 0.0}};
      if (!m.texture.empty()) {
        const std::string type = media_type(m.texture);
        if (type.empty()) {
          fail(ErrorCategory::unsupported,
               m.texture_name + ": material '" + m.name + "''s texture is not PNG or JPEG, so a .glb cannot hold it");
        }
        images.push_back({{"name", fs::path(m.texture_name).stem().string()},
                          {"mimeType", type},
                          {"bufferView", add(m.texture.data(), m.texture.size(), 0, nullptr, 0, 0)}});
        textures.push_back({{"source", images.size() - 1}});
        pbr["baseColorTexture"] = {{"index", textures.size() - 1}};
        pbr["baseColorFactor"] = {1.0, 1.0, 1.0,
                                  m.colour[3]};  // the image is the colour, as OBJ and FBX viewers show it
      }
      materials.push_back({{"name", m.name}, {"pbrMetallicRoughness", pbr}});
    }
  }

  // One glTF mesh's primitives over one vertex array: the vertices of `positions` first, in their
  // order (each with its first corner's attributes; (0, 1, 0) normals on a vertex no face uses),
  // then the corners that differ (a seam, a hard edge). `source` gets each array vertex's vertex.
  // `triangles` (into `positions`) give the smooth normals of a primitive without its own.
  Json add_mesh(const std::vector<SurfacePrimitive>& primitives, const std::vector<Vec3>& positions,
                const std::vector<std::uint32_t>& triangles, std::vector<std::uint32_t>& source) {
    bool any_uv = false, any_normal = false, any_colour = false;
    for (const SurfacePrimitive& prim : primitives) {
      any_uv = any_uv || !prim.uv.empty();
      any_normal = any_normal || !prim.normal.empty();
      any_colour = any_colour || !prim.colour.empty();
    }
    // A primitive without normals beside one with them shares its NORMAL accessor: its corners take
    // the mesh's smooth normal (what a viewer would light it by without one), not a constant.
    std::vector<Eigen::Vector3f> smooth;
    if (any_normal) smooth = smooth_normals(positions, triangles);
    using Attributes = std::array<float, 9>;  // u, v, nx, ny, nz, r, g, b, a
    const std::size_t n = positions.size();
    std::vector<Attributes> attributes(n, Attributes{0, 0, 0, 1, 0, 1, 1, 1, 1});
    source.resize(n);
    for (std::uint32_t v = 0; v < n; ++v) source[v] = v;
    std::vector<char> assigned(n, 0);
    std::map<std::uint32_t, std::vector<std::uint32_t>> extra;
    std::vector<std::vector<std::uint32_t>> indices;
    for (const SurfacePrimitive& prim : primitives) {
      std::vector<std::uint32_t> id(prim.source.size());
      for (std::size_t i = 0; i < prim.source.size(); ++i) {
        Attributes a{0, 0, 0, 1, 0, 1, 1, 1, 1};
        if (!prim.uv.empty()) std::copy_n(&prim.uv[2 * i], 2, a.begin());
        const std::uint32_t v = prim.source[i];
        if (!prim.normal.empty()) {
          std::copy_n(&prim.normal[3 * i], 3, a.begin() + 2);
        } else if (any_normal) {
          std::copy_n(smooth[v].data(), 3, a.begin() + 2);
        }
        if (!prim.colour.empty()) std::copy_n(&prim.colour[4 * i], 4, a.begin() + 5);
        if (!assigned[v]) {
          assigned[v] = 1;
          attributes[v] = a;
          id[i] = v;
          continue;
        }
        id[i] = UINT32_MAX;
        if (attributes[v] == a) id[i] = v;
        for (const std::uint32_t o : extra[v]) {
          if (id[i] == UINT32_MAX && attributes[o] == a) id[i] = o;
        }
        if (id[i] == UINT32_MAX) {
          id[i] = static_cast<std::uint32_t>(attributes.size());
          attributes.push_back(a);
          source.push_back(v);
          extra[v].push_back(id[i]);
        }
      }
      std::vector<std::uint32_t> t = prim.triangles;
      for (std::uint32_t& k : t) k = id[k];
      indices.push_back(std::move(t));
    }
    const std::size_t count = attributes.size();
    std::vector<float> pos, uv, nrm, col;
    Eigen::Vector3f lo = positions[0].cast<float>(), hi = lo;
    for (std::size_t v = 0; v < count; ++v) {
      const Eigen::Vector3f p = positions[source[v]].cast<float>();
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      pos.insert(pos.end(), {p.x(), p.y(), p.z()});
      const Attributes& a = attributes[v];
      uv.insert(uv.end(), a.begin(), a.begin() + 2);
      nrm.insert(nrm.end(), a.begin() + 2, a.begin() + 5);
      col.insert(col.end(), a.begin() + 5, a.end());
    }
    Json shared = {{"POSITION", add(pos.data(), 4 * pos.size(), 5126, "VEC3", count, 34962)}};
    accessors[shared["POSITION"].get<std::size_t>()]["min"] = {lo.x(), lo.y(), lo.z()};
    accessors[shared["POSITION"].get<std::size_t>()]["max"] = {hi.x(), hi.y(), hi.z()};
    if (any_normal) shared["NORMAL"] = add(nrm.data(), 4 * nrm.size(), 5126, "VEC3", count, 34962);
    if (any_uv) shared["TEXCOORD_0"] = add(uv.data(), 4 * uv.size(), 5126, "VEC2", count, 34962);
    if (any_colour) shared["COLOR_0"] = add(col.data(), 4 * col.size(), 5126, "VEC4", count, 34962);
    Json out = Json::array();
    for (std::size_t k = 0; k < primitives.size(); ++k) {
      Json primitive = {
          {"attributes", shared},
          {"indices", add(indices[k].data(), 4 * indices[k].size(), 5125, "SCALAR", indices[k].size(), 34963)}};
      if (primitives[k].material >= 0) primitive["material"] = primitives[k].material;
      out.push_back(std::move(primitive));
    }
    return out;
  }

  // The document: `nodes` (all roots of the one scene) and `meshes`, the rest as built.
  void finish(SurfaceGltf& out, const fs::path& file, Json nodes, Json meshes) {
    bin.append((4 - bin.size() % 4) % 4, '\0');
    Json roots = Json::array();
    for (std::size_t k = 0; k < nodes.size(); ++k) roots.push_back(k);
    Json& doc = out.doc.json;
    doc = {{"asset", {{"version", "2.0"}, {"generator", "sweep bake (from " + file.filename().string() + ")"}}},
           {"scene", 0},
           {"scenes", Json::array({{{"nodes", roots}}})},
           {"nodes", std::move(nodes)},
           {"meshes", std::move(meshes)},
           {"accessors", accessors},
           {"bufferViews", views},
           {"buffers", Json::array({{{"byteLength", bin.size()}}})}};
    if (!materials.empty()) doc["materials"] = materials;
    if (!textures.empty()) doc["textures"] = textures;
    if (!images.empty()) doc["images"] = images;
    doc = Json::parse(doc.dump());  // numbers as a reader sees them (unsigned where not negative)
    out.doc.buffers.push_back(std::move(bin));
  }
};

}  // namespace

SurfaceGltf surface_as_gltf(const MeshSurface& surface, const Mesh& rest, const fs::path& file) {
  SurfaceGltf out;
  DocumentBuilder b;
  b.add_materials(surface.materials);
  std::vector<std::uint32_t> source;
  Json primitives = b.add_mesh(surface.primitives, rest.positions, rest.triangles(), source);
  out.sources.assign(surface.primitives.size(), source);
  out.primitive_mesh.assign(surface.primitives.size(), 0);
  out.mesh_bones.resize(1);
  const std::string stem = file.stem().string();
  b.finish(out, file, Json::array({{{"name", stem}, {"mesh", 0}}}),
           Json::array({{{"name", stem}, {"primitives", primitives}}}));
  return out;
}

SurfaceGltf scene_as_gltf(const SceneSurface& scene, const Mesh& rest, const fs::path& file) {
  SurfaceGltf out;
  DocumentBuilder b;
  b.add_materials(scene.materials);
  Json nodes = Json::array(), meshes = Json::array();
  for (const SurfaceNode& node : scene.nodes) {
    std::vector<std::uint32_t> triangles;
    for (const SurfacePrimitive& prim : node.primitives)
      for (const std::uint32_t t : prim.triangles) triangles.push_back(prim.source[t]);
    std::vector<std::uint32_t> source;
    Json primitives = b.add_mesh(node.primitives, node.positions, triangles, source);
    const std::vector<std::uint32_t> local_source = source;  // each array vertex's vertex of the node
    // Its vertices as the mesh read numbers them: all of them (the rig's mesh), or none (a mesh the
    // bake never moves). Checked by exact position: the same vertex, or the numbering is wrong.
    const std::size_t read = static_cast<std::size_t>(
        std::count_if(node.read_as.begin(), node.read_as.end(), [](std::uint32_t v) { return v != kNotRead; }));
    if (read != 0 && read != node.read_as.size()) {
      fail(ErrorCategory::unsupported,
           file.string() + ": node '" + node.name +
               "' shows meshes the mesh read places by other nodes as well as its own; the .glb bake "
               "cannot give its vertices one place (name the rig's meshes with --mesh, or bake to .pc2)");
    }
    for (std::uint32_t& v : source) {
      if (read == 0) continue;
      const std::uint32_t r = node.read_as[v];
      if (r >= rest.vertex_count() || rest.positions[r] != node.positions[v]) {
        fail(ErrorCategory::internal, file.string() + ": node '" + node.name + "' vertex " + std::to_string(v) +
                                          " is not where the mesh read has it");
      }
      v = r;
    }
    for (std::size_t k = 0; k < node.primitives.size(); ++k) {
      out.sources.push_back(read == 0 ? std::vector<std::uint32_t>{} : source);
      out.primitive_mesh.push_back(meshes.size());
    }
    std::optional<SurfaceGltf::Bones> bones;
    if (node.skin && node.skin->bind.size() == node.positions.size()) {
      bones.emplace();
      bones->skin.bones = node.skin->bones;
      bones->to_world_linear = node.to_world_linear;
      for (const std::uint32_t v : local_source) {
        bones->skin.bind.push_back(node.skin->bind[v]);
        bones->skin.influences.push_back(node.skin->influences[v]);
      }
    }
    out.mesh_bones.push_back(std::move(bones));
    nodes.push_back({{"name", node.name}, {"mesh", meshes.size()}});
    meshes.push_back({{"name", node.mesh_name.empty() ? node.name : node.mesh_name}, {"primitives", primitives}});
  }
  if (meshes.empty()) fail(ErrorCategory::bad_input, file.string() + ": no node shows a mesh with faces");
  b.finish(out, file, std::move(nodes), std::move(meshes));
  return out;
}

}  // namespace sweep::assets::detail
