#pragma once
// What a mesh file says about its surface beyond positions and faces — UVs, normals, vertex colours
// and materials — for the .glb bake to carry (obj_gltf.h makes it a glTF
// document). One primitive a material (a mesh of the file); glTF gives a vertex one UV and one
// normal, so each primitive's vertices are the file's distinct (vertex, UV, normal, colour)
// corners, each naming its `source`: the vertex of the mesh as read_mesh read it.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace sweep::assets {

struct SurfaceMaterial {
  std::string name;
  std::array<double, 4> colour{1, 1, 1, 1};  // base colour, linear RGBA
  std::string texture;                       // the base colour image's bytes (PNG or JPEG), or empty
  std::string texture_name;                  // where it came from, for names and messages
};

struct SurfacePrimitive {
  int material = -1;                      // into MeshSurface::materials, or -1
  std::vector<std::uint32_t> source;      // per vertex
  std::vector<float> uv, normal, colour;  // 2, 3, 4 floats a vertex (uv as glTF's (u, 1 - v)), or empty
  std::vector<std::uint32_t> triangles;   // into this primitive's vertices
};

struct MeshSurface {
  std::vector<SurfacePrimitive> primitives;
  std::vector<SurfaceMaterial> materials;
};

// FBX (and the other formats read_mesh welds through assimp): each assimp mesh a primitive, its
// corners mapped to the welded vertices exactly as read_mesh welds them; normals in world space
// (the node's transform); materials' diffuse or base colour and texture (embedded in the file, or a
// file beside it). `mesh_name` ("" = the whole file) takes one mesh of the file, or several (a
// list, or kAllMeshes), as read_scene_mesh (mesh_io.h) takes them by name. Error(bad_input) for a texture named but not
// found.
MeshSurface read_welded_surface(const std::filesystem::path& path, const std::string& mesh_name = {});

}  // namespace sweep::assets
