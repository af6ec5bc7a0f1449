#pragma once
// What a mesh file says about its surface beyond positions and faces — UVs, normals, vertex colours
// and materials — for the .glb bake to carry (obj_gltf.h makes it a glTF
// document). One primitive a material (a mesh of the file); glTF gives a vertex one UV and one
// normal, so each primitive's vertices are the file's distinct (vertex, UV, normal, colour)
// corners, each naming its `source`: the vertex of the mesh as read_mesh read it.
#include <Eigen/Core>
#include <array>
#include <climits>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sweep/core/mesh.h"

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

// FBX (and the other formats read_mesh welds through assimp), every mesh of the file, for the .glb
// bake that keeps them all: one SurfaceNode a node that shows meshes, depth first (the file's node
// order, as read_scene_mesh lists them), each with its own vertices — welded per importer mesh in
// world space as read_mesh welds them — and one primitive an importer mesh (sources into those
// vertices; corners mapped to the welded vertices exactly as read_mesh welds them; normals in world
// space, one of no length or not finite replaced by its face's; materials' diffuse or base colour
// and texture, embedded in the file or a file beside it, shared in SceneSurface::materials).
// `read_as` says which vertices are the mesh `mesh_name` takes ("" = the whole file; one mesh of
// the file, or several: a list, or kAllMeshes, as read_scene_mesh (mesh_io.h) takes them by name:
// the rig's mesh), by the number that mesh gives them: an importer mesh is the rig's where that
// mesh places the same importer mesh by the same world transform (the first node showing it,
// depth first, for the whole file). A texture named but not found: a warning (`warn`), the material
// kept with its base colour; without `warn`, Error(bad_input). A name no mesh has: Error(bad_input).
inline constexpr std::uint32_t kNotRead = UINT32_MAX;
// A mesh skinned by bones (assimp's skin: a bone names a node and carries its offset, the inverse
// bind matrix): per vertex its position in the mesh's own space, which the offsets take, and its
// influences (an index into `bones`, a weight > 0), as the file gives them.
struct SurfaceSkin {
  std::vector<std::string> bones;  // the nodes' names
  std::vector<Vec3> bind;
  std::vector<std::vector<std::pair<std::uint32_t, double>>> influences;
};
struct SurfaceNode {
  std::string name;       // its node's, as the file names it
  std::string mesh_name;  // its mesh's (SceneMeshEntry::mesh_name), or ""
  std::vector<Vec3> positions;
  std::vector<std::uint32_t> read_as;  // per vertex: its vertex in the mesh read, or kNotRead
  std::vector<SurfacePrimitive> primitives;
  std::optional<SurfaceSkin> skin;                                // when every importer mesh it shows has bones
  Eigen::Matrix3d to_world_linear = Eigen::Matrix3d::Identity();  // its node's world transform's 3×3 part
};
struct SceneSurface {
  std::vector<SurfaceNode> nodes;
  std::vector<SurfaceMaterial> materials;
};
SceneSurface read_scene_surface(const std::filesystem::path& path, const std::string& mesh_name = {},
                                const std::function<void(const std::string&)>& warn = {});

}  // namespace sweep::assets
