#pragma once
// A skinned glTF mesh and its clips as plain data, and linear blend skinning at a time t exactly as
// glTF 2.0 defines it ("Skins", "Animations"):
//     J_k(t) = World(joint_k, t) · IBM_k,     v(t) = Σ_i w_i · J_{k_i}(t) · v_bind
// with World the joint's world transform from the nodes' local transforms (each the clip's value
// where a channel moves it, else its rest value), and v_bind the primitive's POSITION. The skinned
// mesh node's own transform is ignored, as glTF says. Channels: translation, rotation and scale,
// interpolated LINEAR (rotations by slerp, the shortest arc), STEP or CUBICSPLINE (Hermite, the
// tangents scaled by the key interval); held before the first key and after the last.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "sweep/core/frame.h"

namespace sweep::assets {

struct SkinNode {
  std::string name;
  int parent = -1;
  // Rest transform: "matrix", or translation · rotation · scale.
  std::optional<Eigen::Matrix4d> matrix;
  Vec3 translation = Vec3::Zero();
  Quat rotation = Quat::Identity();
  Vec3 scale = Vec3::Ones();
};

enum class ChannelPath { translation, rotation, scale };
enum class ChannelInterpolation { linear, step, cubic };

struct ClipChannel {
  int node = -1;
  ChannelPath path = ChannelPath::translation;
  ChannelInterpolation interpolation = ChannelInterpolation::linear;
  std::vector<double> times;
  // width() numbers a key (3, or 4 for a rotation as x, y, z, w); CUBICSPLINE keys hold three such
  // groups each: in-tangent, value, out-tangent.
  std::vector<double> values;
  int width() const { return path == ChannelPath::rotation ? 4 : 3; }
};

struct SkinClip {
  std::string name;
  std::vector<ClipChannel> channels;
  double start = 0, end = 0;  // the first and last key time over its channels
};

struct SkinModel {
  std::vector<SkinNode> nodes;
  std::vector<SkinClip> clips;
  int mesh_node = -1;                         // the node showing the skinned mesh
  std::vector<int> joints;                    // the skin's joints (node indices)
  std::vector<Eigen::Matrix4d> inverse_bind;  // one per joint
  // Per vertex of the mesh, in the order the importer reads it (its primitives in order): its bind
  // position (POSITION, mesh-local), up to 4 joints (indices into `joints`) and their weights.
  std::vector<Vec3> bind_positions;
  std::vector<std::array<std::uint16_t, 4>> vertex_joints;
  std::vector<std::array<double, 4>> vertex_weights;

  // What the reader changed to play the file, for the user (e.g. influences past 4 dropped).
  std::vector<std::string> warnings;

  int find_node(const std::string& name) const;  // -1 when none
  int find_clip(const std::string& name) const;  // -1 when none
  // The index of node `node` in `joints`, or -1.
  int joint_of_node(int node) const;
  // The nodes clip `c` moves (names, in node order), for messages.
  std::vector<std::string> moved_nodes(int c) const;
  std::string clip_names() const;  // "'Survey', 'Walk', 'Run'"
};

// A channel's value at t (x, y, z, w for rotations, unit; the last entry unused otherwise).
Eigen::Vector4d channel_value(const ClipChannel& channel, double t);

// Every node's world transform with clip `clip` (-1: the rest pose) at time t.
std::vector<Eigen::Matrix4d> world_transforms(const SkinModel& model, int clip, double t);
// The joint matrices J_k = World(joint_k) · IBM_k from the world transforms.
std::vector<Eigen::Matrix4d> joint_matrices(const SkinModel& model, const std::vector<Eigen::Matrix4d>& world);
// v = Σ w_i J_{k_i} v_bind of vertex v.
Vec3 skin_vertex(const SkinModel& model, const std::vector<Eigen::Matrix4d>& joint_matrix, std::size_t v);

// Reads the skinned mesh of a glTF file whose vertices the mesh read from it has (`read_positions`,
// world space at rest, `to_world` its node's transform): the node showing a mesh with a skin whose
// primitives, in order, hold those vertices. nullopt when no node of the file is skinned. Throws
// Error(bad_input) naming the file and what is wrong: more than 4 influences (JOINTS_1), a joint or
// weight that cannot be read, a non-invertible inverse bind matrix, a channel that cannot be read;
// Error(unsupported) when the skinned mesh is not the mesh read.
std::optional<SkinModel> read_gltf_skin(const std::filesystem::path& gltf, std::span<const Vec3> read_positions,
                                        const Eigen::Affine3d& to_world);

}  // namespace sweep::assets
