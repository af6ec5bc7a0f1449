#pragma once
// The parts' motion as joints added to a skinned character's OWN skeleton: the default .glb of a
// skinned clip's bake (gltf_passthrough.h writes what this computes; no file format here).
//
// Per part, skin_fit.h's station joints (and ring joints) become new joints of the character's
// skin, each station joint a child of the part's root joint (SkinnedClip::root_joint_node), each
// ring joint a child of its station joint. With M the skinned mesh node's world transform, G_k
// skin_fit's pose of joint k in the mesh's rest world frame (the frame the rig and the binding are
// in) and World_r the root joint's world transform:
//  - inverse bind matrix IBM'_k = G_k(rest)⁻¹ · M (glTF skins POSITION, which M takes to that frame);
//  - a station s is carried by the character's keyed pose through the rigid matrix K_s(t): the
//    rotation of B_s(t) = Σ_i w̄_{s,i} J_i(t) · M⁻¹ (polar decomposition) and the translation that
//    puts the station's rest axis point where B_s puts it, w̄_s the skin weights of the part's bound
//    vertices that skin_fit weights to station s, averaged with those weights. The station joint's
//    world pose at t is K_s(t) · G_s(t), its local key World_r(t)⁻¹ · K_s(t) · G_s(t); a ring joint's
//    key is skin_fit's, relative to its station.
//  - the baked frames: G_s(t) the simulated, deformed sweep's (SkinFit::pose); any clip played
//    alone (clip_keys): G_s = its rest pose, so the part plays its original skinned motion.
//  - weights: a bound vertex with blend b gets skin_fit's station and ring weights (which sum to
//    b) and its own skin weights × (1 − b); the 4 largest are kept, renormalised, summing to 1 in
//    float (the largest takes what rounding leaves). Every other vertex keeps its weights.
// The skinned error (error()): every bound vertex skinned from the values as written (float keys,
// float inverse bind matrices and weights; the original joints' matrices from the clip) against the
// bake's world positions, over the part's length.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sweep/assets/skin_fit.h"
#include "sweep/assets/skinned_clip.h"

namespace sweep::assets {

struct CharacterJoint {
  std::string name;       // skin_fit's ("tail.03", "tail.03.r05"), made unique among the file's nodes
  int parent_node = -1;   // a station joint's parent: a node of the model (the part's root joint)
  int parent_joint = -1;  // a ring joint's parent: its station, an index into joints()
  int sweep = -1;
};

class CharacterJoints {
 public:
  // `rest`: the mesh as read (the rig's frame). Ring joints carry the radial change by their scale
  // (RingMotion::scale, whatever `layout` says). Throws Error(unsupported) when the skin cannot take
  // the joints (more than 65,536 joints in all).
  CharacterJoints(const SkinnedClip& clip, std::vector<SkinSweep> sweeps, const SkinLayout& layout,
                  std::span<const Eigen::Vector3f> rest);
  ~CharacterJoints();
  CharacterJoints(const CharacterJoints&) = delete;
  CharacterJoints& operator=(const CharacterJoints&) = delete;

  const SkinnedClip& clip() const { return clip_; }
  const std::vector<CharacterJoint>& joints() const { return joints_; }
  // The skin's joints before the new ones (the new joint k is skin joint original_joints() + k).
  int original_joints() const { return static_cast<int>(clip_.model().joints.size()); }
  // Per new joint: its local pose with no clip playing (the node's own transform) and IBM'.
  const std::vector<JointKey>& rest_keys() const { return rest_keys_; }
  const std::vector<Eigen::Matrix4f>& inverse_bind() const { return inverse_bind_; }
  // Per vertex of the mesh: 4 skin joints and weights (float); `reweighted` marks the parts'.
  const std::vector<std::array<std::uint16_t, 4>>& vertex_joints() const { return vertex_joints_; }
  const std::vector<std::array<float, 4>>& vertex_weights() const { return vertex_weights_; }
  const std::vector<char>& reweighted() const { return reweighted_; }
  // Whether joint k has a translation and rotation (a station) or a scale (a ring joint, and a
  // station without a ring) channel.
  bool is_station(int k) const { return joints_[static_cast<std::size_t>(k)].parent_joint < 0; }
  bool has_scale(int k) const { return !is_station(k) || layout_.ring <= 1; }

  // Baked frame `frame` (scene time frame / fps): the deformed sweeps in the rig's frame (one per
  // SkinSweep), the bound vertices there (`deformed`) and the bake's world positions (`world`).
  void pose(std::span<const SweepShape* const> shapes, std::span<const Eigen::Vector3f> deformed,
            std::span<const Eigen::Vector3f> world, int frame);
  // Per baked frame, per new joint: its local key (rotations kept on one hemisphere along a track).
  const std::vector<std::vector<JointKey>>& keys() const { return keys_; }
  const SkinError& error() const { return error_; }

  // The station joints' keys that make clip `clip` (an index into the model's clips) play the
  // parts' original skinned motion: times from the clip's start to its end every 1/fps (the end
  // last), and per time the keys of every new joint (ring joints at rest).
  struct ClipKeys {
    std::vector<float> times;
    std::vector<std::vector<JointKey>> keys;  // per time, per new joint
  };
  ClipKeys clip_keys(int clip, double fps) const;

 private:
  struct Station;
  // The new joints' local keys for the joint matrices `j`, the world transforms `world` and
  // skin_fit's keys `fit_keys` (skin_fit's joint order, the body first).
  void local_keys(const std::vector<Eigen::Matrix4d>& j, const std::vector<Eigen::Matrix4d>& world,
                  std::span<const JointKey> fit_keys, double clip_time, std::vector<JointKey>& out) const;

  const SkinnedClip& clip_;
  SkinLayout layout_;
  std::vector<SkinSweep> sweeps_;
  std::unique_ptr<SkinFit> fit_;
  Eigen::Matrix4d mesh_ = Eigen::Matrix4d::Identity(), from_mesh_ = Eigen::Matrix4d::Identity();
  std::vector<CharacterJoint> joints_;
  std::vector<int> root_node_;                                        // per new joint: the root joint node of its part
  std::vector<std::vector<std::pair<int, double>>> station_weights_;  // per new joint (stations): w̄
  std::vector<Vec3> station_centre_;                                  // per new joint (stations): the rest axis point
  std::vector<JointKey> rest_keys_;
  std::vector<Eigen::Matrix4f> inverse_bind_;
  std::vector<std::array<std::uint16_t, 4>> vertex_joints_;
  std::vector<std::array<float, 4>> vertex_weights_;
  std::vector<char> reweighted_;
  std::vector<double> part_length_;  // per vertex of a part: its part's length
  std::vector<std::vector<JointKey>> keys_;
  std::vector<JointKey> fit_keys_;  // scratch
  SkinError error_;
  double sum_squares_ = 0;
};

}  // namespace sweep::assets
