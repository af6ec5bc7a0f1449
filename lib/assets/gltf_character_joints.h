#pragma once
// Private to the passthrough .glb (gltf_passthrough.cpp): writes a skinned clip's bake as joints
// added to the character's own skeleton (character_joints.h) into the input document. Added:
//  - a node per new joint, under the part's root joint (a ring joint under its station), its own
//    transform the pose with no clip playing;
//  - the new joints appended to the skin's "joints", with a new inverse bind matrices accessor (the
//    skin's own matrices unchanged, then the new joints');
//  - per primitive of the skinned mesh, new JOINTS_0 and WEIGHTS_0 accessors (JOINTS_0 unsigned
//    short past 256 joints; WEIGHTS_0 in the input's component type, normalized integers rounded
//    so that each vertex's sum is exact): every vertex outside the parts keeps its values;
//  - the animation "sweep bake" ("sweep bake 2", ... when taken): the driving clip's channels
//    resampled at the frame times, and the new joints' keys (stations: translation and rotation,
//    and scale without a ring; ring joints that move: scale), LINEAR;
//  - in every animation of the input, the station joints keyed so that the parts play their
//    original skinned motion (every 1/fps from the clip's start to its end, LINEAR), and the ring
//    joints keyed in "sweep bake" held at rest.
#include <nlohmann/json.hpp>
#include <span>
#include <vector>

#include "sweep/assets/character_joints.h"
#include "sweep/assets/gltf_passthrough.h"
#include "sweep/assets/gltf_skin.h"

namespace sweep::assets::detail {

// A channel of the driving clip resampled at the frame times (float values in `block`).
struct ResampledChannel {
  int node = 0;
  ChannelPath path = ChannelPath::translation;
  BinBlock block;
};

// A primitive of the input and, per vertex, its vertex in the mesh as read.
struct PrimitiveSource {
  std::size_t mesh = 0, index = 0;
  const std::vector<std::uint32_t>* source = nullptr;
};

struct BakedFrames {
  int frames = 0;
  double fps = 30;
  BinBlock times;  // the frame times (float), already in the BIN chunk
  float last_time = 0;
};

// `put` appends bytes at a 4-byte boundary. Throws Error(unsupported) (`where` first) for a
// skinned mesh primitive whose JOINTS_0 or WEIGHTS_0 is missing.
void add_character_joints(nlohmann::json& json, const CharacterJoints& joints,
                          std::span<const ResampledChannel> resampled, const BakedFrames& baked,
                          std::span<const PrimitiveSource> primitives, const AppendBin& put, const std::string& where);

}  // namespace sweep::assets::detail
