#pragma once
// The skinned .glb bake (issue 14, "bones for engines"): instead of one morph target a frame, a
// skeleton whose joints follow the simulated sweeps, and a mesh skinned to it (linear blend
// skinning, at most 4 joints a vertex), which every engine plays natively.
//
// What it writes (glTF 2.0 binary, validator-clean, no axis conversion, like the morph writer):
//  - node 0, "<name>_root": the body joint. Every vertex no sweep binds is weighted to it alone.
//    When the body moves (BakeInfo::body_moves) its translation and rotation are the body's pose,
//    animated as the morph writer animates its node; otherwise it stays at the identity.
//  - per sweep, N joints "<sweep>.00" … at N evenly spaced stations t_j = L·j/(N−1) along the sweep,
//    root (j = 0) to tip (j = N−1), children of the body joint. Joint j's transform, in the body's
//    frame, is the deformed sweep's frame at t_j: translation C'(t_j), rotation R'(t_j) (the frame
//    whose z is the sweep's axis), and the cross-section's change as well as one joint can carry
//    it: in the station's plane a scale along each axis and a shift, (a, b, 1) and R'·(c_x, c_y, 0)
//    added to the translation, fitted by least squares to the section's radii at t_j against the
//    rest's (an even swell: a = b, the mean radius ratio, no shift; a squeeze from one side: less
//    scale across it and a shift away from it). The joints are siblings rather than parent and
//    child because glTF composes a child with its parent's scale, and a non-uniform scale followed
//    by a rotation is a shear no TRS
//    node can express; the chain is their order and names. Inverse bind matrices: the rest frames'.
//  - the mesh: rest POSITION, smooth rest NORMAL, triangles, JOINTS_0 (unsigned byte when the skin
//    has at most 256 joints, else unsigned short), WEIGHTS_0 (float). A vertex bound at parameter t
//    (in span j of the stations, u = t/h − j) gets joints j and j+1 with weights (1 − u)·b and u·b,
//    and the body joint 1 − b, b its blend weight (bind.h): a hat function of t, smooth across
//    stations, the weights non-negative and summing to 1 (the last one as 1 minus the others).
//  - one animation "bake": per joint that moves, translation, rotation and scale channels keyed at
//    k / fps, LINEAR (rotations kept on one hemisphere, so slerp takes the short way).
//
// Its error against the bake it is given: each frame the writer skins the bound vertices itself,
// from the very float values it writes (joint TRS, inverse bind matrices, weights), and measures
// the distance to the positions frame() received (the exact or fast bake, in the body's frame),
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

#include "assets/bake.h"
#include "bind/bind.h"
#include "core/sweep_shape.h"

namespace sweep::io {

// Joints a sweep may have: at least its two ends; at most 255 (the byte-sized joint index of a
// skin of one sweep plus the body joint).
inline constexpr int kMinSkinJoints = 2;
inline constexpr int kMaxSkinJoints = 255;

// One sweep of the skin: its rest shape and its binding (both must outlive the writer).
struct SkinSweep {
  std::string name;
  const SweepShape* rest = nullptr;
  const bind::SweepBinding* binding = nullptr;
};

// The skinned result against the bake (fractions of the sweep's length; 0.01 is 1 %).
struct SkinError {
  double max_relative = 0;  // largest distance / L over every bound vertex of every frame
  double rms_relative = 0;  // root mean square of the same
  int max_frame = 0;        // where the largest was first reached
  std::uint32_t max_vertex = 0;
  std::uint64_t samples = 0;  // vertex-frames measured
};

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

// Checks a joint count per sweep against kMinSkinJoints … kMaxSkinJoints and each sweep's station
// count (a joint per station at most: (K − 1)·stations_per_span + 1); throws Error(usage) with a
// message naming --joints otherwise.
void check_skin_joints(int joints, std::span<const SkinSweep> sweeps, int stations_per_span);

// A skinned .glb writer for `out` (extension not checked) with `joints` joints per sweep.
SkinBakeWriter make_skin_bake_writer(const std::filesystem::path& out, std::vector<SkinSweep> sweeps,
                                     int joints);

}  // namespace sweep::io
