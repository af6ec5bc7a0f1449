#pragma once
// Private to the .glb bake (gltf_passthrough.cpp): a file's surface (mesh_surface.h; an FBX's from
// mesh_import.cpp) as a glTF document, and an OBJ's surface — its UVs (`vt`), normals
// (`vn`), vertex colours (`v x y z r g b`) and materials (`usemtl`, `mtllib`: Kd, d, map_Kd) — as a
// glTF document, so that the passthrough .glb carries them. One node and one
// mesh named after the file; one primitive per material, in order of first use, its faces fanned
// into triangles as Mesh::triangles() does. glTF gives a vertex one UV and one normal, so a vertex
// is split where its corners differ (a UV seam, a hard edge): the primitives share one vertex
// array, the mesh's vertices first in its order (each with its first corner's attributes), then a
// copy for each differing corner; `sources` says which mesh vertex (the `v`, 0-based) each is. Positions are the mesh's
// as float32; UVs become (u, 1 - v) (glTF's origin is the top left); normals are normalized; a texture is embedded (PNG
// or JPEG, by its bytes). An attribute is written on a primitive only when all its corners have it.
#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <optional>
#include <vector>

#include "sweep/assets/gltf_document.h"
#include "sweep/assets/mesh_surface.h"
#include "sweep/core/mesh.h"

namespace sweep::assets::detail {

struct SurfaceGltf {
  GltfDocument doc;                                 // buffers[0]: the bytes, in memory
  std::vector<std::vector<std::uint32_t>> sources;  // per primitive, per vertex: the mesh vertex (empty: a
                                                    // primitive of no vertex of the mesh read, never moved)
  std::vector<std::size_t> primitive_mesh;          // per primitive (counted over the meshes): its glTF mesh
  // Per glTF mesh (scene_as_gltf): a mesh of the file skinned by bones, its skin per vertex of its
  // array (SurfaceSkin's bind positions and influences), and its node's world 3×3 part; else none.
  struct Bones {
    SurfaceSkin skin;
    Eigen::Matrix3d to_world_linear;
  };
  std::vector<std::optional<Bones>> mesh_bones;
};

// nullopt when the OBJ has none of vt, vn, vertex colours or usemtl (the plain .glb then serves).
// A material library that cannot be read, a colour, UV or Kd that is not finite, a face's vt or
// vn index out of range: Error(bad_input) naming the file and line. A texture that cannot be read
// (map_Kd; "\" separators are read as "/"): a warning (`warn`), the material kept without it.
std::optional<SurfaceGltf> obj_as_gltf(const std::filesystem::path& obj, const Mesh& rest,
                                       const std::function<void(const std::string&)>& warn = {});

// Any file's surface (mesh_surface.h) as such a document, named after `file`: one primitive a
// surface primitive, its positions the mesh's (float32) at each vertex's source.
SurfaceGltf surface_as_gltf(const MeshSurface& surface, const Mesh& rest, const std::filesystem::path& file);

// Every mesh of a file read through assimp (read_scene_surface) as such a document: one root node
// a node of the file that shows meshes, in the file's order, named as it is, showing a mesh of its
// own (named as its mesh, else as the node) placed in world space as read (the node's transform
// baked into its positions, so the node has none); each mesh one vertex array as above, its
// materials the file's. The meshes of the mesh read (SurfaceNode::read_as) name its vertices in
// `sources` (checked by exact position); the others have none: the bake leaves them where they are.
// Error(unsupported) when a node mixes importer meshes of the mesh read with others.
SurfaceGltf scene_as_gltf(const SceneSurface& scene, const Mesh& rest, const std::filesystem::path& file);

}  // namespace sweep::assets::detail
