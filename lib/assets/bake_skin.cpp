// The skinned .glb writer (bake_skin.h). The binary chunk is assembled in memory in finish() (the
// rest mesh, the skin's attributes and matrices, and the joints' keys, all small) and written with
// the GLB header and the JSON (tinygltf's serializer, keys sorted: stable bytes) into a temporary
// that is renamed onto the output. Layout, every block 4-byte aligned:
//   rest POSITION | rest NORMAL | triangle indices (uint32) | JOINTS_0 (u8 or u16 × 4) |
//   WEIGHTS_0 (float × 4) | inverse bind matrices (mat4) | key times (F floats) |
//   per animated joint, its channels: [translations (F × vec3)] | [rotations (F × vec4)] |
//   [scales (F × vec3)] |
//   [a moving body: its translations | rotations]
#include "sweep/assets/bake_skin.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sweep/assets/bake_detail.h"
#include "sweep/assets/smooth_normals.h"
#include "sweep/core/error.h"

namespace sweep::assets {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the .glb writer stores host floats as glTF's little-endian data");

using detail::kGlbMaxBytes;

class SkinWriter final : public detail::BakeWriterBase, public SkinPoser {
 public:
  SkinWriter(std::filesystem::path out, std::vector<SkinSweep> sweeps, const SkinLayout& layout)
      : BakeWriterBase(std::move(out)), sweeps_(std::move(sweeps)), layout_(layout) {}

  std::vector<std::filesystem::path> files() const override { return {out()}; }
  void pose(std::span<const SweepShape* const> shapes) override;
  const SkinError& skin_error() const override { return fit_ ? fit_->error() : no_error_; }
  int joint_count() const override {
    const int ring = layout_.ring > 1 ? (layout_.stations - 1) * layout_.ring : 0;
    return 1 + static_cast<int>(sweeps_.size()) * (layout_.stations + ring);
  }

 protected:
  void start(const Mesh& mesh) override;
  void write_frame(int index, std::span<const Eigen::Vector3f> positions) override;
  void complete(io::Publication& outputs) override;
  void abandon() noexcept override {
    if (final_) final_->discard();
  }

 private:
  tinygltf::Model build_model(std::vector<unsigned char>& bin) const;

  std::vector<SkinSweep> sweeps_;
  SkinLayout layout_;
  std::unique_ptr<SkinFit> fit_;             // made in start(), with the rest mesh
  std::vector<JointKey> frame_keys_;         // per joint, this frame (scratch)
  std::vector<std::vector<JointKey>> keys_;  // per joint but the body, per frame
  std::vector<std::uint32_t> triangles_;
  std::vector<Eigen::Vector3f> normals_;
  Eigen::Vector3f rest_min_, rest_max_;
  std::vector<const SweepShape*> shapes_;
  bool posed_ = false;
  detail::BodyKeys body_keys_;  // with a moving body
  SkinError no_error_;
  std::unique_ptr<io::TempFile> final_;
};

void SkinWriter::start(const Mesh& mesh) {
  const std::size_t n = rest().size();
  triangles_ = mesh.triangles();
  if (triangles_.empty()) {
    fail(ErrorCategory::unsupported,
         out().string() + ": the mesh has no faces; a .glb bake needs a surface (use .pc2)");
  }
  const int m = joint_count();
  if (m > 65536) {
    fail(ErrorCategory::unsupported,
         out().string() + ": " + std::to_string(m) + " joints are more than a skin's 16-bit joint indices reach");
  }
  normals_ = detail::smooth_normals(mesh.positions, triangles_);
  rest_min_ = rest_max_ = rest().front();
  for (const Eigen::Vector3f& p : rest()) {
    rest_min_ = rest_min_.cwiseMin(p);
    rest_max_ = rest_max_.cwiseMax(p);
  }

  fit_ = std::make_unique<SkinFit>(sweeps_, layout_, rest(), info().name);
  frame_keys_.assign(static_cast<std::size_t>(m), kIdentityKey);
  keys_.assign(static_cast<std::size_t>(m - 1), {});
  for (auto& k : keys_) k.reserve(static_cast<std::size_t>(info().frame_count));

  const std::uint64_t frames = static_cast<std::uint64_t>(info().frame_count);
  const std::uint64_t joint_bytes = m <= 256 ? 4 : 8;
  // Keys: a station joint's 40 bytes a frame (28 with a ring), a ring joint's 12 (at most: a ring
  // joint that never moves is not keyed).
  std::uint64_t key_bytes = 0;
  for (const SkinJoint& j : fit_->joints())
    if (j.sweep >= 0) key_bytes += j.ring >= 0 ? 12 : (layout_.ring > 1 ? 28 : 40);
  const std::uint64_t estimate = 28 + 8192 + 600 * std::uint64_t(m) + 24 * std::uint64_t{n} + 4 * triangles_.size() +
                                 (joint_bytes + 16) * n + 64 * std::uint64_t(m) + 4 * frames + key_bytes * frames +
                                 (info().body_moves ? 28 * frames : 0);
  set_estimate(estimate);
  if (estimate > kGlbMaxBytes) {
    fail(ErrorCategory::unsupported,
         out().string() + ": about " + std::to_string(estimate >> 20) + " MiB, over the 4 GiB a .glb can hold");
  }
}

void SkinWriter::pose(std::span<const SweepShape* const> shapes) {
  if (shapes.size() != sweeps_.size()) {
    fail(ErrorCategory::internal, out().string() + ": " + std::to_string(shapes.size()) +
                                      " sweep shapes given for a skin of " + std::to_string(sweeps_.size()) +
                                      " sweeps");
  }
  shapes_.assign(shapes.begin(), shapes.end());
  posed_ = true;
}

void SkinWriter::write_frame(int index, std::span<const Eigen::Vector3f> positions) {
  if (!posed_) {
    fail(ErrorCategory::internal,
         out().string() + ": frame " + std::to_string(index) + " given without the sweeps' pose");
  }
  posed_ = false;
  if (info().body_moves) {
    body_keys_.add(body_pose());
  }
  fit_->pose(shapes_, positions, index, frame_keys_);
  for (std::size_t j = 0; j < keys_.size(); ++j) {
    JointKey key = frame_keys_[j + 1];
    std::vector<JointKey>& track = keys_[j];
    const JointKey& before = track.empty() ? fit_->rest_keys()[j + 1] : track.back();
    const float dot = key.r[0] * before.r[0] + key.r[1] * before.r[1] + key.r[2] * before.r[2] + key.r[3] * before.r[3];
    if (dot < 0) {
      for (float& c : key.r) c = -c;
    }
    track.push_back(key);
  }
}

template <typename T>
void append(std::vector<unsigned char>& bin, const T* data, std::size_t count) {
  const std::size_t at = bin.size();
  bin.resize(at + count * sizeof(T));
  if (count) std::memcpy(bin.data() + at, data, count * sizeof(T));
  bin.resize((bin.size() + 3) / 4 * 4, 0);
}

tinygltf::Model SkinWriter::build_model(std::vector<unsigned char>& bin) const {
  const std::size_t n = rest().size();
  const std::size_t frames = static_cast<std::size_t>(info().frame_count);
  const int m = joint_count();
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "sweep bake 1 (skin)";

  auto add_view = [&](std::size_t offset, std::size_t length, int target) {
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = offset;
    view.byteLength = length;
    view.target = target;
    model.bufferViews.push_back(view);
    return static_cast<int>(model.bufferViews.size() - 1);
  };
  // Appends `count` elements and an accessor over them.
  auto add_data = [&](const auto* data, std::size_t elements, std::size_t per_element, int component, int type,
                      int target) {
    const std::size_t offset = bin.size();
    append(bin, data, elements * per_element);
    tinygltf::Accessor a;
    a.bufferView = add_view(offset, elements * per_element * sizeof(*data), target);
    a.componentType = component;
    a.type = type;
    a.count = elements;
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size() - 1);
  };
  constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;
  constexpr int kArray = TINYGLTF_TARGET_ARRAY_BUFFER;

  const int position = add_data(rest()[0].data(), n, 3, kFloat, TINYGLTF_TYPE_VEC3, kArray);
  model.accessors[position].minValues = {rest_min_.x(), rest_min_.y(), rest_min_.z()};
  model.accessors[position].maxValues = {rest_max_.x(), rest_max_.y(), rest_max_.z()};
  const int normal = add_data(normals_[0].data(), n, 3, kFloat, TINYGLTF_TYPE_VEC3, kArray);
  const int indices = add_data(triangles_.data(), triangles_.size(), 1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                               TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  const auto& joints_ = fit_->vertex_joints();
  const auto& weights_ = fit_->vertex_weights();
  const auto& inverse_bind_ = fit_->inverse_bind();
  const auto& rest_keys_ = fit_->rest_keys();
  int joints = 0;
  if (m <= 256) {
    std::vector<std::uint8_t> small(4 * n);
    for (std::size_t v = 0; v < n; ++v)
      for (std::size_t k = 0; k < 4; ++k) small[4 * v + k] = static_cast<std::uint8_t>(joints_[v][k]);
    joints = add_data(small.data(), n, 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, kArray);
  } else {
    joints = add_data(joints_[0].data(), n, 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, kArray);
  }
  const int weights = add_data(weights_[0].data(), n, 4, kFloat, TINYGLTF_TYPE_VEC4, kArray);
  const int inverse_bind = add_data(inverse_bind_[0].data(), inverse_bind_.size(), 16, kFloat, TINYGLTF_TYPE_MAT4, 0);

  std::vector<float> times(frames);
  for (std::size_t k = 0; k < frames; ++k) {
    times[k] = static_cast<float>(static_cast<double>(k) / info().fps);
    if (k > 0 && !(times[k] > times[k - 1])) {
      fail(ErrorCategory::unsupported, out().string() + ": frame " + std::to_string(k) + " at " +
                                           std::to_string(info().fps) +
                                           " frames/s has the same float32 time as the frame before it");
    }
  }
  const int time = add_data(times.data(), frames, 1, kFloat, TINYGLTF_TYPE_SCALAR, 0);
  model.accessors[time].minValues = {0.0};
  model.accessors[time].maxValues = {double{times.back()}};

  // Nodes: the body joint, the sweeps' joints, the mesh.
  tinygltf::Node root;
  root.name = info().name + "_root";
  if (info().body_moves) {  // frame 0's pose, for a viewer that does not play the animation
    root.translation = {body_keys_.translations[0], body_keys_.translations[1], body_keys_.translations[2]};
    root.rotation = {body_keys_.rotations[0], body_keys_.rotations[1], body_keys_.rotations[2],
                     body_keys_.rotations[3]};
  }
  model.nodes.push_back(root);
  for (std::size_t k = 1; k < fit_->joints().size(); ++k) {
    const SkinJoint& sj = fit_->joints()[k];
    tinygltf::Node node;
    node.name = sj.name;
    const JointKey& key = rest_keys_[k];
    if (!(key == kIdentityKey)) {
      node.translation = {key.t[0], key.t[1], key.t[2]};
      node.rotation = {key.r[0], key.r[1], key.r[2], key.r[3]};
      if (key.s[0] != 1 || key.s[1] != 1 || key.s[2] != 1) node.scale = {key.s[0], key.s[1], key.s[2]};
    }
    model.nodes.push_back(node);
    model.nodes[static_cast<std::size_t>(sj.parent)].children.push_back(static_cast<int>(k));
  }
  tinygltf::Skin skin;
  skin.name = info().name + "_skin";
  skin.skeleton = 0;
  skin.inverseBindMatrices = inverse_bind;
  for (int j = 0; j < m; ++j) skin.joints.push_back(j);
  model.skins.push_back(skin);

  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = position;
  primitive.attributes["NORMAL"] = normal;
  primitive.attributes["JOINTS_0"] = joints;
  primitive.attributes["WEIGHTS_0"] = weights;
  primitive.indices = indices;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh mesh;
  mesh.name = info().name;
  mesh.primitives.push_back(std::move(primitive));
  model.meshes.push_back(std::move(mesh));
  tinygltf::Node mesh_node;
  mesh_node.name = info().name;
  mesh_node.mesh = 0;
  mesh_node.skin = 0;
  model.nodes.push_back(mesh_node);

  tinygltf::Scene scene;
  scene.nodes = {0, static_cast<int>(model.nodes.size() - 1)};
  model.scenes.push_back(std::move(scene));
  model.defaultScene = 0;

  tinygltf::Animation animation;
  animation.name = "bake";
  auto channel = [&](int node, const char* path, int output) {
    tinygltf::AnimationSampler sampler;
    sampler.input = time;
    sampler.output = output;
    sampler.interpolation = "LINEAR";
    animation.samplers.push_back(std::move(sampler));
    tinygltf::AnimationChannel c;
    c.sampler = static_cast<int>(animation.samplers.size() - 1);
    c.target_node = node;
    c.target_path = path;
    animation.channels.push_back(std::move(c));
  };
  // A joint that never leaves its rest pose needs no channel; when nothing moves at all, every
  // joint keeps its channels (an animation needs one).
  std::vector<char> moves(keys_.size(), 0);
  bool any = info().body_moves;
  for (std::size_t j = 0; j < keys_.size(); ++j) {
    for (const JointKey& k : keys_[j]) {
      if (!(k == rest_keys_[j + 1])) {
        moves[j] = 1;
        any = true;
        break;
      }
    }
  }
  // The channels a joint has: a station joint its translation and rotation (and its scale without
  // a ring), a ring joint its scale (RingMotion::shift: its translation).
  std::vector<float> track(frames * 4);
  for (std::size_t j = 0; j < keys_.size(); ++j) {
    if (any && !moves[j]) continue;
    const int node = static_cast<int>(j + 1);
    const bool ring_joint = fit_->joints()[j + 1].ring >= 0;
    const bool translation = !ring_joint || layout_.motion == RingMotion::shift;
    const bool rotation = !ring_joint;
    const bool scale = layout_.ring <= 1 || (ring_joint && layout_.motion == RingMotion::scale);
    if (translation) {
      for (std::size_t k = 0; k < frames; ++k) std::memcpy(&track[3 * k], keys_[j][k].t, 12);
      channel(node, "translation", add_data(track.data(), frames, 3, kFloat, TINYGLTF_TYPE_VEC3, 0));
    }
    if (rotation) {
      for (std::size_t k = 0; k < frames; ++k) std::memcpy(&track[4 * k], keys_[j][k].r, 16);
      channel(node, "rotation", add_data(track.data(), frames, 4, kFloat, TINYGLTF_TYPE_VEC4, 0));
    }
    if (scale) {
      for (std::size_t k = 0; k < frames; ++k) std::memcpy(&track[3 * k], keys_[j][k].s, 12);
      channel(node, "scale", add_data(track.data(), frames, 3, kFloat, TINYGLTF_TYPE_VEC3, 0));
    }
  }
  if (info().body_moves) {
    channel(0, "translation", add_data(body_keys_.translations.data(), frames, 3, kFloat, TINYGLTF_TYPE_VEC3, 0));
    channel(0, "rotation", add_data(body_keys_.rotations.data(), frames, 4, kFloat, TINYGLTF_TYPE_VEC4, 0));
  }
  model.animations.push_back(std::move(animation));
  return model;
}

void SkinWriter::complete(io::Publication& outputs) {
  std::vector<unsigned char> bin;
  const tinygltf::Model model = build_model(bin);
  std::ostringstream stream;
  tinygltf::TinyGLTF gltf;
  if (!gltf.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/false, /*writeBinary=*/false)) {
    fail(ErrorCategory::internal, out().string() + ": tinygltf could not serialize the model");
  }
  nlohmann::json json = nlohmann::json::parse(stream.str());
  json["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}}});
  std::string text = json.dump();
  text.append((4 - text.size() % 4) % 4, ' ');
  const std::uint64_t total = 12 + 8 + text.size() + 8 + bin.size();
  if (total > kGlbMaxBytes) {
    fail(ErrorCategory::unsupported,
         out().string() + ": the bake needs " + std::to_string(total) + " bytes, over the 4 GiB a .glb can hold");
  }
  auto u32 = [](std::uint64_t v) { return static_cast<std::uint32_t>(v); };
  const std::uint32_t header[5] = {0x46546C67u /* "glTF" */, 2, u32(total), u32(text.size()), 0x4E4F534Au /* "JSON" */};
  const std::uint32_t bin_header[2] = {u32(bin.size()), 0x004E4942u /* "BIN\0" */};
  final_ = std::make_unique<io::TempFile>(out());
  final_->write(header, sizeof header);
  final_->write(text);
  final_->write(bin_header, sizeof bin_header);
  final_->write(bin.data(), bin.size());
  final_->seal();
  outputs.add(std::move(final_));
}

}  // namespace

int skin_stations(const SweepShape& rest, int stations_per_span) {
  return (rest.section_count() - 1) * stations_per_span + 1;
}

DefaultSkinJoints default_skin_joints(std::span<const SweepDef> sweeps, int stations_per_span) {
  DefaultSkinJoints chosen;
  for (const SweepDef& def : sweeps) {
    const int stations = skin_stations(def.rest, stations_per_span);
    if (stations < chosen.joints) {
      chosen.joints = std::max(kMinSkinJoints, stations);
      chosen.fewest = &def;
    }
  }
  return chosen;
}

void check_skin_joints(const SkinLayout& layout, std::span<const SkinSweep> sweeps, int stations_per_span) {
  const int joints = layout.stations;
  if (joints < kMinSkinJoints || joints > kMaxSkinJoints) {
    fail(ErrorCategory::usage, "--joints: expected " + std::to_string(kMinSkinJoints) + " to " +
                                   std::to_string(kMaxSkinJoints) + " joints a sweep, got " + std::to_string(joints));
  }
  if (layout.ring < 1 || layout.ring > kMaxRingJoints) {
    fail(ErrorCategory::usage, "--ring-joints: expected 1 to " + std::to_string(kMaxRingJoints) +
                                   " joints a station, got " + std::to_string(layout.ring));
  }
  for (const SkinSweep& sw : sweeps) {
    const int stations = skin_stations(*sw.rest, stations_per_span);
    if (joints > stations) {
      fail(ErrorCategory::usage,
           "--joints: " + std::to_string(joints) + " joints on sweep \"" + sw.name + "\", which has " +
               std::to_string(stations) + " stations (" + std::to_string(sw.rest->section_count()) + " key sections, " +
               std::to_string(stations_per_span) + " stations a span): at most one joint a station");
    }
  }
  // JOINTS_0 is unsigned short: a skeleton of more joints would wrap its indices.
  if (!sweeps.empty()) {
    const std::uint64_t per_sweep =
        static_cast<std::uint64_t>(joints) +
        static_cast<std::uint64_t>(joints - 1) * static_cast<std::uint64_t>(layout.ring > 1 ? layout.ring : 0);
    const std::uint64_t total = 1 + per_sweep * sweeps.size();
    if (total > 65535) {
      fail(ErrorCategory::usage, "--joints " + std::to_string(joints) + " --ring-joints " +
                                     std::to_string(layout.ring) + " on " + std::to_string(sweeps.size()) +
                                     " sweeps: " + std::to_string(total) +
                                     " joints, more than a glTF skin's 65535 joint indices hold");
    }
  }
}

SkinBakeWriter make_skin_bake_writer(const std::filesystem::path& out, std::vector<SkinSweep> sweeps,
                                     const SkinLayout& layout) {
  check_skin_joints(layout, {}, 1);
  auto writer = std::make_unique<SkinWriter>(out, std::move(sweeps), layout);
  SkinPoser* poser = writer.get();
  return {std::move(writer), poser};
}

}  // namespace sweep::assets
