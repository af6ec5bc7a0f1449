// The skinned .glb writer (bake_skin.h). The binary chunk is assembled in memory in finish() (the
// rest mesh, the skin's attributes and matrices, and the joints' keys, all small) and written with
// the GLB header and the JSON (tinygltf's serializer, keys sorted: stable bytes) into a temporary
// that is renamed onto the output. Layout, every block 4-byte aligned:
//   rest POSITION | rest NORMAL | triangle indices (uint32) | JOINTS_0 (u8 or u16 × 4) |
//   WEIGHTS_0 (float × 4) | inverse bind matrices (mat4) | key times (F floats) |
//   per animated joint: translations (F × vec3) | rotations (F × vec4) | scales (F × vec3) |
//   [a moving body: its translations | rotations]
#include "assets/bake_skin.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "assets/bake_detail.h"
#include "assets/smooth_normals.h"
#include "core/error.h"

namespace sweep::io {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the .glb writer stores host floats as glTF's little-endian data");

constexpr std::uint64_t kGlbMaxBytes = std::numeric_limits<std::uint32_t>::max();

// One joint's pose as written: translation, rotation (x, y, z, w), scale.
struct JointKey {
  float t[3];
  float r[4];
  float s[3];
  bool operator==(const JointKey& o) const {
    return std::memcmp(this, &o, sizeof(JointKey)) == 0;
  }
};
static_assert(sizeof(JointKey) == 40);

// The matrix a joint key stands for, T·R·S, in double from the floats (the rotation normalized, as
// engines do).
Eigen::Matrix4d key_matrix(const JointKey& k) {
  Eigen::Quaterniond q(k.r[3], k.r[0], k.r[1], k.r[2]);
  q.normalize();
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = q.toRotationMatrix() * Eigen::Vector3d(k.s[0], k.s[1], k.s[2]).asDiagonal();
  m.topRightCorner<3, 1>() = Eigen::Vector3d(k.t[0], k.t[1], k.t[2]);
  return m;
}

// The station frame of `shape` at t and its radii at the sample angles (no floor).
struct Station {
  Frame frame;
  std::vector<double> radii;
};
Station station(const SweepShape& shape, double t) {
  Station st{frame_at(shape, t), std::vector<double>(static_cast<std::size_t>(shape.radial_count))};
  radii_at_samples(shape, t, st.radii);
  return st;
}

// The cross-section's change at a station as one joint carries it: in the station's plane, a scale
// along each of its axes and a shift, x' = a·x + c_x and y' = b·y + c_y, fitted by least squares to
// the sample points (r_j cos θ_j, r_j sin θ_j) → (r'_j cos θ_j, r'_j sin θ_j). A section that
// swells evenly gives a = b (its mean radius ratio) and no shift; one squeezed from a side, a
// smaller scale across the squeeze and a shift away from it.
struct InPlane {
  double a = 1, b = 1, cx = 0, cy = 0;
};
InPlane fit_in_plane(const SweepShape& shape, std::span<const double> rest, std::span<const double> now) {
  InPlane f;
  const std::size_t n = rest.size();
  for (int axis = 0; axis < 2; ++axis) {
    double mx = 0, my = 0;
    std::vector<double> x(n), y(n);
    for (std::size_t j = 0; j < n; ++j) {
      const double angle = shape.sample_angle(static_cast<int>(j));
      const double c = axis == 0 ? std::cos(angle) : std::sin(angle);
      x[j] = rest[j] * c;
      y[j] = now[j] * c;
      mx += x[j];
      my += y[j];
    }
    mx /= static_cast<double>(n);
    my /= static_cast<double>(n);
    double sxx = 0, sxy = 0;
    for (std::size_t j = 0; j < n; ++j) {
      sxx += (x[j] - mx) * (x[j] - mx);
      sxy += (x[j] - mx) * (y[j] - my);
    }
    const double scale = sxx > 0 && std::isfinite(sxy / sxx) ? sxy / sxx : 1.0;
    (axis == 0 ? f.a : f.b) = scale;
    (axis == 0 ? f.cx : f.cy) = my - scale * mx;
  }
  return f;
}

class SkinWriter final : public detail::BakeWriterBase, public SkinPoser {
 public:
  SkinWriter(std::filesystem::path out, std::vector<SkinSweep> sweeps, int joints)
      : BakeWriterBase(std::move(out)), sweeps_(std::move(sweeps)), per_sweep_(joints) {}

  std::vector<std::filesystem::path> files() const override { return {out()}; }
  void pose(std::span<const SweepShape* const> shapes) override;
  const SkinError& skin_error() const override { return error_; }
  int joint_count() const override { return 1 + static_cast<int>(sweeps_.size()) * per_sweep_; }

 protected:
  void start(const Mesh& mesh) override;
  void write_frame(int index, std::span<const Eigen::Vector3f> positions) override;
  void complete(Publication& outputs) override;
  void abandon() noexcept override {
    if (final_) final_->discard();
  }

 private:
  JointKey key_of(const Frame& f, const InPlane& in_plane) const;
  tinygltf::Model build_model(std::vector<unsigned char>& bin) const;

  std::vector<SkinSweep> sweeps_;
  int per_sweep_ = 0;
  std::vector<double> station_t_;        // per sweep, per_sweep_ parameters
  std::vector<std::vector<double>> rest_radii_;  // per sweep joint: the rest radii at its station
  std::vector<JointKey> rest_keys_;       // per sweep joint: the rest pose (node defaults)
  std::vector<Eigen::Matrix4f> inverse_bind_;  // per skin joint (0: the body)
  std::vector<std::vector<JointKey>> keys_;  // per sweep joint, per frame
  std::vector<std::uint32_t> triangles_;
  std::vector<Eigen::Vector3f> normals_;
  Eigen::Vector3f rest_min_, rest_max_;
  // Per vertex: 4 joints and weights (skin joint indices).
  std::vector<std::array<std::uint16_t, 4>> joints_;
  std::vector<std::array<float, 4>> weights_;
  // The bound vertices, with their sweep (for the error's length).
  std::vector<std::uint32_t> bound_;
  std::vector<double> bound_length_;
  std::vector<const SweepShape*> shapes_;
  bool posed_ = false;
  detail::BodyKeys body_keys_;  // with a moving body
  SkinError error_;
  double sum_squares_ = 0;
  std::unique_ptr<TempFile> final_;
};

JointKey SkinWriter::key_of(const Frame& f, const InPlane& in_plane) const {
  JointKey k{};
  const Vec3 t = f.center + f.rotation * Vec3(in_plane.cx, in_plane.cy, 0);
  for (int c = 0; c < 3; ++c) k.t[c] = static_cast<float>(t[c]);
  const Quat q = f.rotation.normalized();
  k.r[0] = static_cast<float>(q.x());
  k.r[1] = static_cast<float>(q.y());
  k.r[2] = static_cast<float>(q.z());
  k.r[3] = static_cast<float>(q.w());
  k.s[0] = static_cast<float>(in_plane.a);
  k.s[1] = static_cast<float>(in_plane.b);
  k.s[2] = 1.0f;
  return k;
}

void SkinWriter::start(const Mesh& mesh) {
  const std::size_t n = rest().size();
  triangles_ = mesh.triangles();
  if (triangles_.empty()) {
    fail(ErrorCategory::unsupported,
         out().string() + ": the mesh has no faces; a .glb bake needs a surface (use .pc2)");
  }
  const int m = joint_count();
  if (m > 65536) {
    fail(ErrorCategory::unsupported, out().string() + ": " + std::to_string(m) +
                                         " joints are more than a skin's 16-bit joint indices reach");
  }
  normals_ = detail::smooth_normals(mesh.positions, triangles_);
  rest_min_ = rest_max_ = rest().front();
  for (const Eigen::Vector3f& p : rest()) {
    rest_min_ = rest_min_.cwiseMin(p);
    rest_max_ = rest_max_.cwiseMax(p);
  }

  // Stations, rest keys and inverse bind matrices (from the rest keys as written).
  inverse_bind_.assign(1, Eigen::Matrix4f::Identity());
  for (const SkinSweep& sw : sweeps_) {
    const double length = sw.rest->length();
    for (int j = 0; j < per_sweep_; ++j) {
      const double t = j == per_sweep_ - 1 ? length : length * j / (per_sweep_ - 1);
      station_t_.push_back(t);
      Station st = station(*sw.rest, t);
      const JointKey key = key_of(st.frame, InPlane{});
      rest_radii_.push_back(std::move(st.radii));
      rest_keys_.push_back(key);
      inverse_bind_.push_back(key_matrix(key).inverse().cast<float>());
    }
  }
  keys_.assign(rest_keys_.size(), {});
  for (auto& k : keys_) k.reserve(static_cast<std::size_t>(info().frame_count));

  // Weights: the body joint for everything unbound; hat functions of t for bound vertices.
  joints_.assign(n, {0, 0, 0, 0});
  weights_.assign(n, {1.0f, 0.0f, 0.0f, 0.0f});
  std::vector<char> seen(n, 0);
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    const bind::SweepBinding& b = *sweeps_[s].binding;
    const double length = sweeps_[s].rest->length();
    const double h = length / (per_sweep_ - 1);
    const int first = 1 + static_cast<int>(s) * per_sweep_;
    for (std::size_t i = 0; i < b.size(); ++i) {
      const std::uint32_t v = b.vertices[i];
      if (v >= n || seen[v]) {
        fail(ErrorCategory::internal, out().string() + ": vertex " + std::to_string(v) +
                                          " bound twice or not in the mesh");
      }
      seen[v] = 1;
      const double x = std::clamp(static_cast<double>(b.t[i]) / h, 0.0, double(per_sweep_ - 1));
      const int j = std::min(static_cast<int>(std::floor(x)), per_sweep_ - 2);
      const double u = x - j;
      const double blend = std::clamp(static_cast<double>(b.weight[i]), 0.0, 1.0);
      float wa = static_cast<float>((1 - u) * blend), wb = static_cast<float>(u * blend);
      float wr = 1.0f - wa - wb;
      if (wr < 0) wr = 0;
      // Slots: the two stations, then the body; a zero weight keeps joint 0 (the body).
      std::array<std::uint16_t, 4> js{0, 0, 0, 0};
      std::array<float, 4> ws{0, 0, 0, 0};
      int slot = 0;
      auto put = [&](int joint, float w) {
        if (w > 0) {
          js[static_cast<std::size_t>(slot)] = static_cast<std::uint16_t>(joint);
          ws[static_cast<std::size_t>(slot)] = w;
          ++slot;
        }
      };
      put(first + j, wa);
      put(first + j + 1, wb);
      put(0, wr);
      // Exactly 1 in float: the largest weight takes what rounding left over.
      float sum = 0;
      for (int k = 1; k < 4; ++k) sum += ws[static_cast<std::size_t>(k)];
      ws[0] = std::max(0.0f, 1.0f - sum);
      joints_[v] = js;
      weights_[v] = ws;
      bound_.push_back(v);
      bound_length_.push_back(length);
    }
  }

  const std::uint64_t frames = static_cast<std::uint64_t>(info().frame_count);
  const std::uint64_t joint_bytes = m <= 256 ? 4 : 8;
  const std::uint64_t estimate = 28 + 8192 + 600 * std::uint64_t(m) + 24 * std::uint64_t{n} +
                                 4 * triangles_.size() + (joint_bytes + 16) * n + 64 * std::uint64_t(m) +
                                 4 * frames + 40 * frames * rest_keys_.size() +
                                 (info().body_moves ? 28 * frames : 0);
  set_estimate(estimate);
  if (estimate > kGlbMaxBytes) {
    fail(ErrorCategory::unsupported, out().string() + ": about " + std::to_string(estimate >> 20) +
                                         " MiB, over the 4 GiB a .glb can hold");
  }
}

void SkinWriter::pose(std::span<const SweepShape* const> shapes) {
  if (shapes.size() != sweeps_.size()) {
    fail(ErrorCategory::internal, out().string() + ": " + std::to_string(shapes.size()) +
                                      " sweep shapes given for a skin of " +
                                      std::to_string(sweeps_.size()) + " sweeps");
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
  // The joints' keys of this frame, and the skinning matrices they give (joint · inverse bind).
  std::vector<Eigen::Matrix4d> skinning(1 + rest_keys_.size(), Eigen::Matrix4d::Identity());
  std::size_t joint = 0;
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    for (int j = 0; j < per_sweep_; ++j, ++joint) {
      const Station st = station(*shapes_[s], station_t_[joint]);
      JointKey key = key_of(st.frame, fit_in_plane(*shapes_[s], rest_radii_[joint], st.radii));
      std::vector<JointKey>& track = keys_[joint];
      const JointKey& before = track.empty() ? rest_keys_[joint] : track.back();
      const float dot = key.r[0] * before.r[0] + key.r[1] * before.r[1] + key.r[2] * before.r[2] +
                        key.r[3] * before.r[3];
      if (dot < 0) {
        for (float& c : key.r) c = -c;
      }
      track.push_back(key);
      skinning[joint + 1] = key_matrix(key) * inverse_bind_[joint + 1].cast<double>();
    }
  }
  // The skinned bound vertices against the bake.
  for (std::size_t i = 0; i < bound_.size(); ++i) {
    const std::uint32_t v = bound_[i];
    const Eigen::Vector4d p(rest()[v].x(), rest()[v].y(), rest()[v].z(), 1.0);
    Eigen::Vector4d q = Eigen::Vector4d::Zero();
    for (int k = 0; k < 4; ++k) {
      const float w = weights_[v][static_cast<std::size_t>(k)];
      if (w != 0) q += static_cast<double>(w) * (skinning[joints_[v][static_cast<std::size_t>(k)]] * p);
    }
    const double e = (q.head<3>() - positions[v].cast<double>()).norm() / bound_length_[i];
    sum_squares_ += e * e;
    if (e > error_.max_relative) {
      error_.max_relative = e;
      error_.max_frame = index;
      error_.max_vertex = v;
    }
  }
  error_.samples += bound_.size();
  error_.rms_relative =
      error_.samples ? std::sqrt(sum_squares_ / static_cast<double>(error_.samples)) : 0.0;
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
  auto add_data = [&](const auto* data, std::size_t elements, std::size_t per_element, int component,
                      int type, int target) {
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
  const int indices = add_data(triangles_.data(), triangles_.size(), 1,
                               TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                               TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  int joints = 0;
  if (m <= 256) {
    std::vector<std::uint8_t> small(4 * n);
    for (std::size_t v = 0; v < n; ++v)
      for (std::size_t k = 0; k < 4; ++k) small[4 * v + k] = static_cast<std::uint8_t>(joints_[v][k]);
    joints = add_data(small.data(), n, 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, kArray);
  } else {
    joints = add_data(joints_[0].data(), n, 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                      TINYGLTF_TYPE_VEC4, kArray);
  }
  const int weights = add_data(weights_[0].data(), n, 4, kFloat, TINYGLTF_TYPE_VEC4, kArray);
  const int inverse_bind =
      add_data(inverse_bind_[0].data(), inverse_bind_.size(), 16, kFloat, TINYGLTF_TYPE_MAT4, 0);

  std::vector<float> times(frames);
  for (std::size_t k = 0; k < frames; ++k) {
    times[k] = static_cast<float>(static_cast<double>(k) / info().fps);
    if (k > 0 && !(times[k] > times[k - 1])) {
      fail(ErrorCategory::unsupported,
           out().string() + ": frame " + std::to_string(k) + " at " + std::to_string(info().fps) +
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
    root.rotation = {body_keys_.rotations[0], body_keys_.rotations[1], body_keys_.rotations[2], body_keys_.rotations[3]};
  }
  model.nodes.push_back(root);
  std::size_t joint = 0;
  for (const SkinSweep& sw : sweeps_) {
    for (int j = 0; j < per_sweep_; ++j, ++joint) {
      tinygltf::Node node;
      std::string digits = std::to_string(j);
      const std::size_t width = std::to_string(per_sweep_ - 1).size() < 2 ? 2 : std::to_string(per_sweep_ - 1).size();
      if (digits.size() < width) digits.insert(0, width - digits.size(), '0');
      node.name = sw.name + "." + digits;
      const JointKey& k = rest_keys_[joint];
      node.translation = {k.t[0], k.t[1], k.t[2]};
      node.rotation = {k.r[0], k.r[1], k.r[2], k.r[3]};
      model.nodes.push_back(node);
      model.nodes[0].children.push_back(static_cast<int>(model.nodes.size() - 1));
    }
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
      if (!(k == rest_keys_[j])) {
        moves[j] = 1;
        any = true;
        break;
      }
    }
  }
  std::vector<float> track(frames * 4);
  for (std::size_t j = 0; j < keys_.size(); ++j) {
    if (any && !moves[j]) continue;
    const int node = static_cast<int>(j + 1);
    for (std::size_t k = 0; k < frames; ++k) std::memcpy(&track[3 * k], keys_[j][k].t, 12);
    channel(node, "translation", add_data(track.data(), frames, 3, kFloat, TINYGLTF_TYPE_VEC3, 0));
    for (std::size_t k = 0; k < frames; ++k) std::memcpy(&track[4 * k], keys_[j][k].r, 16);
    channel(node, "rotation", add_data(track.data(), frames, 4, kFloat, TINYGLTF_TYPE_VEC4, 0));
    for (std::size_t k = 0; k < frames; ++k) std::memcpy(&track[3 * k], keys_[j][k].s, 12);
    channel(node, "scale", add_data(track.data(), frames, 3, kFloat, TINYGLTF_TYPE_VEC3, 0));
  }
  if (info().body_moves) {
    channel(0, "translation",
            add_data(body_keys_.translations.data(), frames, 3, kFloat, TINYGLTF_TYPE_VEC3, 0));
    channel(0, "rotation", add_data(body_keys_.rotations.data(), frames, 4, kFloat, TINYGLTF_TYPE_VEC4, 0));
  }
  model.animations.push_back(std::move(animation));
  return model;
}

void SkinWriter::complete(Publication& outputs) {
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
    fail(ErrorCategory::unsupported, out().string() + ": the bake needs " + std::to_string(total) +
                                         " bytes, over the 4 GiB a .glb can hold");
  }
  auto u32 = [](std::uint64_t v) { return static_cast<std::uint32_t>(v); };
  const std::uint32_t header[5] = {0x46546C67u /* "glTF" */, 2, u32(total), u32(text.size()),
                                   0x4E4F534Au /* "JSON" */};
  const std::uint32_t bin_header[2] = {u32(bin.size()), 0x004E4942u /* "BIN\0" */};
  final_ = std::make_unique<TempFile>(out());
  final_->write(header, sizeof header);
  final_->write(text);
  final_->write(bin_header, sizeof bin_header);
  final_->write(bin.data(), bin.size());
  final_->seal();
  outputs.add(std::move(final_));
}

}  // namespace

void check_skin_joints(int joints, std::span<const SkinSweep> sweeps, int stations_per_span) {
  if (joints < kMinSkinJoints || joints > kMaxSkinJoints) {
    fail(ErrorCategory::usage, "--joints: expected " + std::to_string(kMinSkinJoints) + " to " +
                                   std::to_string(kMaxSkinJoints) + " joints a sweep, got " +
                                   std::to_string(joints));
  }
  for (const SkinSweep& sw : sweeps) {
    const int stations = (sw.rest->section_count() - 1) * stations_per_span + 1;
    if (joints > stations) {
      fail(ErrorCategory::usage,
           "--joints: " + std::to_string(joints) + " joints on sweep \"" + sw.name + "\", which has " +
               std::to_string(stations) + " stations (" + std::to_string(sw.rest->section_count()) +
               " key sections, " + std::to_string(stations_per_span) +
               " stations a span): at most one joint a station");
    }
  }
}

SkinBakeWriter make_skin_bake_writer(const std::filesystem::path& out, std::vector<SkinSweep> sweeps,
                                     int joints) {
  if (joints < kMinSkinJoints || joints > kMaxSkinJoints) {
    fail(ErrorCategory::usage, "--joints: expected " + std::to_string(kMinSkinJoints) + " to " +
                                   std::to_string(kMaxSkinJoints) + ", got " + std::to_string(joints));
  }
  auto writer = std::make_unique<SkinWriter>(out, std::move(sweeps), joints);
  SkinPoser* poser = writer.get();
  return {std::move(writer), poser};
}

}  // namespace sweep::io
