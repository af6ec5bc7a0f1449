// .glb: glTF 2.0 binary with one morph target per baked frame and a weights animation (bake.h).
// Each target moves positions and normals (POSITION and NORMAL deltas), so that a bent part is lit
// as bent: the frame's smooth normals, computed as the rest's are, minus the rest's.
//
// Streaming: the binary chunk is written as frames arrive into a nameless scratch file beside the
// output. Its layout, every block 4-byte aligned (all elements are 4 bytes):
//   rest POSITION (n × vec3) | rest NORMAL (n × vec3) | triangle indices (uint32) |
//   [sparse target indices (uint32, ascending, shared by every target)] |
//   animation times (F floats) | animation weights, one-hot F × F as a sparse accessor
//   (F uint32 flat indices k·F + k, then F floats 1) |
//   [sparse normal indices (uint32): the listed vertices and every vertex on a face with one] |
//   frame 0 deltas | frame 0 normal deltas | frame 1 deltas | ...   (s × vec3 and s' × vec3 each:
//   s = listed vertices, s' = those and their face neighbours, or n when dense) |
//   [a moving body: translations (F × vec3) | rotations (F × vec4), the node's animation]
// finish() builds the JSON with tinygltf (its serializer sorts keys, so the bytes are stable),
// then writes the GLB header, the JSON chunk and the scratch file's bytes as the BIN chunk into a
// temporary that is renamed onto the output.
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sweep/assets/bake.h"
#include "sweep/assets/bake_detail.h"
#include "sweep/assets/gltf_passthrough.h"
#include "sweep/assets/smooth_normals.h"
#include "sweep/core/error.h"

namespace sweep::assets {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the .glb writer stores host floats as glTF's little-endian data");
static_assert(sizeof(Eigen::Vector3f) == 12, "Vector3f arrays are written as packed float triples");

using detail::kGlbMaxBytes;
// Upper bound on the JSON a frame adds (two accessors, buffer views, target, name, weight).
constexpr std::uint64_t kJsonBytesPerFrame = 1024;
constexpr std::uint64_t kJsonBytesFixed = 8192;

class GltfWriter final : public detail::BakeWriterBase {
 public:
  explicit GltfWriter(std::filesystem::path out) : BakeWriterBase(std::move(out)) {}

  std::vector<std::filesystem::path> files() const override { return {out()}; }

 protected:
  void start(const Mesh& mesh) override;
  void write_frame(int index, std::span<const Eigen::Vector3f> positions) override;
  void complete(io::Publication& outputs) override;
  int morph_targets() const override { return info().frame_count; }
  void abandon() noexcept override {
    if (scratch_) scratch_->discard();
    if (final_) final_->discard();
  }

 private:
  struct Block {
    std::uint64_t offset = 0, length = 0;
  };
  Block append_block(const void* data, std::size_t bytes) {
    Block b{scratch_->size(), bytes};
    scratch_->write(data, bytes);
    return b;
  }
  tinygltf::Model build_model() const;
  void start_passthrough(const Mesh& mesh);
  void write_glb(io::Publication& outputs, nlohmann::json json);

  std::unique_ptr<io::TempFile> scratch_, final_;
  // A glTF source: the input document whole plus the bake (gltf_passthrough.h).
  std::unique_ptr<detail::GltfPassthrough> passthrough_;
  detail::AppendBin append_bin_ = [this](const void* data, std::size_t bytes) {
    const Block b = append_block(data, bytes);
    return detail::BinBlock{b.offset, b.length};
  };
  bool sparse_ = false;
  std::vector<std::uint32_t> targets_;  // the listed vertices when sparse
  // ... and the vertices whose normal can change: those and every vertex on a face with one.
  std::vector<std::uint32_t> normal_targets_;
  std::vector<std::uint32_t> triangles_;
  std::vector<Eigen::Vector3f> rest_normals_;
  std::size_t triangle_index_count_ = 0;
  Block positions_, normals_, indices_, sparse_indices_, sparse_normal_indices_, times_, weight_indices_, weights_;
  Eigen::Vector3f rest_min_, rest_max_;
  float last_time_ = 0;
  std::vector<Eigen::Vector3f> delta_, normal_delta_;  // one frame's deltas, reused
  std::vector<Block> frame_blocks_, normal_blocks_;
  std::vector<Eigen::Vector3f> frame_min_, frame_max_;
  // A moving body: its pose per frame (translation xyz, rotation xyzw), animated on the node.
  detail::BodyKeys body_keys_;  // with a moving body
  Block body_translation_block_, body_rotation_block_;
};

void GltfWriter::start_passthrough(const Mesh&) {
  const std::uint64_t frames = static_cast<std::uint64_t>(info().frame_count);
  if (frames * frames > std::uint64_t{UINT32_MAX}) {
    fail(ErrorCategory::unsupported,
         out().string() + ": " + std::to_string(frames) +
             " frames are more morph targets than a .glb's weights can index (at most 65,535); "
             "bake to .pc2 or an .obj sequence");
  }
  // The input's JSON and its buffers and images (fixed_bytes; a .glb's file size would count them
  // twice), then the bake's additions.
  const std::uint64_t estimate =
      28 + kJsonBytesFixed + passthrough_->json_bytes() + passthrough_->fixed_bytes() + 8 * frames +
      (kJsonBytesPerFrame * passthrough_->deformed_primitives() + passthrough_->bytes_per_frame()) * frames;
  set_estimate(estimate);
  if (estimate > kGlbMaxBytes) {
    fail(ErrorCategory::unsupported, out().string() + ": " + std::to_string(frames) + " frames need about " +
                                         std::to_string(estimate >> 20) +
                                         " MiB, over the 4 GiB a .glb can hold; bake fewer frames or to .pc2");
  }
  scratch_ = std::make_unique<io::TempFile>(out(), /*scratch=*/true);
  passthrough_->start(append_bin_);
}

void GltfWriter::start(const Mesh& mesh) {
  if (detail::is_passthrough_source(info().source.path) || info().skinned) {
    // A skinned character (glTF, or read through assimp: made a glTF character) keeps its skeleton.
    // A skinned clip moves every vertex; the parts' vertices are those that leave their skinned pose.
    // With joints in the character's skeleton no vertex gets a target.
    passthrough_ = detail::GltfPassthrough::open(info().source.path, out(), mesh,
                                                 info().character_joints ? std::vector<std::uint32_t>{}
                                                 : info().skinned        ? info().part_vertices
                                                                         : animated(),
                                                 info());
    if (passthrough_) {
      start_passthrough(mesh);
      return;
    }
  }
  if (info().skinned) fail(ErrorCategory::internal, out().string() + ": a skinned clip's bake needs its glTF source");
  const std::size_t n = rest().size();
  const std::uint64_t frames = static_cast<std::uint64_t>(info().frame_count);
  const std::vector<std::uint32_t> triangles = mesh.triangles();
  if (triangles.empty()) {
    fail(ErrorCategory::unsupported,
         out().string() + ": the mesh has no faces; a .glb bake needs a surface (use .pc2)");
  }
  triangle_index_count_ = triangles.size();
  sparse_ = !all_animated();
  if (sparse_) {
    // A sparse accessor needs at least one entry: with nothing listed, vertex 0 (always at rest,
    // so a zero delta) stands in.
    targets_ = animated().empty() ? std::vector<std::uint32_t>{0} : animated();
  }
  const std::uint64_t s = sparse_ ? targets_.size() : n;
  if (sparse_) {
    std::vector<char> near(n, 0);
    for (const std::uint32_t v : targets_) near[v] = 1;
    std::vector<char> ring = near;
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
      if (near[triangles[t]] || near[triangles[t + 1]] || near[triangles[t + 2]]) {
        for (int k = 0; k < 3; ++k) ring[triangles[t + static_cast<std::size_t>(k)]] = 1;
      }
    }
    for (std::uint32_t v = 0; v < n; ++v) {
      if (ring[v]) normal_targets_.push_back(v);
    }
  }
  const std::uint64_t sn = sparse_ ? normal_targets_.size() : n;
  triangles_ = triangles;

  // A .glb is at most 4 GiB: say so now, not after the whole simulation.
  // The weights are F × F values, one-hot: stored sparse (an index and a 1 per key), so their
  // flat index k·F + k must fit a uint32.
  if (frames * frames > std::uint64_t{UINT32_MAX}) {
    fail(ErrorCategory::unsupported,
         out().string() + ": " + std::to_string(frames) +
             " frames are more morph targets than a .glb's weights can index (at most 65,535); "
             "bake to .pc2 or an .obj sequence");
  }
  const std::uint64_t bin = 24 * std::uint64_t{n} + 4 * std::uint64_t{triangles.size()} +
                            (sparse_ ? 4 * s + 4 * sn : 0) + 4 * frames + 8 * frames + 12 * (s + sn) * frames +
                            (info().body_moves ? 28 * frames : 0);
  const std::uint64_t estimate = 28 + kJsonBytesFixed + kJsonBytesPerFrame * frames + bin;
  set_estimate(estimate);
  if (estimate > kGlbMaxBytes) {
    fail(ErrorCategory::unsupported, out().string() + ": " + std::to_string(frames) + " frames of " +
                                         std::to_string(s) + " moving vertices need about " +
                                         std::to_string(estimate >> 20) +
                                         " MiB, over the 4 GiB a .glb can hold; bake fewer frames or to .pc2");
  }

  scratch_ = std::make_unique<io::TempFile>(out(), /*scratch=*/true);

  rest_min_ = rest_max_ = rest().front();
  for (const Eigen::Vector3f& p : rest()) {
    rest_min_ = rest_min_.cwiseMin(p);
    rest_max_ = rest_max_.cwiseMax(p);
  }
  positions_ = append_block(rest().data(), n * sizeof(Eigen::Vector3f));

  rest_normals_ = detail::smooth_normals(mesh.positions, triangles);
  normals_ = append_block(rest_normals_.data(), n * sizeof(Eigen::Vector3f));
  indices_ = append_block(triangles.data(), triangles.size() * sizeof(std::uint32_t));
  if (sparse_) {
    sparse_indices_ = append_block(targets_.data(), targets_.size() * 4);
    sparse_normal_indices_ = append_block(normal_targets_.data(), normal_targets_.size() * 4);
  }

  // Key k at k / fps; rounded to float32 they must still increase.
  {
    std::vector<float> times(frames);
    for (std::uint64_t k = 0; k < frames; ++k) {
      times[k] = static_cast<float>(static_cast<double>(k) / info().fps);
      if (k > 0 && !(times[k] > times[k - 1])) {
        fail(ErrorCategory::unsupported, out().string() + ": frame " + std::to_string(k) + " at " +
                                             std::to_string(info().fps) +
                                             " frames/s has the same float32 time as the frame before it");
      }
    }
    last_time_ = times.back();
    times_ = append_block(times.data(), frames * 4);
  }
  // One-hot weights (key k: target k at 1, the rest 0) as a sparse accessor over zeros: the flat
  // indices k·F + k, then F ones. O(F), where the dense F × F floats grew with frames squared.
  {
    std::vector<std::uint32_t> at(frames);
    for (std::uint64_t k = 0; k < frames; ++k) at[k] = static_cast<std::uint32_t>(k * frames + k);
    weight_indices_ = append_block(at.data(), frames * 4);
    const std::vector<float> ones(frames, 1.0f);
    weights_ = append_block(ones.data(), frames * 4);
  }

  delta_.resize(s);
  normal_delta_.resize(sn);
  frame_blocks_.reserve(frames);
  normal_blocks_.reserve(frames);
  frame_min_.reserve(frames);
  frame_max_.reserve(frames);
}

void GltfWriter::write_frame(int, std::span<const Eigen::Vector3f> positions) {
  if (passthrough_) {
    passthrough_->frame(positions, body_pose(), append_bin_);
    return;
  }
  if (info().body_moves) {
    body_keys_.add(body_pose());
  }
  const std::vector<Eigen::Vector3f>& r = rest();
  Eigen::Vector3f lo = Eigen::Vector3f::Zero(), hi = Eigen::Vector3f::Zero();
  auto put = [&](std::size_t slot, std::size_t v) {
    Eigen::Vector3f& d = delta_[slot];
    d = positions[v] - r[v];
    if (slot == 0) {
      lo = hi = d;
    } else {
      lo = lo.cwiseMin(d);
      hi = hi.cwiseMax(d);
    }
  };
  if (sparse_) {
    for (std::size_t i = 0; i < targets_.size(); ++i) put(i, targets_[i]);
    if (targets_.size() < r.size()) {  // the unlisted vertices' deltas are zeros
      lo = lo.cwiseMin(Eigen::Vector3f::Zero());
      hi = hi.cwiseMax(Eigen::Vector3f::Zero());
    }
  } else {
    for (std::size_t v = 0; v < r.size(); ++v) put(v, v);
  }
  frame_blocks_.push_back(append_block(delta_.data(), delta_.size() * sizeof(Eigen::Vector3f)));
  frame_min_.push_back(lo);
  frame_max_.push_back(hi);
  // The frame's normals, as the rest's were made, less the rest's.
  const std::vector<Eigen::Vector3f> normals = detail::smooth_normals(positions, triangles_);
  if (sparse_) {
    for (std::size_t i = 0; i < normal_targets_.size(); ++i)
      normal_delta_[i] = normals[normal_targets_[i]] - rest_normals_[normal_targets_[i]];
  } else {
    for (std::size_t v = 0; v < normals.size(); ++v) normal_delta_[v] = normals[v] - rest_normals_[v];
  }
  normal_blocks_.push_back(append_block(normal_delta_.data(), normal_delta_.size() * sizeof(Eigen::Vector3f)));
}

std::vector<double> to_doubles(const Eigen::Vector3f& v) {
  return {v.x(), v.y(), v.z()};
}

tinygltf::Model GltfWriter::build_model() const {
  const int frames = info().frame_count;
  const std::size_t n = rest().size();
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "sweep bake 1";

  auto add_view = [&](const Block& b, int target) {
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = b.offset;
    view.byteLength = b.length;
    view.target = target;
    model.bufferViews.push_back(view);
    return static_cast<int>(model.bufferViews.size() - 1);
  };
  auto add_accessor = [&](int view, int component, int type, std::size_t count) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = component;
    a.type = type;
    a.count = count;
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size() - 1);
  };
  constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;
  constexpr int kUint = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;

  const int position = add_accessor(add_view(positions_, TINYGLTF_TARGET_ARRAY_BUFFER), kFloat, TINYGLTF_TYPE_VEC3, n);
  model.accessors[position].minValues = to_doubles(rest_min_);
  model.accessors[position].maxValues = to_doubles(rest_max_);
  const int normal = add_accessor(add_view(normals_, TINYGLTF_TARGET_ARRAY_BUFFER), kFloat, TINYGLTF_TYPE_VEC3, n);
  const int indices = add_accessor(add_view(indices_, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER), kUint,
                                   TINYGLTF_TYPE_SCALAR, triangle_index_count_);
  const int sparse_view = sparse_ ? add_view(sparse_indices_, 0) : -1;
  const int sparse_normal_view = sparse_ ? add_view(sparse_normal_indices_, 0) : -1;
  const int times = add_accessor(add_view(times_, 0), kFloat, TINYGLTF_TYPE_SCALAR, static_cast<std::size_t>(frames));
  model.accessors[times].minValues = {0.0};
  model.accessors[times].maxValues = {double{last_time_}};
  const int weights = add_accessor(-1, kFloat, TINYGLTF_TYPE_SCALAR,
                                   static_cast<std::size_t>(frames) * static_cast<std::size_t>(frames));
  {
    auto& sparse = model.accessors[weights].sparse;
    sparse.isSparse = true;
    sparse.count = frames;
    sparse.indices.bufferView = add_view(weight_indices_, 0);
    sparse.indices.byteOffset = 0;
    sparse.indices.componentType = kUint;
    sparse.values.bufferView = add_view(weights_, 0);
    sparse.values.byteOffset = 0;
  }

  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = position;
  primitive.attributes["NORMAL"] = normal;
  primitive.indices = indices;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Value::Array names;
  for (int k = 0; k < frames; ++k) {
    const Block& block = frame_blocks_[static_cast<std::size_t>(k)];
    int accessor = 0;
    if (sparse_) {
      accessor = add_accessor(-1, kFloat, TINYGLTF_TYPE_VEC3, n);
      auto& sparse = model.accessors[accessor].sparse;
      sparse.isSparse = true;
      sparse.count = static_cast<int>(targets_.size());
      sparse.indices.bufferView = sparse_view;
      sparse.indices.byteOffset = 0;
      sparse.indices.componentType = kUint;
      sparse.values.bufferView = add_view(block, 0);
      sparse.values.byteOffset = 0;
    } else {
      accessor = add_accessor(add_view(block, TINYGLTF_TARGET_ARRAY_BUFFER), kFloat, TINYGLTF_TYPE_VEC3, n);
    }
    model.accessors[accessor].minValues = to_doubles(frame_min_[static_cast<std::size_t>(k)]);
    model.accessors[accessor].maxValues = to_doubles(frame_max_[static_cast<std::size_t>(k)]);
    const Block& normal_block = normal_blocks_[static_cast<std::size_t>(k)];
    int normal_accessor = 0;
    if (sparse_) {
      normal_accessor = add_accessor(-1, kFloat, TINYGLTF_TYPE_VEC3, n);
      auto& sparse = model.accessors[normal_accessor].sparse;
      sparse.isSparse = true;
      sparse.count = static_cast<int>(normal_targets_.size());
      sparse.indices.bufferView = sparse_normal_view;
      sparse.indices.byteOffset = 0;
      sparse.indices.componentType = kUint;
      sparse.values.bufferView = add_view(normal_block, 0);
      sparse.values.byteOffset = 0;
    } else {
      normal_accessor =
          add_accessor(add_view(normal_block, TINYGLTF_TARGET_ARRAY_BUFFER), kFloat, TINYGLTF_TYPE_VEC3, n);
    }
    primitive.targets.push_back({{"POSITION", accessor}, {"NORMAL", normal_accessor}});
    std::string name = obj_sequence_path("frame", k, frames).stem().string();  // "frame_0000"
    names.emplace_back(std::move(name));
  }

  tinygltf::Mesh gltf_mesh;
  gltf_mesh.name = info().name;
  gltf_mesh.primitives.push_back(std::move(primitive));
  gltf_mesh.weights.assign(static_cast<std::size_t>(frames), 0.0);
  tinygltf::Value::Object extras;
  extras["targetNames"] = tinygltf::Value(std::move(names));
  gltf_mesh.extras = tinygltf::Value(std::move(extras));
  model.meshes.push_back(std::move(gltf_mesh));

  tinygltf::Node node;
  node.name = info().name;
  node.mesh = 0;
  if (info().body_moves) {  // frame 0's pose, for a viewer that does not play the animation
    node.translation = {body_keys_.translations[0], body_keys_.translations[1], body_keys_.translations[2]};
    node.rotation = {body_keys_.rotations[0], body_keys_.rotations[1], body_keys_.rotations[2],
                     body_keys_.rotations[3]};
  }
  model.nodes.push_back(std::move(node));
  tinygltf::Scene scene;
  scene.nodes = {0};
  model.scenes.push_back(std::move(scene));
  model.defaultScene = 0;

  tinygltf::Animation animation;
  animation.name = "bake";
  tinygltf::AnimationSampler sampler;
  sampler.input = times;
  sampler.output = weights;
  sampler.interpolation = "LINEAR";
  animation.samplers.push_back(std::move(sampler));
  tinygltf::AnimationChannel channel;
  channel.sampler = 0;
  channel.target_node = 0;
  channel.target_path = "weights";
  animation.channels.push_back(std::move(channel));
  if (info().body_moves) {
    // The body: translation and rotation of the same node, keyed at the same times.
    const int translations = add_accessor(add_view(body_translation_block_, 0), kFloat, TINYGLTF_TYPE_VEC3,
                                          static_cast<std::size_t>(frames));
    const int rotations =
        add_accessor(add_view(body_rotation_block_, 0), kFloat, TINYGLTF_TYPE_VEC4, static_cast<std::size_t>(frames));
    for (const auto& [accessor, path] : {std::pair{translations, "translation"}, std::pair{rotations, "rotation"}}) {
      tinygltf::AnimationSampler body_sampler;
      body_sampler.input = times;
      body_sampler.output = accessor;
      body_sampler.interpolation = "LINEAR";
      animation.samplers.push_back(std::move(body_sampler));
      tinygltf::AnimationChannel body_channel;
      body_channel.sampler = static_cast<int>(animation.samplers.size() - 1);
      body_channel.target_node = 0;
      body_channel.target_path = path;
      animation.channels.push_back(std::move(body_channel));
    }
  }
  model.animations.push_back(std::move(animation));
  return model;
}

void GltfWriter::complete(io::Publication& outputs) {
  if (passthrough_) {
    write_glb(outputs, passthrough_->finish(append_bin_));
    return;
  }
  // tinygltf serializes everything but the buffer (it would want the bytes in memory); the one
  // buffer, the GLB's BIN chunk, is added here with its length.
  if (info().body_moves) {
    body_translation_block_ =
        append_block(body_keys_.translations.data(), body_keys_.translations.size() * sizeof(float));
    body_rotation_block_ = append_block(body_keys_.rotations.data(), body_keys_.rotations.size() * sizeof(float));
  }
  const tinygltf::Model model = build_model();
  std::ostringstream stream;
  tinygltf::TinyGLTF gltf;
  if (!gltf.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/false, /*writeBinary=*/false)) {
    fail(ErrorCategory::internal, out().string() + ": tinygltf could not serialize the model");
  }
  write_glb(outputs, nlohmann::json::parse(stream.str()));
}

// The GLB: header, the JSON chunk (with "buffers": the one BIN buffer) and the scratch file's bytes.
void GltfWriter::write_glb(io::Publication& outputs, nlohmann::json json) {
  const std::uint64_t bin_length = scratch_->size();  // a multiple of 4: every element is 4 bytes
  json["buffers"] = nlohmann::json::array({{{"byteLength", bin_length}}});
  std::string text = json.dump();
  text.append((4 - text.size() % 4) % 4, ' ');

  const std::uint64_t total = 12 + 8 + text.size() + 8 + bin_length;
  if (total > kGlbMaxBytes) {
    fail(ErrorCategory::unsupported,
         out().string() + ": the bake needs " + std::to_string(total) + " bytes, over the 4 GiB a .glb can hold");
  }
  auto u32 = [](std::uint64_t v) { return static_cast<std::uint32_t>(v); };
  const std::uint32_t header[5] = {0x46546C67u /* "glTF" */, 2, u32(total), u32(text.size()), 0x4E4F534Au /* "JSON" */};
  const std::uint32_t bin_header[2] = {u32(bin_length), 0x004E4942u /* "BIN\0" */};
  final_ = std::make_unique<io::TempFile>(out());
  final_->write(header, sizeof header);
  final_->write(text);
  final_->write(bin_header, sizeof bin_header);
  scratch_->copy_to(*final_);
  final_->seal();
  outputs.add(std::move(final_));
  scratch_.reset();
}

}  // namespace

std::unique_ptr<BakeWriter> make_gltf_bake_writer(const std::filesystem::path& out) {
  return std::make_unique<GltfWriter>(out);
}

}  // namespace sweep::assets
