#include "sweep/assets/assimp_skin.h"

#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <assimp/Importer.hpp>
#include <bit>
#include <cmath>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "sweep/assets/assimp_placement.h"
#include "sweep/assets/file_error_detail.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/core/error.h"
#include "sweep/core/fp_environment.h"
#include "sweep/core/text.h"

namespace sweep::assets {
namespace {

using Mat4 = Eigen::Matrix4d;

using detail::refuse;

using detail::key_of;
using detail::PositionKey;
using detail::PositionKeyHash;
using detail::to_transform;

// The node tree, depth first (a node before its children), with each node's world transform at rest.
struct Tree {
  std::vector<SkinNode> nodes;
  std::vector<const aiNode*> source;
  std::vector<Mat4> world;
};
void collect(const aiNode* n, int parent, const Mat4& parent_world, Tree& tree) {
  const int i = static_cast<int>(tree.nodes.size());
  SkinNode node;
  node.name = n->mName.C_Str();
  node.parent = parent;
  node.matrix = to_transform(n->mTransformation);
  // An animated node's channels replace these (a clip keys all three for every node it moves).
  aiVector3D scale, position;
  aiQuaternion rotation;
  n->mTransformation.Decompose(scale, rotation, position);
  node.translation = Vec3(position.x, position.y, position.z);
  node.rotation = Quat(rotation.w, rotation.x, rotation.y, rotation.z).normalized();
  node.scale = Vec3(scale.x, scale.y, scale.z);
  const Mat4 world = parent_world * *node.matrix;
  tree.nodes.push_back(std::move(node));
  tree.source.push_back(n);
  tree.world.push_back(world);
  for (unsigned c = 0; c < n->mNumChildren; ++c) collect(n->mChildren[c], i, world, tree);
}

int find_node(const Tree& tree, const std::string& name) {
  for (std::size_t i = 0; i < tree.nodes.size(); ++i)
    if (tree.nodes[i].name == name) return static_cast<int>(i);
  return -1;
}

// A vertex's influences, as the file gives them: (joint, weight), weights > 0.
using Influences = std::vector<std::pair<std::uint16_t, double>>;

bool same_influences(Influences a, Influences b) {
  if (a.size() != b.size()) return false;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].first != b[i].first || std::abs(a[i].second - b[i].second) > 1e-6) return false;
  return true;
}

std::vector<SkinClip> read_clips(const std::filesystem::path& file, const aiScene* scene, const Tree& tree) {
  std::vector<SkinClip> clips;
  for (unsigned a = 0; a < scene->mNumAnimations; ++a) {
    const aiAnimation* anim = scene->mAnimations[a];
    SkinClip clip;
    clip.name = anim->mName.length > 0 ? anim->mName.C_Str() : "animation " + std::to_string(a);
    const double ticks = anim->mTicksPerSecond > 0 ? anim->mTicksPerSecond : 25.0;
    for (unsigned ci = 0; ci < anim->mNumChannels; ++ci) {
      const aiNodeAnim* ch = anim->mChannels[ci];
      const int node = find_node(tree, ch->mNodeName.C_Str());
      if (node < 0) continue;  // keys a node of no mesh's tree: it moves no vertex
      const auto add = [&](ChannelPath path, unsigned count, const auto& time_of, const auto& values_of) {
        if (count == 0) return;
        ClipChannel c;
        c.node = node;
        c.path = path;
        const std::string what = "animation '" + clip.name + "': the keys of node '" + tree.nodes[node].name + "'";
        for (unsigned k = 0; k < count; ++k) {
          const double t = time_of(k) / ticks;
          if (!std::isfinite(t) || t < 0 || (!c.times.empty() && !(t > c.times.back())))
            refuse(file, what + ": key times must be finite, at least 0 and increasing");
          c.times.push_back(t);
          for (const double v : values_of(k)) {
            if (!std::isfinite(v)) refuse(file, what + ": a value is not finite");
            c.values.push_back(v);
          }
        }
        clip.start = clip.channels.empty() ? c.times.front() : std::min(clip.start, c.times.front());
        clip.end = clip.channels.empty() ? c.times.back() : std::max(clip.end, c.times.back());
        clip.channels.push_back(std::move(c));
      };
      add(
          ChannelPath::translation, ch->mNumPositionKeys, [&](unsigned k) { return ch->mPositionKeys[k].mTime; },
          [&](unsigned k) {
            const aiVector3D& v = ch->mPositionKeys[k].mValue;
            return std::array<double, 3>{v.x, v.y, v.z};
          });
      add(
          ChannelPath::rotation, ch->mNumRotationKeys, [&](unsigned k) { return ch->mRotationKeys[k].mTime; },
          [&](unsigned k) {
            const aiQuaternion& q = ch->mRotationKeys[k].mValue;
            const Quat u = Quat(q.w, q.x, q.y, q.z).normalized();
            return std::array<double, 4>{u.x(), u.y(), u.z(), u.w()};
          });
      add(
          ChannelPath::scale, ch->mNumScalingKeys, [&](unsigned k) { return ch->mScalingKeys[k].mTime; },
          [&](unsigned k) {
            const aiVector3D& v = ch->mScalingKeys[k].mValue;
            return std::array<double, 3>{v.x, v.y, v.z};
          });
    }
    clips.push_back(std::move(clip));
  }
  return clips;
}

}  // namespace

std::optional<SkinModel> read_assimp_skin(const std::filesystem::path& file, std::span<const Vec3> read_positions,
                                          const Eigen::Affine3d& to_world) {
  Assimp::Importer importer;
  const aiScene* scene = nullptr;
  {
    const QuietFpEnvironment quiet;
    scene = importer.ReadFile(file.string(), 0);  // no post-processing, as the mesh reader reads it
  }
  if (scene == nullptr || scene->mRootNode == nullptr) return std::nullopt;
  bool any_bones = false;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) any_bones = any_bones || scene->mMeshes[m]->mNumBones > 0;
  if (!any_bones) return std::nullopt;

  SkinModel model;
  Tree tree;
  collect(scene->mRootNode, -1, Mat4::Identity(), tree);
  // Each importer mesh's node: the first showing it, depth first (where the mesh reader places it).
  std::vector<int> node_of(scene->mNumMeshes, -1);
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    for (unsigned k = 0; k < tree.source[i]->mNumMeshes; ++k) {
      const unsigned m = tree.source[i]->mMeshes[k];
      if (m < scene->mNumMeshes && node_of[m] < 0) node_of[m] = static_cast<int>(i);
    }
  }
  // The joints: every bone of every skinned mesh, once a node, with its offset matrix.
  std::map<int, std::size_t> joint_of_node;
  struct Corner {
    int node;
    Vec3 bind;
    Influences influences;
  };
  std::unordered_map<PositionKey, std::vector<Corner>, PositionKeyHash> corners;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    if (am->mNumBones == 0 || node_of[m] < 0) continue;
    std::vector<Influences> influences(am->mNumVertices);
    for (unsigned b = 0; b < am->mNumBones; ++b) {
      const aiBone* bone = am->mBones[b];
      const int node = find_node(tree, bone->mName.C_Str());
      if (node < 0)
        refuse(file, "mesh '" + std::string(am->mName.C_Str()) + "': bone '" + bone->mName.C_Str() + "' names no node");
      const Mat4 offset = to_transform(bone->mOffsetMatrix);
      const double det = offset.topLeftCorner<3, 3>().determinant();
      if (!offset.allFinite() || !(std::abs(det) > 1e-12) ||
          (offset.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6) {
        refuse(file, "the offset (inverse bind) matrix of bone '" + tree.nodes[node].name +
                         "' is not an invertible affine transform (determinant " + format_number(det) + ")");
      }
      auto [it, added] = joint_of_node.try_emplace(node, model.joints.size());
      if (added) {
        model.joints.push_back(node);
        model.inverse_bind.push_back(offset);
      } else if ((model.inverse_bind[it->second] - offset).cwiseAbs().maxCoeff() >
                 1e-9 * std::max(1.0, offset.cwiseAbs().maxCoeff())) {
        refuse(file, "bone '" + tree.nodes[node].name + "' has different offset matrices in two meshes",
               ErrorCategory::unsupported);
      }
      for (unsigned w = 0; w < bone->mNumWeights; ++w) {
        const aiVertexWeight& vw = bone->mWeights[w];
        if (vw.mVertexId >= am->mNumVertices || !std::isfinite(vw.mWeight) || vw.mWeight < 0)
          refuse(file, "bone '" + tree.nodes[node].name + "': a weight of vertex " + std::to_string(vw.mVertexId) +
                           " cannot be read");
        if (vw.mWeight > 0) influences[vw.mVertexId].emplace_back(static_cast<std::uint16_t>(it->second), vw.mWeight);
      }
    }
    const Mat4& world = tree.world[static_cast<std::size_t>(node_of[m])];
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
      corners[key_of(detail::apply(world, am->mVertices[v]))].push_back(
          {node_of[m], Vec3(am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z), std::move(influences[v])});
    }
  }
  if (model.joints.size() > 65535) refuse(file, "the skin has more than 65535 joints", ErrorCategory::unsupported);

  // Each vertex read, matched to the skinned vertices at its position.
  model.mesh_node = -1;
  model.bind_positions.resize(read_positions.size());
  model.vertex_joints.resize(read_positions.size());
  model.vertex_weights.resize(read_positions.size());
  std::size_t reduced = 0;  // vertices of more than 4 influences
  double most_dropped = 0;  // the largest share of a vertex's weight left out
  for (std::size_t v = 0; v < read_positions.size(); ++v) {
    const auto it = corners.find(key_of(read_positions[v]));
    if (it == corners.end()) {
      refuse(
          file,
          "vertex " + std::to_string(v) + " of the mesh read, at " + format_point(read_positions[v]) +
              ", is not a vertex of a skinned mesh (the skinned character must be the mesh read: name it with --mesh)",
          ErrorCategory::unsupported);
    }
    const Corner& first = it->second.front();
    for (const Corner& c : it->second) {
      if (c.node != first.node)
        refuse(file, "the skinned meshes are shown by several nodes (vertex " + std::to_string(v) + ")",
               ErrorCategory::unsupported);
      if (!same_influences(c.influences, first.influences))
        refuse(file, "vertex " + std::to_string(v) + " at " + format_point(read_positions[v]) +
                         ": copies of it are weighted differently");
    }
    if (model.mesh_node < 0) model.mesh_node = first.node;
    if (first.node != model.mesh_node)
      refuse(file, "the skinned meshes are shown by several nodes (vertex " + std::to_string(v) + ")",
             ErrorCategory::unsupported);
    Influences in = first.influences;
    if (in.empty())
      refuse(file, "vertex " + std::to_string(v) + " at " + format_point(read_positions[v]) + " has no bone weight");
    if (in.size() > 4) {
      // Played as engines and glTF's JOINTS_0 play a skin: the 4 largest, renormalised.
      std::stable_sort(in.begin(), in.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
      double dropped = 0;
      for (std::size_t k = 4; k < in.size(); ++k) dropped += in[k].second;
      double total = dropped;
      for (std::size_t k = 0; k < 4; ++k) total += in[k].second;
      most_dropped = std::max(most_dropped, dropped / total);
      ++reduced;
      in.resize(4);
    }
    double sum = 0;
    for (const auto& [j, w] : in) sum += w;
    for (std::size_t k = 0; k < in.size(); ++k) {
      model.vertex_joints[v][k] = in[k].first;
      model.vertex_weights[v][k] = in[k].second / sum;
    }
    model.bind_positions[v] = first.bind;
  }
  if (reduced > 0) {
    model.warnings.push_back(file.string() + ": " + std::to_string(reduced) +
                             " vertices have more than 4 bone influences; each plays its 4 largest, renormalised "
                             "(at most " +
                             format_percent(most_dropped) + " of a vertex's weight left out)");
  }
  // The mesh was read in the space `to_world` maps to world; the bones' offsets take the mesh node's
  // own space. Where the two differ (the whole file read, its skinned node placed by a transform),
  // the bind positions are taken in the space read and the offsets composed to match:
  //     offset · W⁻¹ · M  applied to  M⁻¹ · p  =  offset · v_bind.
  const Mat4& node_world = tree.world[static_cast<std::size_t>(model.mesh_node)];
  if (!(node_world - to_world.matrix()).isZero(0.0)) {
    const Mat4 rebase = node_world.inverse() * to_world.matrix();
    for (Mat4& ibm : model.inverse_bind) ibm = ibm * rebase;
    const Eigen::Affine3d from_world = to_world.inverse();
    for (std::size_t v = 0; v < read_positions.size(); ++v) model.bind_positions[v] = from_world * read_positions[v];
  }
  model.clips = read_clips(file, scene, tree);
  model.nodes = std::move(tree.nodes);
  return model;
}

std::optional<SkinModel> read_skin(const std::filesystem::path& file, std::span<const Vec3> read_positions,
                                   const Eigen::Affine3d& to_world) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".gltf" || ext == ".glb") return read_gltf_skin(file, read_positions, to_world);
  return read_assimp_skin(file, read_positions, to_world);
}

}  // namespace sweep::assets
