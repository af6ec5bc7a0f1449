#include "sweep/assets/skinned_clip.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "sweep/assets/file_error_detail.h"
#include "sweep/core/error.h"
#include "sweep/core/text.h"

namespace sweep::assets {
namespace {

using detail::refuse;

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

// The root ring: bound vertices within this share of the part's length of its root.
constexpr double kRootRingShare = 0.02;
// Samples of a part's root motion per output frame (the body path's linear pieces).
constexpr int kSamplesPerFrame = 2;
// How far from a rotation (|RᵀR − I|, per entry) a root joint's motion may be: 1e-4, a scale of
// 1 ± 5e-5 at most.
constexpr double kRigidTolerance = 1e-4;
// A looping clip whose last and first poses put a section farther apart than this share of the
// part's length jumps at its seam (float keys written equal differ by rounding alone).
constexpr double kSeamShare = 1e-6;

}  // namespace

SkinnedClip::SkinnedClip(const std::filesystem::path& file, SkinModel model, const Eigen::Affine3d& to_world,
                         const Rig& rig, const bind::Binding& binding, const std::string& node,
                         const std::string& animation, bool loop, double preroll_seconds, double fps)
    : model_(std::move(model)), loop_(loop), fps_(fps), from_mesh_(to_world.inverse()), binding_(&binding) {
  const std::string mesh_node = model_.nodes[model_.mesh_node].name;
  std::vector<std::string> joint_names;
  for (int j : model_.joints) joint_names.push_back("'" + model_.nodes[j].name + "'");
  const int n = model_.find_node(node);
  if (n < 0 || (n != model_.mesh_node && model_.joint_of_node(n) < 0)) {
    refuse(file, "the scene's body follows node '" + node + "', which is " +
                     (n < 0 ? "not a node of the file" : "neither the skinned mesh's node nor a joint of its skin") +
                     ": name the skinned mesh's node '" + mesh_node + "' or one of its joints (" + joined(joint_names) +
                     ")");
  }
  if (model_.clips.empty())
    refuse(file, "the scene's body plays a clip of node '" + node + "', but the file has no animations");
  if (animation.empty()) {
    clip_ = 0;
  } else {
    clip_ = model_.find_clip(animation);
    if (clip_ < 0)
      refuse(file, "no animation is named '" + animation + "'; the file's clips are " + model_.clip_names());
  }
  bool moves = false;
  for (const ClipChannel& c : model_.clips[clip_].channels) {
    // A joint, or a node above the skeleton (its whole motion reaches the joints).
    for (int j : model_.joints) {
      for (int p = j; p >= 0 && !moves; p = model_.nodes[p].parent) moves = p == c.node;
    }
  }
  if (!moves) {
    refuse(file, "animation '" + clip_name() + "' moves none of the joints of the skin of '" + mesh_node +
                     "' (it moves " + joined(model_.moved_nodes(clip_)) + "); the file's clips are " +
                     model_.clip_names());
  }
  if (!(preroll_seconds >= 0) || !std::isfinite(preroll_seconds))
    refuse(file, "the body's preroll must be a finite number of seconds, at least 0");
  preroll_frames_ = static_cast<int>(std::lround(preroll_seconds * fps));
  // Each part's root joint: the most weight over its root ring.
  for (std::size_t i = 0; i < rig.sweeps.size(); ++i) {
    const bind::SweepBinding& table = binding.sweeps[i];
    std::map<int, double> weight;
    Vec3 centre = Vec3::Zero();
    int ring = 0;
    if (table.size() > 0) {
      const float first = *std::min_element(table.t.begin(), table.t.end());
      const double band = first + kRootRingShare * rig.sweeps[i].rest.length();
      for (std::size_t k = 0; k < table.size(); ++k) {
        if (table.t[k] > band) continue;
        const std::uint32_t v = table.vertices[k];
        for (int e = 0; e < 4; ++e) weight[model_.vertex_joints[v][e]] += model_.vertex_weights[v][e];
        centre += to_world * model_.bind_positions[v];
        ++ring;
      }
    }
    if (ring == 0)
      refuse(file, "part '" + rig.sweeps[i].name + "' binds no vertex near its root: its root joint cannot be found");
    const auto best = std::max_element(weight.begin(), weight.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    root_joint_.push_back(best->first);
    pivot_.push_back(centre / ring);
    // Each section placed in the keyed pose as the bound vertices nearest it along the part are:
    // with the mean of their skin weights.
    const SweepShape& shape = rig.sweeps[i].rest;
    std::vector<SectionSkin> sections(static_cast<std::size_t>(shape.section_count()));
    for (int j = 0; j < shape.section_count(); ++j) {
      sections[j].centre = shape.frames[j].center;
      double nearest = std::numeric_limits<double>::infinity();
      for (const float t : table.t) nearest = std::min(nearest, std::abs(t - shape.t[j]));
      const double reach = nearest + kRootRingShare * shape.length();
      std::map<int, double> mean;
      int count = 0;
      for (std::size_t k = 0; k < table.size(); ++k) {
        if (std::abs(table.t[k] - shape.t[j]) > reach) continue;
        const std::uint32_t v = table.vertices[k];
        for (int e = 0; e < 4; ++e)
          if (model_.vertex_weights[v][e] != 0) mean[model_.vertex_joints[v][e]] += model_.vertex_weights[v][e];
        ++count;
      }
      for (const auto& [joint, w] : mean) sections[j].weights.emplace_back(joint, w / count);
    }
    section_skin_.push_back(std::move(sections));
    length_.push_back(shape.length());
  }
}

double SkinnedClip::clip_time(double scene_time) const {
  const SkinClip& c = model_.clips[clip_];
  const double length = c.end - c.start;
  if (!loop_ || !(length > 0)) return c.start + std::clamp(scene_time, 0.0, std::max(length, 0.0));
  double u = std::fmod(scene_time, length);
  if (u < 0) u += length;
  return c.start + u;
}

std::vector<Eigen::Matrix4d> SkinnedClip::joint_matrices_at(double scene_time) const {
  return joint_matrices(model_, world_at(scene_time));
}

std::vector<Eigen::Matrix4d> SkinnedClip::world_at(double scene_time) const {
  return world_transforms(model_, clip_, clip_time(scene_time));
}

Eigen::Affine3d SkinnedClip::part_transform(const std::vector<Eigen::Matrix4d>& joints, int sweep) const {
  Eigen::Affine3d b;
  b.matrix() = joints[root_joint_[sweep]] * from_mesh_.matrix();
  return b;
}

void SkinnedClip::root_pose(const std::vector<Eigen::Matrix4d>& joints, int sweep, double clip_time, Quat& rotation,
                            Vec3& translation) const {
  const Eigen::Affine3d b = part_transform(joints, sweep);
  const Eigen::Matrix3d r = b.linear();
  // Exporters write scales of 1 as 0.9999999 and so on (float32 round trips): a scale within
  // kRigidTolerance of 1 is that noise, not a scale channel.
  if (!((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < kRigidTolerance) ||
      !(r.determinant() > 0)) {
    fail(ErrorCategory::bad_input, "animation '" + clip_name() + "': the root joint '" +
                                       model_.nodes[root_joint_node(sweep)].name + "' of part " +
                                       std::to_string(sweep) + " is scaled or sheared at " + format_number(clip_time) +
                                       " s (a scale channel on it or above it, or a scaled inverse bind matrix): a "
                                       "part's root moves and turns rigidly");
  }
  translation = b * pivot_[sweep];
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  rotation = Quat(Eigen::Matrix3d(svd.matrixU() * svd.matrixV().transpose()));
  rotation.normalize();  // the nearest rotation (polar decomposition)
}

sim::BodyPath SkinnedClip::sweep_path(int sweep, double duration) const {
  const long long frames = static_cast<long long>(std::floor(duration * fps_ + 1e-9));
  std::vector<sim::BodyKey> keys;
  Quat last = Quat::Identity();
  for (long long f = 0; f <= frames; ++f) {
    for (int s = 0; s < (f < frames ? kSamplesPerFrame : 1); ++s) {
      // On the simulator's clock: frame f at f / fps exactly, as the simulator computes it.
      const double t = s == 0 ? f / fps_ : (f + static_cast<double>(s) / kSamplesPerFrame) / fps_;
      const double scene_time = (f - preroll_frames_ + static_cast<double>(s) / kSamplesPerFrame) / fps_;
      sim::BodyKey key;
      key.time = t;
      root_pose(joint_matrices_at(scene_time), sweep, clip_time(scene_time), key.rotation, key.translation);
      if (key.rotation.dot(last) < 0) key.rotation.coeffs() *= -1;  // continuous: slerp takes the short way
      last = key.rotation;
      keys.push_back(key);
    }
  }
  return sim::BodyPath(std::move(keys), sim::BodyInterpolation::linear, pivot_[sweep]);
}

void SkinnedClip::keyed_sections(int sweep, double clip_time, std::vector<Vec3>& out) const {
  const std::vector<Eigen::Matrix4d> joints = joint_matrices(model_, world_transforms(model_, clip_, clip_time));
  Quat rotation;
  Vec3 translation;
  root_pose(joints, sweep, clip_time, rotation, translation);
  const Eigen::Matrix3d to_root = rotation.toRotationMatrix().transpose();
  const std::vector<SectionSkin>& sections = section_skin_[sweep];
  out.resize(sections.size());
  for (std::size_t j = 0; j < sections.size(); ++j) {
    const Eigen::Vector4d c = (from_mesh_ * sections[j].centre).homogeneous();
    Eigen::Vector4d world = Eigen::Vector4d::Zero();
    for (const auto& [joint, w] : sections[j].weights) world += w * (joints[joint] * c);
    out[j] = to_root * (world.head<3>() - translation) + pivot_[sweep];
  }
}

bool SkinnedClip::jumps_between(double a, double b, bool seam) const {
  const SkinClip& clip = model_.clips[clip_];
  const double ca = clip_time(a), cb = clip_time(b);
  const bool wrapped = cb < ca;  // a looping clip's seam lies between them
  if (wrapped && seam) return true;
  for (const ClipChannel& c : clip.channels) {
    if (c.interpolation != ChannelInterpolation::step) continue;
    // Before its first key a channel holds that key's value: only the later keys jump.
    for (std::size_t k = 1; k < c.times.size(); ++k) {
      const double key = c.times[k];
      if (wrapped ? (key > ca || key <= cb) : (key > ca && key <= cb)) return true;
    }
  }
  return false;
}

sim::KeyedBend SkinnedClip::keyed_bend(int sweep, double duration, double spacing) const {
  const int sections = static_cast<int>(section_skin_[sweep].size());
  const double preroll = preroll_frames_ / fps_;
  // A looping clip whose last pose is not its first jumps at its seam.
  const SkinClip& clip = model_.clips[clip_];
  const double length = clip.end - clip.start;
  const bool looping = loop_ && length > 0;
  std::vector<Vec3> before, after;
  bool seam = false;
  double extent = 1;  // the size of the coordinates, for the rounding's floor
  if (looping) {
    keyed_sections(sweep, clip.end, before);
    keyed_sections(sweep, clip.start, after);
    for (std::size_t j = 1; j < before.size(); ++j)
      seam = seam || (before[j] - after[j]).norm() > kSeamShare * length_[sweep];
  }
  for (const SectionSkin& s : section_skin_[sweep]) extent = std::max(extent, (from_mesh_ * s.centre).norm());
  // Samples first … last of the second differences at `step`, sample n at scene time scene_time(n).
  const auto differences = [&](double step, const auto& scene_time, long long first, long long last) {
    // Accelerations below what rounding the positions (a few ulps of the coordinates) makes are
    // none: a part whose keys do not bend it is not loaded, and sleeps.
    const double floor = 64 * std::numeric_limits<double>::epsilon() * extent / (step * step);
    // Positions at samples n − 1, n, n + 1 (the velocity over a piece that jumps is the one before
    // it: a STEP key or an unequal seam is a cut, taken as the pose's jump, not felt).
    std::vector<Vec3> p_prev, p_cur, p_next;
    std::vector<Eigen::Vector3f> accelerations;
    accelerations.reserve(static_cast<std::size_t>(std::max(last - first + 1, 0LL)) * sections);
    keyed_sections(sweep, clip_time(scene_time(first - 1)), p_prev);
    keyed_sections(sweep, clip_time(scene_time(first)), p_cur);
    std::vector<Vec3> v_before(sections, Vec3::Zero()), v_after(sections);
    if (!jumps_between(scene_time(first - 1), scene_time(first), seam)) {
      for (int j = 0; j < sections; ++j) v_before[j] = (p_cur[j] - p_prev[j]) / step;
    }
    for (long long n = first; n <= last; ++n) {
      keyed_sections(sweep, clip_time(scene_time(n + 1)), p_next);
      const bool cut = jumps_between(scene_time(n), scene_time(n + 1), seam);
      for (int j = 0; j < sections; ++j) {
        v_after[j] = cut ? v_before[j] : Vec3((p_next[j] - p_cur[j]) / step);
        Vec3 a = j == 0 ? Vec3::Zero() : Vec3((v_after[j] - v_before[j]) / step);
        if (a.cwiseAbs().maxCoeff() < floor) a = Vec3::Zero();
        accelerations.push_back(a.cast<float>());
      }
      std::swap(v_before, v_after);
      std::swap(p_cur, p_next);
    }
    return accelerations;
  };
  if (looping) {
    // One period, at the spacing nearest the step that divides the clip's length into whole
    // samples (the step's own would not repeat: L / h is rarely whole). Sample k at the phase
    // (k mod count) · step in [0, L), so that the seam falls between samples count − 1 and count
    // (jumps_between sees it as the clip's time going back). A period before it is run first: a
    // cut carries the velocity before it, which may lie in the previous period.
    const long long count = std::max(1LL, std::llround(length / spacing));
    const double step = length / static_cast<double>(count);
    const auto phase = [&](long long k) { return static_cast<double>(((k % count) + count) % count) * step; };
    std::vector<Eigen::Vector3f> two = differences(step, phase, -count, count - 1);
    std::vector<Eigen::Vector3f> period(two.begin() + static_cast<std::ptrdiff_t>(count * sections), two.end());
    // Phase 0 (scene time 0, the clip's start) at simulator time `preroll`.
    return sim::KeyedBend::repeating(length, preroll, sections, std::move(period));
  }
  // A clip held at its ends: the keyed sections stand still before scene time 0 and after the
  // clip's length, so sample n (scene time n · spacing − preroll) is zero where n + 1 is at or
  // before 0 or n − 1 at or after the length. Kept: from the last such sample before to the first
  // after (with a margin of one for rounding), within the bake's [0, ceil(duration / spacing)].
  const long long bake_last = static_cast<long long>(std::ceil(duration / spacing - 1e-9));
  const long long first = std::max(0LL, static_cast<long long>(std::floor(preroll / spacing)) - 2);
  const long long last =
      std::min(bake_last, static_cast<long long>(std::ceil((preroll + std::max(length, 0.0)) / spacing)) + 2);
  if (first > last) return sim::KeyedBend(spacing, sections, {}, 0);
  const auto scene_time = [&](long long n) { return static_cast<double>(n) * spacing - preroll; };
  return sim::KeyedBend(spacing, sections, differences(spacing, scene_time, first, last), first);
}

void SkinnedClip::pose(double scene_time, std::span<const Eigen::Vector3f> deformed,
                       std::span<Eigen::Vector3f> out) const {
  const std::vector<Eigen::Matrix4d> joints = joint_matrices_at(scene_time);
  for (std::size_t v = 0; v < out.size(); ++v) out[v] = skin_vertex(model_, joints, v).cast<float>();
  for (const bind::SweepBinding& table : binding_->sweeps) {
    for (const std::uint32_t v : table.vertices) {
      // The vertex's own skinning matrix, taking the mesh as read to the keyed pose, carries its
      // simulated deviation: M_v · p, which is the keyed pose where p is the rest.
      Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
      for (int i = 0; i < 4; ++i) {
        const double w = model_.vertex_weights[v][i];
        if (w != 0) m += w * joints[model_.vertex_joints[v][i]];
      }
      out[v] = (m * from_mesh_.matrix() * deformed[v].cast<double>().homogeneous()).head<3>().cast<float>();
    }
  }
}

}  // namespace sweep::assets
