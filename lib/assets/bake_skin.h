#pragma once
// The skinned .glb bake ("bones for engines"): instead of one morph target a frame, a
// skeleton whose joints follow the simulated sweeps, and a mesh skinned to it (linear blend
// skinning, at most 4 joints a vertex), which every engine plays natively.
//
// What it writes (glTF 2.0 binary, validator-clean, no axis conversion, like the morph writer):
//  - node 0, "<name>_root": the body joint. Every vertex no sweep binds is weighted to it alone.
//    When the body moves (BakeInfo::body_moves) its translation and rotation are the body's pose,
//    animated as the morph writer animates its node; otherwise it stays at the identity.
//  - the skeleton of skin_fit.h, in its joint order (skin joint k is node k): per sweep N station
//    joints "<sweep>.00" … (children of the body joint) and, with a ring of M ≥ 2, M ring joints
//    "<sweep>.03.r05" … at every station but the root (children of their station joint, keyed by
//    scale alone). Inverse bind matrices: the rest poses'.
//  - the mesh: rest POSITION, smooth rest NORMAL, triangles, JOINTS_0 (unsigned byte when the skin
//    has at most 256 joints, else unsigned short), WEIGHTS_0 (float): skin_fit.h's weights, at most
//    4 a vertex, non-negative, summing to 1.
//  - one animation "bake": per joint that moves, its channels keyed at k / fps, LINEAR (rotations
//    kept on one hemisphere, so slerp takes the short way): a station joint's translation and
//    rotation (and scale without a ring), a ring joint's scale (or translation, RingMotion::shift).
//
// Its error against the bake it is given: each frame the skin is posed (SkinFit::pose) and the
// bound vertices skinned from the very float values it writes (joint TRS, inverse bind matrices,
// weights), against the positions frame() received (the exact or fast bake, in the body's frame),
// over the length of the vertex's sweep: the largest and the root mean square over every bound
// vertex of every frame (skin_error()).
//
// The joints' keys are kept in memory until finish() (40 bytes a joint a frame); the rest of the
// protocol, the atomicity (temporaries renamed in finish()) and the determinism are the other
// writers' (bake.h).
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sweep/assets/bake.h"
#include "sweep/assets/skin_fit.h"
#include "sweep/bind/bind.h"
#include "sweep/core/rig.h"
#include "sweep/core/sweep_shape.h"

namespace sweep::assets {

// Station joints a sweep may have (--joints): at least its two ends; at most 255.
inline constexpr int kMinSkinJoints = 2;
inline constexpr int kMaxSkinJoints = 255;
// Ring joints a station may have (--ring-joints): 1 (none: the station joint carries the section's
// change) to 64.
inline constexpr int kMaxRingJoints = 64;
// The defaults (--joints without a number): a joint a key section and a ring joint a radial handle
// of sweep-fit's default K = n = 24 (a one-handle dent then lies on a ring joint). On the
// diplodocus Fig. 4 scene, 601 frames, they keep the skinned result within 0.48 % of each part's
// length at 1/29 of the morph-target bake's size: only the ring joints whose handles move are
// keyed (BENCHMARKS.md, "Skinned .glb").
inline constexpr int kDefaultSkinJoints = 24;
inline constexpr int kDefaultRingJoints = 24;

// What the bake driver gives the skin writer beside the positions: before each frame(), the
// deformed shape of every sweep (one per SkinSweep, same order) in the body's frame.
class SkinPoser {
 public:
  virtual ~SkinPoser() = default;
  virtual void pose(std::span<const SweepShape* const> shapes) = 0;
  virtual const SkinError& skin_error() const = 0;
  virtual int joint_count() const = 0;  // in the skin, the body joint included
};

struct SkinBakeWriter {
  std::unique_ptr<BakeWriter> writer;
  SkinPoser* poser = nullptr;  // the same object, seen as a SkinPoser
};

// The stations a sweep of `rest` is sampled at: (K − 1)·stations_per_span + 1, at most a joint each.
int skin_stations(const SweepShape& rest, int stations_per_span);

// The station joints of --joints without a number: kDefaultSkinJoints or, where a sweep has fewer
// stations, as many as the fewest any sweep has (at least kMinSkinJoints; one N serves every
// sweep); `fewest` is the sweep that set it (nullptr: the default stands).
struct DefaultSkinJoints {
  int joints = kDefaultSkinJoints;
  const SweepDef* fewest = nullptr;
};
DefaultSkinJoints default_skin_joints(std::span<const SweepDef> sweeps, int stations_per_span);

// Checks the layout's station joints against kMinSkinJoints … kMaxSkinJoints and each sweep's
// station count (a joint per station at most: (K − 1)·stations_per_span + 1), and its ring joints
// against 1 … kMaxRingJoints; throws Error(usage) with a message naming --joints or --ring-joints
// otherwise.
void check_skin_joints(const SkinLayout& layout, std::span<const SkinSweep> sweeps, int stations_per_span);

// A skinned .glb writer for `out` (extension not checked).
SkinBakeWriter make_skin_bake_writer(const std::filesystem::path& out, std::vector<SkinSweep> sweeps,
                                     const SkinLayout& layout);

}  // namespace sweep::assets
