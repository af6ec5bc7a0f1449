#pragma once
// Private to the .glb bake (gltf_passthrough.cpp): a skinned character read through assimp (FBX,
// Collada, ...: assimp_skin.h) made a glTF character, so that its bake writes the same rigged .glb
// as a glTF character's (its skeleton kept, the parts' joints added, or morph targets under the
// skin). Added to the surface document (obj_gltf.h's surface_as_gltf: its materials, UVs and
// normals) from the SkinModel the bake played:
//  - the nodes: the model's, in its order (so that its node numbers are the document's), named as
//    the file names them, under their parents; the skinned mesh on the model's mesh node (made a
//    root when it is a leaf, no joint and unanimated, its transform the one that places the
//    mesh's space in the world as read; glTF's skinning ignores it). A node
//    a clip moves gets its rest translation, rotation and scale (what the clip's channels
//    replace); any other its matrix, as TRS where that decomposition gives it back (1e-9);
//  - the skin: the model's joints and inverse bind matrices;
//  - per vertex (every primitive shares one vertex array): POSITION the model's bind position
//    (the mesh's own space, in which the inverse binds take it), NORMAL turned into that space,
//    JOINTS_0 (unsigned byte up to 256 joints, else unsigned short) and WEIGHTS_0 (float): its up
//    to 4 influences as the model plays them (the 4 largest, renormalised);
//  - one animation a clip, in order, named as the clip: one sampler a channel (its key times in
//    seconds, LINEAR or STEP as the model keys it; where a clip keys a node and path twice, the
//    last, as the model plays it). A clip with no channel keys the root at rest (glTF wants one).
// Played by glTF's skinning, the document shows what the model shows, to float precision. The
// surface's other meshes (the file's meshes besides the skinned one, scene_as_gltf, placed in
// world space) are kept, each on the model's node that shows it in the file, made a root of no
// transform (when that node is a leaf, no joint and moved by no clip; else on a root of its own):
// static, or skinned by the skin where the file skins it by bones that are all joints of the model
// (its 4 largest influences a vertex, renormalised).
#include <Eigen/Geometry>

#include "sweep/assets/gltf_skin.h"
#include "sweep/assets/obj_gltf.h"

namespace sweep::assets::detail {

// `to_world`: the mesh's space as read → world (BakeSource::to_world); the surface's positions and
// normals are world. Throws Error(internal) when the surface's mesh read is not the model's mesh.
void add_skin(SurfaceGltf& gltf, const SkinModel& model, const Eigen::Affine3d& to_world);

}  // namespace sweep::assets::detail
