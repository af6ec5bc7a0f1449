#include "sweep/assets/character_joints.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "sweep/core/error.h"
#include "sweep/core/text.h"

namespace sweep::assets {
namespace {

using Mat4 = Eigen::Matrix4d;
using Mat3 = Eigen::Matrix3d;

// How far from orthonormal (|RᵀR − I|, per entry) the rotation of a local key may be: a root joint
// scaled unevenly and turned would shear its children, which translation, rotation and scale
// cannot write.
constexpr double kShearTolerance = 1e-5;

// The nearest rotation to `a` (polar decomposition).
Mat3 nearest_rotation(const Mat3& a) {
  const Eigen::JacobiSVD<Mat3> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 u = svd.matrixU();
  if ((u * svd.matrixV().transpose()).determinant() < 0) u.col(2) = -u.col(2);
  return u * svd.matrixV().transpose();
}

// A local transform as translation, rotation and scale; false when it is sheared.
bool to_key(const Mat4& m, JointKey& key) {
  const Mat3 a = m.topLeftCorner<3, 3>();
  Vec3 s(a.col(0).norm(), a.col(1).norm(), a.col(2).norm());
  if (!(s.minCoeff() > 0) || !std::isfinite(s.maxCoeff())) return false;
  Mat3 r = a * s.cwiseInverse().asDiagonal();
  if (r.determinant() < 0) {
    s.x() = -s.x();
    r.col(0) = -r.col(0);
  }
  if (!((r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff() < kShearTolerance)) return false;
  const Quat q = Quat(nearest_rotation(r)).normalized();
  for (int c = 0; c < 3; ++c) {
    key.t[c] = static_cast<float>(m(c, 3));
    key.s[c] = static_cast<float>(s[c]);
  }
  key.r[0] = static_cast<float>(q.x());
  key.r[1] = static_cast<float>(q.y());
  key.r[2] = static_cast<float>(q.z());
  key.r[3] = static_cast<float>(q.w());
  return true;
}

// Keeps `key`'s rotation on the side of `before`'s, so that slerp between them takes the short way.
void same_hemisphere(JointKey& key, const JointKey& before) {
  float dot = 0;
  for (int c = 0; c < 4; ++c) dot += key.r[c] * before.r[c];
  if (dot < 0)
    for (float& c : key.r) c = -c;
}

}  // namespace

CharacterJoints::~CharacterJoints() = default;

CharacterJoints::CharacterJoints(const SkinnedClip& clip, std::vector<SkinSweep> sweeps, const SkinLayout& layout,
                                 std::span<const Eigen::Vector3f> rest)
    : clip_(clip), layout_(layout), sweeps_(std::move(sweeps)) {
  layout_.motion = RingMotion::scale;  // the ring joints' channel is their scale
  const SkinModel& model = clip_.model();
  fit_ = std::make_unique<SkinFit>(sweeps_, layout_, rest, "body");
  mesh_ = clip_.mesh_transform();
  from_mesh_ = mesh_.inverse();
  const std::vector<SkinJoint>& fit_joints = fit_->joints();
  const int added = fit_->joint_count() - 1;  // skin_fit's body joint is the character's own skin
  if (original_joints() + added > 65536) {
    fail(ErrorCategory::unsupported, "the skin has " + std::to_string(original_joints()) +
                                         " joints and the parts add " + std::to_string(added) +
                                         ", more than a skin's 16-bit joint indices reach; "
                                         "fewer --joints or --ring-joints");
  }
  // Names: skin_fit's, with " 2", " 3", ... where the file has a node of that name.
  std::set<std::string> taken;
  for (const SkinNode& n : model.nodes) taken.insert(n.name);
  for (int k = 1; k <= added; ++k) {
    const SkinJoint& sj = fit_joints[static_cast<std::size_t>(k)];
    CharacterJoint j;
    j.sweep = sj.sweep;
    j.name = sj.name;
    for (int n = 2; taken.count(j.name) > 0; ++n) j.name = sj.name + " " + std::to_string(n);
    taken.insert(j.name);
    if (sj.ring >= 0) {
      j.parent_joint = sj.parent - 1;
    } else {
      j.parent_node = clip_.root_joint_node(sj.sweep);
    }
    root_node_.push_back(clip_.root_joint_node(sj.sweep));
    joints_.push_back(std::move(j));
    // IBM' = G_k(rest)⁻¹ · M.
    inverse_bind_.push_back((fit_->inverse_bind()[static_cast<std::size_t>(k)].cast<double>() * mesh_).cast<float>());
    station_centre_.push_back(
        key_matrix(fit_->rest_keys()[static_cast<std::size_t>(sj.ring >= 0 ? sj.parent : k)]).col(3).head<3>());
  }

  // Weights, and each station's average of the skin weights it takes over.
  const std::size_t n = rest.size();
  vertex_joints_ = model.vertex_joints;
  vertex_weights_.resize(n);
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t e = 0; e < 4; ++e) vertex_weights_[v][e] = static_cast<float>(model.vertex_weights[v][e]);
  reweighted_.assign(n, 0);
  part_length_.assign(n, 0);
  std::vector<std::map<int, double>> average(static_cast<std::size_t>(added));
  const std::uint16_t first_new = static_cast<std::uint16_t>(original_joints());
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    const bind::SweepBinding& b = *sweeps_[s].binding;
    for (const std::uint32_t v : b.vertices) {
      reweighted_[v] = 1;
      part_length_[v] = sweeps_[s].rest->length();
      const auto& fj = fit_->vertex_joints()[v];
      const auto& fw = fit_->vertex_weights()[v];
      std::map<int, double> w;  // skin joint → weight
      for (std::size_t e = 0; e < 4; ++e) {
        if (fw[e] == 0) continue;
        if (fj[e] == 0) {  // skin_fit's body: the vertex's own skin
          for (std::size_t i = 0; i < 4; ++i)
            if (model.vertex_weights[v][i] != 0) w[model.vertex_joints[v][i]] += fw[e] * model.vertex_weights[v][i];
          continue;
        }
        const int k = fj[e] - 1;
        w[first_new + k] += fw[e];
        const int station = fit_joints[fj[e]].ring >= 0 ? fit_joints[fj[e]].parent - 1 : k;
        for (std::size_t i = 0; i < 4; ++i)
          if (model.vertex_weights[v][i] != 0)
            average[static_cast<std::size_t>(station)][model.vertex_joints[v][i]] += fw[e] * model.vertex_weights[v][i];
      }
      std::vector<std::pair<int, double>> sorted(w.begin(), w.end());
      std::stable_sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& c) { return a.second > c.second; });
      sorted.resize(std::min<std::size_t>(sorted.size(), 4));
      double kept = 0;
      for (const auto& [joint, weight] : sorted) kept += weight;
      std::array<std::uint16_t, 4> joints{0, 0, 0, 0};
      std::array<float, 4> weights{0, 0, 0, 0};
      float others = 0;
      for (std::size_t e = 0; e < sorted.size(); ++e) {
        joints[e] = static_cast<std::uint16_t>(sorted[e].first);
        weights[e] = static_cast<float>(sorted[e].second / kept);
        if (e > 0) others += weights[e];
      }
      weights[0] = std::max(0.0f, 1.0f - others);  // the heaviest takes what rounding left
      vertex_joints_[v] = joints;
      vertex_weights_[v] = weights;
    }
  }
  station_weights_.resize(static_cast<std::size_t>(added));
  for (int k = 0; k < added; ++k) {
    if (!is_station(k)) continue;
    double total = 0;
    for (const auto& [joint, w] : average[static_cast<std::size_t>(k)]) total += w;
    if (!(total > 0)) {  // no vertex near it: it follows its root joint
      const int root = model.joint_of_node(root_node_[static_cast<std::size_t>(k)]);
      station_weights_[static_cast<std::size_t>(k)] = {{root, 1.0}};
      continue;
    }
    for (const auto& [joint, w] : average[static_cast<std::size_t>(k)])
      station_weights_[static_cast<std::size_t>(k)].emplace_back(joint, w / total);
  }

  // The nodes' own transforms: no clip playing, the sweeps at rest.
  const std::vector<Mat4> world = world_transforms(model, -1, 0.0);
  local_keys(joint_matrices(model, world), world, fit_->rest_keys(), 0.0, rest_keys_);
  fit_keys_.resize(static_cast<std::size_t>(fit_->joint_count()));
}

void CharacterJoints::local_keys(const std::vector<Mat4>& j, const std::vector<Mat4>& world,
                                 std::span<const JointKey> fit_keys, double clip_time,
                                 std::vector<JointKey>& out) const {
  out.resize(joints_.size());
  for (std::size_t k = 0; k < joints_.size(); ++k) {
    const JointKey& fit_key = fit_keys[k + 1];
    if (!is_station(static_cast<int>(k))) {
      out[k] = fit_key;
      continue;
    }
    Mat4 b = Mat4::Zero();
    for (const auto& [joint, w] : station_weights_[k]) b += w * j[static_cast<std::size_t>(joint)];
    b = b * from_mesh_;
    Mat4 carry = Mat4::Identity();
    const Mat3 r = nearest_rotation(b.topLeftCorner<3, 3>());
    const Vec3& c = station_centre_[k];
    carry.topLeftCorner<3, 3>() = r;
    carry.topRightCorner<3, 1>() = (b * c.homogeneous()).head<3>() - r * c;
    const Mat4 local = world[static_cast<std::size_t>(root_node_[k])].inverse() * carry * key_matrix(fit_key);
    if (!to_key(local, out[k])) {
      fail(ErrorCategory::unsupported, "joint '" + clip_.model().nodes[static_cast<std::size_t>(root_node_[k])].name +
                                           "', the root joint of part '" +
                                           sweeps_[static_cast<std::size_t>(joints_[k].sweep)].name +
                                           "', is scaled unevenly at " + format_number(clip_time) +
                                           " s of its clip: the part's joints under it would be sheared, which a "
                                           "joint's translation, rotation and scale cannot hold; bake with --morph");
    }
  }
}

void CharacterJoints::pose(std::span<const SweepShape* const> shapes, std::span<const Eigen::Vector3f> deformed,
                           std::span<const Eigen::Vector3f> world_positions, int frame) {
  const SkinModel& model = clip_.model();
  const double scene_time = frame / clip_.fps();
  fit_->pose(shapes, deformed, frame, fit_keys_);
  const std::vector<Mat4> world = clip_.world_at(scene_time);
  const std::vector<Mat4> j = joint_matrices(model, world);
  std::vector<JointKey> keys;
  local_keys(j, world, fit_keys_, clip_.clip_time(scene_time), keys);
  for (std::size_t k = 0; k < keys.size(); ++k)
    same_hemisphere(keys[k], keys_.empty() ? rest_keys_[k] : keys_.back()[k]);

  // The skin as written: the original joints' matrices, and the new joints' from their float keys.
  std::vector<Mat4> skinning = j;
  std::vector<Mat4> global(joints_.size());
  for (std::size_t k = 0; k < joints_.size(); ++k) {
    const Mat4 local = key_matrix(keys[k]);
    global[k] = joints_[k].parent_joint >= 0 ? Mat4(global[static_cast<std::size_t>(joints_[k].parent_joint)] * local)
                                             : Mat4(world[static_cast<std::size_t>(joints_[k].parent_node)] * local);
    skinning.push_back(global[k] * inverse_bind_[k].cast<double>());
  }
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    for (const std::uint32_t v : sweeps_[s].binding->vertices) {
      const Eigen::Vector4d b = model.bind_positions[v].homogeneous();
      Eigen::Vector4d q = Eigen::Vector4d::Zero();
      for (std::size_t e = 0; e < 4; ++e) {
        const float w = vertex_weights_[v][e];
        if (w != 0) q += static_cast<double>(w) * (skinning[vertex_joints_[v][e]] * b);
      }
      const double err = (q.head<3>() - world_positions[v].cast<double>()).norm() / part_length_[v];
      sum_squares_ += err * err;
      if (err > error_.max_relative) {
        error_.max_relative = err;
        error_.max_frame = frame;
        error_.max_vertex = v;
      }
      ++error_.samples;
    }
  }
  error_.rms_relative = error_.samples ? std::sqrt(sum_squares_ / static_cast<double>(error_.samples)) : 0.0;
  keys_.push_back(std::move(keys));
}

CharacterJoints::ClipKeys CharacterJoints::clip_keys(int clip, double fps) const {
  const SkinModel& model = clip_.model();
  const SkinClip& c = model.clips[static_cast<std::size_t>(clip)];
  ClipKeys out;
  const double length = std::max(c.end - c.start, 0.0);
  const long long steps = static_cast<long long>(std::floor(length * fps + 1e-9));
  for (long long i = 0; i <= steps; ++i) out.times.push_back(static_cast<float>(c.start + i / fps));
  if (const float end = static_cast<float>(c.end); out.times.back() < end) out.times.push_back(end);
  // Two keys with the same float time (a clip shorter than a frame of float precision) would be
  // invalid glTF: one is enough.
  out.times.erase(std::unique(out.times.begin(), out.times.end()), out.times.end());
  for (const float t : out.times) {
    const std::vector<Mat4> world = world_transforms(model, clip, t);
    std::vector<JointKey> keys;
    local_keys(joint_matrices(model, world), world, fit_->rest_keys(), t, keys);
    for (std::size_t k = 0; k < keys.size(); ++k)
      same_hemisphere(keys[k], out.keys.empty() ? rest_keys_[k] : out.keys.back()[k]);
    out.keys.push_back(std::move(keys));
  }
  return out;
}

}  // namespace sweep::assets
