#pragma once
// A skinned character's own clip driving a bake (scene "body": {"node", "animation", "loop",
// "preroll"} on a skinned glTF mesh). Every vertex outside the parts follows the clip by linear
// blend skinning (gltf_skin.h). Each part's root follows its root joint: the joint with the most
// skin weight on the part's root ring (the bound vertices within 2 % of the part's length of its
// root). It is found here, from the mesh's weights, not stored in the rig: the weights are in the
// mesh file the rig already names, so a rig fitted before skins were read works unchanged, and
// re-weighting the mesh cannot leave a stale joint in the rig. The part's rigid motion is
//     B_i(t) = J_r(t) · M⁻¹     (J_r = World(r, t) · IBM_r, M the mesh node's transform)
// which takes the mesh as read (world space at rest) to the pose at t: a vertex skinned to r alone
// follows it exactly. The simulator sees it as a body path of its own: linear pieces through
// samples twice a frame (every frame time among them), each sample a kink the part feels as a
// kick. Eight a frame changed a walking tail's swing by under 0.01 degrees at several times the
// simulation's cost (the simulator scans its kinks each step); the smooth cubic path turns a 3-D
// rotation through its rotation vector and left a looping bake's cycles unequal, so it is not
// used. The part feels its root's acceleration, turning, centrifugal and Coriolis loads, and
// deforms away from its rest in its root's frame. The part's
// own keyed pose is what it deforms around (the spring-bone pattern: the keyed pose composed with
// the simulated deviation): a bound vertex is placed by its own skinning matrix,
//     M_v(t) · p,    M_v(t) = Σ_i w_i J_{k_i}(t) · M⁻¹
// with p its position deformed by the part in the mesh's frame, so that a part at rest is exactly
// its skinned pose, and its deviation turns with the keyed bend of the joints that skin it.
// The keyed bend's own accelerations load the springs too (a tail whose joints are keyed to sway
// while the hip stands still lags and overshoots its keys): each section's centre is placed in the
// keyed pose by the mean skin weights of the bound vertices nearest it along the part, taken to its
// root's frame, and its acceleration there, a_key, loads the section as the root's acceleration at
// its centre does, so that its deviation q obeys m q'' + c q' + k q = −m a_key (sim/keyed_bend.h;
// the paper's springs: each section's positional spring; material mode: through the joints, as
// weight). The sections are point masses, as for the root's loads, so the keyed turning of a
// section enters only through its centre's acceleration, and the Coriolis and centrifugal terms of
// the keyed motion in a turning root are left out. a_key is the second difference of the keyed
// centres at the simulator's internal step h on its own clock (the looped clip's time, so a clip
// whose last pose is its first has no seam): its relative error is (ωh)²/12 for a sway at ω (4e-4
// at 5 Hz at the default 1/480 s step), and a corner of LINEAR keys is its exact change of
// velocity spread over 2h. A STEP key, and the seam of a loop whose ends differ, are cuts: the
// part takes the jump with its deviation unchanged, without feeling it.
//
// Time: scene time τ (frame k at k / fps) maps to the clip's time start + τ, held at its ends, or
// with `loop` start + (τ mod its length); `preroll` seconds (rounded to whole frames) are simulated
// before frame 0, so that a looping bake starts in steady motion.
#include <Eigen/Geometry>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "sweep/assets/gltf_skin.h"
#include "sweep/bind/bind.h"
#include "sweep/core/rig.h"
#include "sweep/sim/body_path.h"
#include "sweep/sim/keyed_bend.h"

namespace sweep::assets {

class SkinnedClip {
 public:
  // Checks the scene's node and clip against the model and finds each part's root joint. Throws
  // Error(bad_input) naming the file and listing what it holds: an unknown node (not the skinned
  // mesh's node nor a joint of its skin), an unknown clip, a clip that moves none of the skin's
  // joints, a part's root joint that is scaled or sheared by the clip.
  SkinnedClip(const std::filesystem::path& file, SkinModel model, const Eigen::Affine3d& to_world, const Rig& rig,
              const bind::Binding& binding, const std::string& node, const std::string& animation, bool loop,
              double preroll_seconds, double fps);

  int preroll_frames() const { return preroll_frames_; }
  double fps() const { return fps_; }
  double clip_time(double scene_time) const;
  const std::string& clip_name() const { return model_.clips[clip_].name; }
  int clip() const { return clip_; }  // into model().clips
  // The joint node each sweep's root follows.
  int root_joint_node(int sweep) const { return model_.joints[root_joint_[sweep]]; }
  const SkinModel& model() const { return model_; }

  // The joint matrices at scene time τ.
  std::vector<Eigen::Matrix4d> joint_matrices_at(double scene_time) const;
  // Every node's world transform at scene time τ (the clip at clip_time(τ)).
  std::vector<Eigen::Matrix4d> world_at(double scene_time) const;
  // M, the skinned mesh node's world transform (the mesh as read is M · POSITION).
  Eigen::Matrix4d mesh_transform() const { return from_mesh_.inverse().matrix(); }
  // B_i from the joint matrices.
  Eigen::Affine3d part_transform(const std::vector<Eigen::Matrix4d>& joints, int sweep) const;
  // Sweep i's root motion from scene time −preroll to `duration`, on the simulator's clock
  // (simulator time 0 = scene time −preroll).
  sim::BodyPath sweep_path(int sweep, double duration) const;
  // Sweep i's keyed bend over the same time, sampled about every `spacing` seconds on the same
  // clock (the simulator's internal step): each section's keyed acceleration relative to its root.
  // Only what the clip produces is held: a looping clip's one period (sampled at its length over
  // round(length / spacing), repeating), or a held clip's span with a zero sample on either side
  // (exactly the samples at every `spacing` from 0 a bake-long sampling gives; zero outside it).
  sim::KeyedBend keyed_bend(int sweep, double duration, double spacing) const;

  // World positions at scene time τ: `deformed` the bake's positions in the mesh's frame (rest
  // where no part moves them).
  void pose(double scene_time, std::span<const Eigen::Vector3f> deformed, std::span<Eigen::Vector3f> out) const;

 private:
  SkinModel model_;
  int clip_ = -1;
  bool loop_ = false;
  int preroll_frames_ = 0;
  double fps_ = 30;
  Eigen::Affine3d from_mesh_ = Eigen::Affine3d::Identity();  // M⁻¹
  std::vector<int> root_joint_;                              // per sweep, into model_.joints
  std::vector<Vec3> pivot_;                                  // per sweep: the root ring's centre at rest
  // Per sweep, per section: its centre at rest and the skin weights (joint, weight) that place it
  // in the keyed pose, the mean of those of the bound vertices nearest it along the part.
  struct SectionSkin {
    Vec3 centre = Vec3::Zero();
    std::vector<std::pair<int, double>> weights;
  };
  std::vector<std::vector<SectionSkin>> section_skin_;
  std::vector<double> length_;  // per sweep, its length at rest
  // Sweep i's root at clip time c as a rigid motion (the body path's key): world = rotation ·
  // (mesh − pivot) + translation. Throws Error(bad_input) where it is scaled or sheared.
  void root_pose(const std::vector<Eigen::Matrix4d>& joints, int sweep, double clip_time, Quat& rotation,
                 Vec3& translation) const;
  // Sweep i's section centres in the keyed pose at clip time c, in its root's frame (mesh coordinates).
  void keyed_sections(int sweep, double clip_time, std::vector<Vec3>& out) const;
  // Whether a STEP key of the clip falls in (clip_time(a), clip_time(b)] (a before b, less than a
  // clip length apart; clip_time(b) < clip_time(a) is across the loop's seam), or, with `seam`, the
  // loop's seam does.
  bool jumps_between(double a, double b, bool seam) const;
  const bind::Binding* binding_ = nullptr;
};

}  // namespace sweep::assets
