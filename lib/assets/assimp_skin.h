#pragma once
// A skinned mesh and its clips from the files assimp reads besides glTF (FBX, Collada, DirectX .x,
// ...), as the same plain data as a glTF skin (gltf_skin.h), so that a skinned character's clip
// drives a bake whatever its format (skinned_clip.h).
//
// assimp's model of a skin is glTF's: each bone names a node and carries its offset matrix, which
// takes the mesh's own space to the bone's at bind time, so J_k(t) = World(bone_k, t) · offset_k —
// glTF's World · IBM — and a vertex is Σ w_i J_{k_i}(t) v_bind. Nodes keep their transforms as
// assimp gives them (an FBX's pivots become assimp's "$AssimpFbx$" helper nodes, which clips key
// like any other); an animated node's rest transform is its matrix decomposed into translation,
// rotation and scale, which the clip's channels replace. Channels are keyed LINEAR (STEP where
// assimp marks a key so); key times are the file's ticks over its ticks per second (25 when the
// file states none, as assimp's own players take it).
//
// The mesh read (read_scene_mesh: its vertices welded by exact position, in world space) is matched
// to assimp's vertices by position: every vertex read must be a vertex of a skinned importer mesh
// of one node, and the copies of one position (assimp gives an FBX polygon corner its own vertex)
// must carry the same weights.
#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <span>

#include "sweep/assets/gltf_skin.h"

namespace sweep::assets {

// The skin of `file` (not glTF) whose vertices the mesh read from it has (`read_positions`, world
// space at rest; `to_world` its node's transform). nullopt when no mesh of the file has bones.
// Throws Error(bad_input) naming the file and what is wrong: a vertex with no weight, copies of a
// vertex weighted differently, a bone naming no node, an offset matrix that is not an invertible
// affine transform, a channel whose keys cannot be read; Error(unsupported) when a vertex of the
// mesh read is in no skinned mesh or the skinned meshes are shown by several nodes. A vertex of
// more than 4 influences plays its 4 largest, renormalised (as engines play a skin), said in
// SkinModel::warnings.
std::optional<SkinModel> read_assimp_skin(const std::filesystem::path& file, std::span<const Vec3> read_positions,
                                          const Eigen::Affine3d& to_world);

// read_gltf_skin for .gltf and .glb, read_assimp_skin for any other file.
std::optional<SkinModel> read_skin(const std::filesystem::path& file, std::span<const Vec3> read_positions,
                                   const Eigen::Affine3d& to_world);

}  // namespace sweep::assets
