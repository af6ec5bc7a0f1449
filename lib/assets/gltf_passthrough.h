#pragma once
// Private to the .glb bake writer (bake_gltf.cpp): a bake of a glTF/GLB mesh written as the INPUT
// document plus the bake. Everything in the input is kept as it was — nodes,
// names, transforms, meshes, materials, textures, images, samplers, every attribute, extensions and
// animations — and its bytes are copied unchanged into the one BIN chunk: each input buffer at a
// 16-byte aligned base (its bufferViews re-pointed), then each image that was a file or a data URI
// (now a bufferView with its mimeType). What is added:
//  - on every primitive of each deformed mesh (a glTF mesh with a vertex the bake moves), one morph
//    target per frame: POSITION deltas, NORMAL deltas where the primitive has NORMAL and TANGENT
//    deltas where it has TANGENT, in the primitive's own (mesh-local) space. The importer reads
//    positions in world space (mesh_import.cpp: glTF meshes in order, their primitives in order,
//    each placed by the world transform of the first node showing it, depth first in the default
//    scene; of a file of several meshes, only the primitives BakeSource::parts names, the rig's
//    mesh: the others are never deformed); a world delta is mapped back by the inverse of that
//    node's linear transform. The
//    input's own normals and tangents are turned by the rotation that takes each vertex's smooth
//    rest normal (area-weighted, over the mesh welded by position, so UV seams do not show) to the
//    frame's; a vertex that does not move keeps a zero delta exactly. Targets are sparse: each
//    primitive lists the vertices whose position or normal can change (none: zero accessors).
//  - the mesh's "weights" (zeros) and extras.targetNames ("frame_0000", ...);
//  - one new animation (named "sweep bake", or "sweep bake 2", ... when taken) with a weights
//    channel on every node showing a deformed mesh (one-hot keys at k / fps, LINEAR) and, when the
//    body moves, that node's translation and rotation: its parent-relative transform
//    L(t) = P⁻¹ · B(t) · P · L (P the parent's world transform, L the node's own), so its world
//    transform is B(t) times the rest one, as the bake's positions are. A node given by "matrix"
//    then gets the same transform as translation, rotation and scale. Other nodes do not follow
//    the body (the .pc2 moves every vertex; here only the deformed meshes' nodes are animated),
//    except in a rig of several meshes (BakeSource::mesh_name a list): its meshes that do not bend
//    get the body's keys too (and no weights channel: they have no targets).
//  When no mesh moves (no force reaches a part), the document is written as it was, with no
//  animation added.
//  A skinned character's clip (BakeInfo::skinned): the skinned mesh keeps its skin, and each frame's
//  target is taken back under it — a vertex's world offset from its skinned pose, Δ = p − S·b
//  (S = Σ w_i J_i its skinning matrix at the frame, b its POSITION), becomes A⁻¹·Δ with A the 3×3
//  linear part of S, since glTF applies morph targets before skinning: skinning the target
//  reproduces the bake to float precision. Targets list the parts' vertices (BakeInfo::part_vertices)
//  and their face neighbours; normals and tangents are turned in world space and taken back by A⁻¹
//  as well. The new animation holds the weights channel and every channel of the clip resampled at
//  the frame times (the clip time each frame played: looped or held, after any preroll), LINEAR,
//  so an engine playing it alone shows the bake; the file's clips are kept as they were.
//  A vertex whose skinning matrix is singular at some frame is refused then (Error(unsupported)).
//  With BakeInfo::character_joints (sweep-sim's default for a skinned clip) no target is added:
//  the parts' joints join the character's skeleton instead (gltf_character_joints.h), and the new
//  animation holds the resampled channels and their keys.
//  Another skinned mesh that moves, with no clip of its skin driving the bake, is refused.
// Refused, before anything is simulated (Error(unsupported), exit 3, naming the file and what):
// compressed geometry (KHR_draco_mesh_compression, EXT/KHR_meshopt_compression), a deformed
// primitive that already has morph targets or whose POSITION, NORMAL or TANGENT is not a plain
// float accessor (sparse, quantized), a deformed mesh shown by several nodes with different world
// transforms, or by a skinned node whose clip does not drive the bake, and a moving body under a parent that is not a
// similarity (rotation, uniform scale, translation). A buffer or image that cannot be read is Error(bad_input). An OBJ
// source with UVs, normals, colours or materials is first made a glTF document (obj_gltf.h); its vertices are split per
// corner, so each primitive vertex names its source vertex in the mesh as read, and the targets follow that vertex.
// Any other format assimp reads (FBX, Collada, .x, .blend, ...) is made one the same way, every mesh of the file on a
// node of its own (scene_as_gltf: the rig's meshes carry the targets, and with a moving body the keys; the others stay
// still), and a skinned character's gets its skeleton, skin and clips too (skin_gltf.h).
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <span>
#include <vector>

#include "sweep/assets/bake.h"
#include "sweep/core/mesh.h"

namespace sweep::assets::detail {

// Whether a bake of a mesh read from `source` may write the passthrough .glb (a .gltf, .glb, an
// .obj — its UVs, normals, colours and materials become a glTF document first, obj_gltf.h — or any
// other format assimp reads but OFF, PLY and STL, which hold one mesh and no materials).
bool is_passthrough_source(const std::filesystem::path& source);

struct BinBlock {
  std::uint64_t offset = 0, length = 0;
};
// Appends bytes to the BIN chunk being built and says where they went.
using AppendBin = std::function<BinBlock(const void*, std::size_t)>;

class GltfPassthrough {
 public:
  // Reads and checks `source` against `rest` (the mesh the bake deforms, as read_mesh read it) and
  // `animated` (ascending vertices that may move). `out` names the output in messages.
  GltfPassthrough(const std::filesystem::path& source, const std::filesystem::path& out, const Mesh& rest,
                  const std::vector<std::uint32_t>& animated, const BakeInfo& info);
  // The passthrough for `source`, or nullptr when it is an OBJ with no UVs, normals, colours or
  // materials (the plain .glb then).
  static std::unique_ptr<GltfPassthrough> open(const std::filesystem::path& source, const std::filesystem::path& out,
                                               const Mesh& rest, const std::vector<std::uint32_t>& animated,
                                               const BakeInfo& info);
  ~GltfPassthrough();
  GltfPassthrough(const GltfPassthrough&) = delete;
  GltfPassthrough& operator=(const GltfPassthrough&) = delete;

  // The BIN chunk's size before the frames and what each frame adds (for the size estimate).
  std::uint64_t fixed_bytes() const;
  // The input document's JSON text, as it will be written before the bake's additions.
  std::uint64_t json_bytes() const;
  std::uint64_t bytes_per_frame() const;
  // Deformed primitives (JSON added per frame: three accessors and views each).
  std::size_t deformed_primitives() const;
  // Writes the input's bytes, the key times and weights and the targets' index lists: must be the
  // first thing in the BIN chunk (offset 0).
  void start(const AppendBin& append);
  // One frame: positions in the body's frame (world at rest), the body's pose.
  void frame(std::span<const Eigen::Vector3f> positions, const BodyPose& body, const AppendBin& append);
  // The document: the input's JSON with the additions, all but "buffers" (the caller's: the one
  // BIN buffer). Call once, after every frame (appends the body's keys).
  nlohmann::json finish(const AppendBin& append);

  struct State;  // gltf_passthrough.cpp's

 private:
  std::unique_ptr<State> s_;
};

}  // namespace sweep::assets::detail
