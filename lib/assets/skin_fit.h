#pragma once
// The skeleton of the skinned .glb (bake_skin.h) without any file format: which joints a skin has,
// how each vertex is weighted to them, and, frame by frame, the joints' poses that reproduce the
// simulated sweeps, with the skinned result's error against the bake. bake_skin.cpp writes what
// this computes as glTF.
//
// Joints (skin joint index = glTF node index): 0 is the body. Per sweep, N station joints at
// t_j = L·j/(N−1), children of the body, each carrying the deformed sweep's frame at t_j
// (translation C'(t_j), rotation R'(t_j), z along the axis). With a ring (M ≥ 2), every station
// but the root (section 0 never moves in the body's frame, radii included) has M ring joints at the
// angles φ_m = 2πm/M, children of their station joint, which carry the radial change at φ_m (see
// RingMotion) and nothing else; the station joints then have no scale, so a child never inherits
// a non-uniform scale (glTF would shear it). Without a ring (M = 1) the station joint carries the
// section's change itself: an in-plane scale per axis and a shift, fitted by least squares to the
// section's radii (what one joint can carry of an uneven squeeze).
//
// Weights: a bound vertex at (t, θ) in span j (u = t/h − j) and angle cell m (w = θ/(2π/M) − m),
// blend weight b (bind.h): (1−u)·b on station j and u·b on station j+1, each split over the ring
// joints m and m+1 of that station as 1−w and w (bilinear: a hat in t times a hat in θ, continuous
// across stations and angles); the root station's share stays on its station joint; 1−b on the
// body. At most 4 joints: only a blended vertex (b < 1) beyond the first span could reach 5 (a
// tip cut's blend, a blend deeper than a span); it keeps the ring split at the station it is
// nearer and puts the other station's share on that station joint (frame only, no radial change).
// Weights are non-negative and sum to 1 in float.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sweep/bind/bind.h"
#include "sweep/core/sweep_shape.h"

namespace sweep::assets {

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

// How a ring joint carries the radial change at its angle φ.
enum class RingMotion {
  // An in-plane scale (ρ, ρ, 1): a vertex between two ring joints is scaled towards the axis by
  // the blend of their ρ, along its own direction, whatever its depth (the sweep's own rule,
  // v = C + R·(s·r(θ)·(cos θ, sin θ), z), with r scaled by ρ). The default: measured better
  // (a one-handle dent on the test tube, 6 × 8 joints: 0.0061 of the length against 0.0084).
  scale,
  // A translation τ along the joint's radial direction (cos φ, sin φ, 0): the same shift for every
  // vertex it weighs, on the surface or deep inside.
  shift,
};

struct SkinLayout {
  int stations = 8;  // N joints along each sweep, ≥ 2 (--joints)
  int ring = 1;      // M ring joints at each station but the root; 1 = none (--ring-joints)
  RingMotion motion = RingMotion::scale;
  // Ring joints' keys fitted each frame by least squares over the vertices they weigh (all the
  // sweep's ring joints at once: a vertex weighs two stations), pulled lightly towards the change
  // sampled at the joint's angle (kRingFitPull); false: the sampled change alone. The fit also
  // takes up some of the stations' error between them, so every ring joint moves and is keyed:
  // on the Fig. 4 scene 24 × 24 joints fall from 0.48 % to 0.19 % of the length, the file grows
  // from 2.7 to 10.8 MB (BENCHMARKS.md). Off by default (--ring-fit).
  bool fit = false;
};

// The weight of the pull towards the sampled change in the ring fit, as a share of one vertex on
// the surface at the joint (unitless): keeps a ring joint that weighs no vertex at its sample and
// never outweighs a real vertex.
inline constexpr double kRingFitPull = 1e-3;

// One joint's pose as written: translation, rotation (x, y, z, w), scale, relative to its parent.
struct JointKey {
  float t[3];
  float r[4];
  float s[3];
  bool operator==(const JointKey& o) const;
};
static_assert(sizeof(JointKey) == 40);
inline constexpr JointKey kIdentityKey{{0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}};

// The matrix a joint key stands for, T·R·S, in double from the floats (the rotation normalized, as
// engines do).
Eigen::Matrix4d key_matrix(const JointKey& k);

struct SkinJoint {
  std::string name;  // "<sweep>.03" (station 3), "<sweep>.03.r05" (its ring joint 5)
  int parent = -1;   // skin joint index; -1 for the body
  int sweep = -1;    // -1 for the body
  int station = -1;
  int ring = -1;     // -1 for a station joint
  double t = 0;      // the station's parameter, mesh units
  double angle = 0;  // a ring joint's φ, radians
};

class SkinFit {
 public:
  // Throws Error(internal) when a binding names a vertex outside `rest` or twice.
  SkinFit(std::vector<SkinSweep> sweeps, const SkinLayout& layout, std::span<const Eigen::Vector3f> rest,
          const std::string& body_name);
  ~SkinFit();
  SkinFit(const SkinFit&) = delete;
  SkinFit& operator=(const SkinFit&) = delete;

  int joint_count() const { return static_cast<int>(joints_.size()); }
  const std::vector<SkinJoint>& joints() const { return joints_; }
  // Per joint: its rest pose relative to its parent (the node's defaults) and the inverse of its
  // rest pose in the body's frame.
  const std::vector<JointKey>& rest_keys() const { return rest_keys_; }
  const std::vector<Eigen::Matrix4f>& inverse_bind() const { return inverse_bind_; }
  // Per vertex: 4 skin joints and their weights (unused slots: joint 0, weight 0).
  const std::vector<std::array<std::uint16_t, 4>>& vertex_joints() const { return vertex_joints_; }
  const std::vector<std::array<float, 4>>& vertex_weights() const { return vertex_weights_; }

  // One frame: `shapes`, the deformed sweeps in the body's frame (one per SkinSweep, same order),
  // and `positions`, the bake's vertices in the body's frame. Writes every joint's key into `keys`
  // (joint_count() of them; the body's stays the identity) and adds the frame to error().
  void pose(std::span<const SweepShape* const> shapes, std::span<const Eigen::Vector3f> positions, int frame,
            std::span<JointKey> keys);
  const SkinError& error() const { return error_; }

 private:
  struct SweepData;
  std::vector<SkinSweep> sweeps_;
  SkinLayout layout_;
  std::vector<Eigen::Vector3f> rest_;
  std::vector<SkinJoint> joints_;
  std::vector<JointKey> rest_keys_;
  std::vector<Eigen::Matrix4f> inverse_bind_;
  std::vector<std::array<std::uint16_t, 4>> vertex_joints_;
  std::vector<std::array<float, 4>> vertex_weights_;
  std::vector<std::unique_ptr<SweepData>> data_;
  std::vector<Eigen::Matrix4d> skinning_;  // per joint, this frame (scratch)
  std::vector<Eigen::Matrix4d> global_;    // per joint, this frame (scratch)
  SkinError error_;
  double sum_squares_ = 0;
};

}  // namespace sweep::assets
