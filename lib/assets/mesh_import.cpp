// The import of mesh_io.h: read_mesh (checks the file, then chooses the reader by extension),
// and assimp for PLY, glTF/glb and every other format it reads, welded by exact position where the
// format has no shared vertex list. The only file that sees assimp.
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <assimp/Importer.hpp>
#include <bit>
#include <cerrno>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <vector>

#include "assets/mesh_checks.h"
#include "assets/mesh_io.h"
#include "assets/mesh_io_detail.h"
#include "assets/mesh_surface.h"
#include "core/error.h"
#include "core/fp_environment.h"
#include "core/hash.h"
#include "core/text.h"
#include "io/read_file.h"

namespace sweep::io {
namespace {

namespace fs = std::filesystem;
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

using Transform = Eigen::Matrix4d;

Transform to_transform(const aiMatrix4x4& m) {
  Transform t;
  t << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3,
      m.d4;
  return t;
}

// World transform of each mesh: that of the first node referring to it in depth-first order
// (identity when no node does). Instances (one mesh under several nodes) are not duplicated.
void collect_transforms(const aiNode* node, const Transform& parent,
                        std::vector<Transform>& transforms, std::vector<bool>& seen) {
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

Vec3 apply(const Transform& t, const aiVector3D& v) {
  if (t.isIdentity(0.0)) return Vec3(v.x, v.y, v.z);  // exact: no arithmetic at all
  const Eigen::Vector4d h = t * Eigen::Vector4d(v.x, v.y, v.z, 1.0);
  return h.head<3>();
}

// Key for welding by exact position: the bit patterns, with -0 and +0 counted as one.
struct PositionKey {
  std::array<std::uint64_t, 3> bits;
  bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
  std::size_t operator()(const PositionKey& k) const {
    std::uint64_t h = kFnvOffset;  // FNV-1a's constants, a 64-bit word at a time: a table key, not a file's hash
    for (std::uint64_t b : k.bits) h = (h ^ b) * kFnvPrime;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
PositionKey key_of(const Vec3& p) {
  PositionKey key;
  for (int k = 0; k < 3; ++k) key.bits[k] = std::bit_cast<std::uint64_t>(p[k] == 0.0 ? 0.0 : p[k]);
  return key;
}

// `bytes` given: the file's content already in memory (PLY, read from there so that a byte order
// mark can be skipped and the body checked first), with `hint` its extension; else the file
// `source` is read by assimp itself (glTF may refer to other files beside it).
Mesh read_with_assimp(const std::string& source, bool weld, std::string_view bytes = {},
                      const char* hint = "") {
  Assimp::Importer importer;
  // No post-processing: it keeps the stored vertices, their order and count, and the polygons.
  const aiScene* scene = nullptr;
  {
    const QuietFpEnvironment quiet;
    scene = bytes.empty() ? importer.ReadFile(source, 0)
                          : importer.ReadFileFromMemory(bytes.data(), bytes.size(), 0, hint);
  }
  if (scene == nullptr) bad(source, "cannot parse: " + one_line(importer.GetErrorString()));
  if (scene->mNumMeshes == 0 || scene->mMeshes == nullptr) bad(source, "no vertices");

  std::vector<Transform> transforms(scene->mNumMeshes, Transform::Identity());
  std::vector<bool> seen(scene->mNumMeshes, false);
  if (scene->mRootNode != nullptr) {
    collect_transforms(scene->mRootNode, Transform::Identity(), transforms, seen);
  }

  Mesh mesh;
  std::size_t face = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    const Transform& t = transforms[m];
    const std::size_t base = mesh.positions.size();
    if (!weld) {
      for (unsigned i = 0; i < am->mNumVertices; ++i)
        mesh.positions.push_back(apply(t, am->mVertices[i]));
    }
    std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> welded;
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& af = am->mFaces[f];
      if (af.mNumIndices < 3) continue;  // points and lines are not surface
      for (unsigned k = 0; k < af.mNumIndices; ++k) {
        const unsigned v = af.mIndices[k];
        if (v >= am->mNumVertices) {
          bad(source, "face " + std::to_string(face) + " uses vertex " + std::to_string(v) +
                          " of mesh " + std::to_string(m) + ", out of range (that mesh has " +
                          std::to_string(am->mNumVertices) + " vertices)");
        }
        if (!weld) {
          mesh.face_vertices.push_back(static_cast<std::uint32_t>(base + v));
          continue;
        }
        const Vec3 p = apply(t, am->mVertices[v]);
        const auto [it, inserted] =
            welded.try_emplace(key_of(p), static_cast<std::uint32_t>(mesh.positions.size()));
        if (inserted) mesh.positions.push_back(p);
        mesh.face_vertices.push_back(it->second);
      }
      mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_vertices.size()));
      ++face;
    }
  }
  return mesh;
}

}  // namespace

MeshSurface read_welded_surface(const fs::path& path) {
  const std::string source = path.string();
  Assimp::Importer importer;
  const aiScene* scene = nullptr;
  {
    const QuietFpEnvironment quiet;
    scene = importer.ReadFile(source, 0);
  }
  if (scene == nullptr || scene->mMeshes == nullptr) bad(source, "cannot parse: " + one_line(importer.GetErrorString()));
  std::vector<Transform> transforms(scene->mNumMeshes, Transform::Identity());
  std::vector<bool> seen(scene->mNumMeshes, false);
  if (scene->mRootNode != nullptr) collect_transforms(scene->mRootNode, Transform::Identity(), transforms, seen);

  MeshSurface out;
  std::vector<int> slot(scene->mNumMaterials, -1);
  auto material = [&](unsigned index) {
    if (index >= scene->mNumMaterials) return -1;
    if (slot[index] >= 0) return slot[index];
    const aiMaterial* m = scene->mMaterials[index];
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
      if (const aiTexture* embedded = scene->GetEmbeddedTexture(texture.C_Str()); embedded != nullptr) {
        if (embedded->mHeight == 0) sm.texture.assign(reinterpret_cast<const char*>(embedded->pcData), embedded->mWidth);
      } else {
        for (const fs::path& p : {path.parent_path() / file, path.parent_path() / fs::path(file).filename()}) {
          std::error_code ec;
          if (sm.texture.empty() && fs::is_regular_file(p, ec)) {
            sm.texture = read_file(p);
            sm.texture_name = p.string();
          }
        }
        if (sm.texture.empty()) {
          bad(source, "material '" + sm.name + "' names the texture '" + file +
                          "', which is neither in the file nor beside it; the .glb bake embeds it");
        }
      }
    }
    slot[index] = static_cast<int>(out.materials.size());
    out.materials.push_back(std::move(sm));
    return slot[index];
  };
  std::uint32_t next = 0;  // welded vertices so far: read_with_assimp's numbering
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    const Transform& t = transforms[m];
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
        const auto [it, inserted] = welded.try_emplace(key_of(apply(t, am->mVertices[v])), next);
        if (inserted) ++next;
        // One glTF vertex a distinct (vertex, UV, colour, normal); normals within 0.01° are one
        // (exporters write a normal per corner, rounded apart).
        std::array<float, 6> attributes{};  // u, v, r, g, b, a
        if (am->mTextureCoords[0]) attributes[0] = am->mTextureCoords[0][v].x, attributes[1] = 1 - am->mTextureCoords[0][v].y;
        if (am->mColors[0]) {
          const aiColor4D& col = am->mColors[0][v];
          attributes[2] = col.r, attributes[3] = col.g, attributes[4] = col.b, attributes[5] = col.a;
        }
        Vec3 n = Vec3::UnitZ();
        if (am->mNormals) n = (normal_matrix * Vec3(am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z)).normalized();
        std::vector<std::uint32_t>& same = corners[it->second];
        std::uint32_t found = UINT32_MAX;
        for (const std::uint32_t o : same) {
          if (corner_attributes[o] == attributes && corner_normals[o].dot(n) > std::cos(1e-2 * 3.14159265358979 / 180)) found = o;
        }
        if (found == UINT32_MAX) {
          found = static_cast<std::uint32_t>(prim.source.size());
          same.push_back(found);
          corner_attributes.push_back(attributes);
          corner_normals.push_back(n);
          prim.source.push_back(it->second);
          if (am->mTextureCoords[0]) prim.uv.insert(prim.uv.end(), {attributes[0], attributes[1]});
          if (am->mColors[0]) prim.colour.insert(prim.colour.end(), attributes.begin() + 2, attributes.end());
          if (am->mNormals) prim.normal.insert(prim.normal.end(), {static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())});
        }
        ids.push_back(found);
      }
      for (std::size_t k = 1; k + 1 < ids.size(); ++k) prim.triangles.insert(prim.triangles.end(), {ids[0], ids[k], ids[k + 1]});
    }
    if (prim.source.empty()) continue;
    prim.material = material(am->mMaterialIndex);
    out.primitives.push_back(std::move(prim));
  }
  return out;
}

Mesh parse_ply(std::string_view bytes, const std::string& source) {
  bytes = detail::skip_bom(bytes);
  if (bytes.empty()) bad(source, "empty file");
  detail::check_ascii_ply(bytes, source);
  return read_with_assimp(source, /*weld=*/false, bytes, "ply");
}

Mesh read_mesh(const fs::path& path) {
  const std::string source = path.string();
  check_input_file(path);
  const std::string ext = lower_extension(path);
  Mesh mesh;
  if (ext == "off") {
    mesh = parse_off(read_file(path), source);
  } else if (ext == "obj") {
    mesh = parse_obj(read_file(path), source);
  } else if (ext == "ply") {
    mesh = parse_ply(read_file(path), source);
  } else if (ext == "gltf" || ext == "glb") {
    detail::check_gltf_indices(path);
    mesh = read_with_assimp(source, /*weld=*/false);
  } else {
    if (ext.empty()) {
      fail(ErrorCategory::unsupported, source + ": no file extension, so the format is unknown");
    }
    const Assimp::Importer probe;
    if (!probe.IsExtensionSupported("." + ext)) {
      fail(ErrorCategory::unsupported, source + ": unsupported mesh format '." + ext + "'");
    }
    mesh = read_with_assimp(source, /*weld=*/true);
  }
  validate_mesh(mesh, source);
  return mesh;
}

void validate_mesh(const Mesh& mesh, const std::string& source) {
  if (const std::string why = check_mesh(mesh); !why.empty()) bad(source, why);
}

}  // namespace sweep::io
