#include "sweep/assets/gltf_skin.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>

#include "sweep/assets/file_error_detail.h"
#include "sweep/assets/gltf_document.h"
#include "sweep/core/error.h"
#include "sweep/core/text.h"

namespace sweep::assets {
namespace {

using detail::GltfDocument;
using Json = nlohmann::json;
using Mat4 = Eigen::Matrix4d;

using detail::refuse;

// Any accessor of `components` numbers an element, as doubles: floats as they are, integers as
// they are, or mapped to [0, 1] / [-1, 1] when "normalized" (glTF 2.0, "Accessor data types").
std::optional<std::vector<double>> read_numbers(const GltfDocument& file, const Json& index, int components) {
  const Json* accessor = detail::gltf_element(file.json, "accessors", index);
  if (accessor == nullptr || accessor->contains("sparse")) return std::nullopt;
  const auto type_member = accessor->find("type");
  const std::string type =
      type_member != accessor->end() && type_member->is_string() ? type_member->get<std::string>() : "";
  const int want = type == "SCALAR" ? 1
                   : type == "VEC2" ? 2
                   : type == "VEC3" ? 3
                   : type == "VEC4" ? 4
                   : type == "MAT4" ? 16
                                    : 0;
  if (want != components) return std::nullopt;
  const std::uint64_t ct = detail::gltf_unsigned(*accessor, "componentType", 0);
  const int size = ct == 5120 || ct == 5121 ? 1 : ct == 5122 || ct == 5123 ? 2 : ct == 5125 || ct == 5126 ? 4 : 0;
  if (size == 0) return std::nullopt;
  const auto normalized_member = accessor->find("normalized");
  const bool normalized =
      normalized_member != accessor->end() && normalized_member->is_boolean() && normalized_member->get<bool>();
  const Json* view = accessor->contains("bufferView")
                         ? detail::gltf_element(file.json, "bufferViews", (*accessor)["bufferView"])
                         : nullptr;
  if (view == nullptr) return std::nullopt;
  const std::uint64_t b = detail::gltf_unsigned(*view, "buffer", file.buffers.size());
  if (b >= file.buffers.size() || !file.buffers[b]) return std::nullopt;
  const std::string& data = *file.buffers[b];
  const std::uint64_t element = static_cast<std::uint64_t>(size) * components;
  const std::uint64_t stride = detail::gltf_unsigned(*view, "byteStride", element);
  const std::uint64_t view_begin = detail::gltf_unsigned(*view, "byteOffset", 0);
  const std::uint64_t offset = detail::gltf_unsigned(*accessor, "byteOffset", 0);
  const std::uint64_t count = detail::gltf_unsigned(*accessor, "count", 0);
  if (!detail::gltf_fits(view_begin, detail::gltf_unsigned(*view, "byteLength", 0), offset, count, element, stride,
                         data.size())) {
    return std::nullopt;
  }
  const std::uint64_t begin = view_begin + offset;
  std::vector<double> out(count * static_cast<std::uint64_t>(components));
  for (std::uint64_t i = 0; i < count; ++i) {
    const char* at = data.data() + begin + i * stride;
    for (int c = 0; c < components; ++c, at += size) {
      double v = 0;
      switch (ct) {
        case 5120: {
          std::int8_t x;
          std::memcpy(&x, at, 1);
          v = normalized ? std::max(x / 127.0, -1.0) : x;
          break;
        }
        case 5121: {
          std::uint8_t x;
          std::memcpy(&x, at, 1);
          v = normalized ? x / 255.0 : x;
          break;
        }
        case 5122: {
          std::int16_t x;
          std::memcpy(&x, at, 2);
          v = normalized ? std::max(x / 32767.0, -1.0) : x;
          break;
        }
        case 5123: {
          std::uint16_t x;
          std::memcpy(&x, at, 2);
          v = normalized ? x / 65535.0 : x;
          break;
        }
        case 5125: {
          std::uint32_t x;
          std::memcpy(&x, at, 4);
          v = x;
          break;
        }
        default: {
          float x;
          std::memcpy(&x, at, 4);
          v = x;
          break;
        }  // little-endian, as glTF is
      }
      out[i * components + c] = v;
    }
  }
  return out;
}

Mat4 local_matrix(const Vec3& t, const Quat& r, const Vec3& s) {
  Eigen::Affine3d a = Eigen::Affine3d::Identity();
  a.translate(t);
  a.rotate(r);
  a.scale(s);
  return a.matrix();
}

double hermite(double v0, double b0, double v1, double a1, double s, double dt) {
  const double s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * v0 + (s3 - 2 * s2 + s) * dt * b0 + (-2 * s3 + 3 * s2) * v1 + (s3 - s2) * dt * a1;
}

}  // namespace

int SkinModel::find_node(const std::string& name) const {
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].name == name) return static_cast<int>(i);
  return -1;
}
int SkinModel::find_clip(const std::string& name) const {
  for (std::size_t i = 0; i < clips.size(); ++i)
    if (clips[i].name == name) return static_cast<int>(i);
  return -1;
}
int SkinModel::joint_of_node(int node) const {
  const auto it = std::find(joints.begin(), joints.end(), node);
  return it == joints.end() ? -1 : static_cast<int>(it - joints.begin());
}
std::vector<std::string> SkinModel::moved_nodes(int c) const {
  std::vector<int> moved;
  for (const ClipChannel& ch : clips[c].channels) moved.push_back(ch.node);
  std::sort(moved.begin(), moved.end());
  moved.erase(std::unique(moved.begin(), moved.end()), moved.end());
  std::vector<std::string> names;
  for (int n : moved) names.push_back("'" + nodes[n].name + "'");
  return names;
}
std::string SkinModel::clip_names() const {
  std::string out;
  for (const SkinClip& c : clips) out += (out.empty() ? "'" : ", '") + c.name + "'";
  return out.empty() ? "none" : out;
}

Eigen::Vector4d channel_value(const ClipChannel& c, double t) {
  const int w = c.width();
  const bool cubic = c.interpolation == ChannelInterpolation::cubic;
  const int group = cubic ? 3 * w : w;
  auto value = [&](std::size_t k, int part) {  // part: 0 in-tangent, 1 value, 2 out-tangent (cubic)
    Eigen::Vector4d v(0, 0, 0, 0);
    const std::size_t at = k * group + (cubic ? part * w : 0);
    for (int i = 0; i < w; ++i) v[i] = c.values[at + i];
    return v;
  };
  auto finish = [&](Eigen::Vector4d v) {
    if (c.path == ChannelPath::rotation) v.normalize();
    return v;
  };
  const std::size_t n = c.times.size();
  if (t <= c.times.front()) return finish(value(0, 1));
  if (t >= c.times.back()) return finish(value(n - 1, 1));
  const std::size_t k = std::upper_bound(c.times.begin(), c.times.end(), t) - c.times.begin() - 1;
  const double dt = c.times[k + 1] - c.times[k];
  const double s = (t - c.times[k]) / dt;
  switch (c.interpolation) {
    case ChannelInterpolation::step:
      return finish(value(k, 1));
    case ChannelInterpolation::cubic: {
      Eigen::Vector4d v(0, 0, 0, 0);
      const Eigen::Vector4d v0 = value(k, 1), b0 = value(k, 2), v1 = value(k + 1, 1), a1 = value(k + 1, 0);
      for (int i = 0; i < w; ++i) v[i] = hermite(v0[i], b0[i], v1[i], a1[i], s, dt);
      return finish(v);
    }
    case ChannelInterpolation::linear:
      break;
  }
  const Eigen::Vector4d a = value(k, 1), b = value(k + 1, 1);
  if (c.path != ChannelPath::rotation) return a + s * (b - a);
  const Quat qa = Quat(a[3], a[0], a[1], a[2]).normalized(), qb = Quat(b[3], b[0], b[1], b[2]).normalized();
  const Quat q = qa.slerp(s, qb);  // Eigen's slerp takes the shortest arc, as glTF's LINEAR rotation
  return Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
}

std::vector<Mat4> world_transforms(const SkinModel& model, int clip, double t) {
  const std::size_t n = model.nodes.size();
  std::vector<Vec3> tr(n), sc(n);
  std::vector<Quat> ro(n);
  std::vector<bool> animated(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    tr[i] = model.nodes[i].translation;
    ro[i] = model.nodes[i].rotation;
    sc[i] = model.nodes[i].scale;
  }
  if (clip >= 0) {
    for (const ClipChannel& c : model.clips[clip].channels) {
      const Eigen::Vector4d v = channel_value(c, t);
      animated[c.node] = true;
      if (c.path == ChannelPath::translation) tr[c.node] = v.head<3>();
      if (c.path == ChannelPath::scale) sc[c.node] = v.head<3>();
      if (c.path == ChannelPath::rotation) ro[c.node] = Quat(v[3], v[0], v[1], v[2]);
    }
  }
  std::vector<Mat4> world(n);
  std::vector<char> done(n, 0);
  std::function<const Mat4&(int)> of = [&](int i) -> const Mat4& {
    if (!done[i]) {
      const SkinNode& node = model.nodes[i];
      // A node given by "matrix" is never animated (glTF forbids it), so its matrix stands.
      const Mat4 local = node.matrix && !animated[i] ? *node.matrix : local_matrix(tr[i], ro[i], sc[i]);
      world[i] = node.parent >= 0 ? Mat4(of(node.parent) * local) : local;
      done[i] = 1;
    }
    return world[i];
  };
  for (std::size_t i = 0; i < n; ++i) of(static_cast<int>(i));
  return world;
}

std::vector<Mat4> joint_matrices(const SkinModel& model, const std::vector<Mat4>& world) {
  std::vector<Mat4> out(model.joints.size());
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = world[model.joints[k]] * model.inverse_bind[k];
  return out;
}

Vec3 skin_vertex(const SkinModel& model, const std::vector<Mat4>& joint_matrix, std::size_t v) {
  const Eigen::Vector4d p(model.bind_positions[v].x(), model.bind_positions[v].y(), model.bind_positions[v].z(), 1.0);
  Eigen::Vector4d out = Eigen::Vector4d::Zero();
  for (int i = 0; i < 4; ++i) {
    const double w = model.vertex_weights[v][i];
    if (w != 0) out += w * (joint_matrix[model.vertex_joints[v][i]] * p);
  }
  return out.head<3>();
}

std::optional<SkinModel> read_gltf_skin(const std::filesystem::path& gltf, std::span<const Vec3> read_positions,
                                        const Eigen::Affine3d& to_world) {
  const std::string ext = lower_extension(gltf);
  if (ext != "gltf" && ext != "glb") return std::nullopt;
  const GltfDocument file = detail::read_gltf_document(gltf);
  const Json& doc = file.json;
  if (!doc.is_object()) return std::nullopt;
  const Json nodes = doc.value("nodes", Json::array());
  if (!nodes.is_array()) return std::nullopt;
  SkinModel model;
  model.nodes.resize(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const Json& node = nodes[i];
    SkinNode& out = model.nodes[i];
    if (!node.is_object()) continue;
    out.name =
        detail::gltf_string(node, "name", "node " + std::to_string(i), gltf.string() + ": /nodes/" + std::to_string(i));
    auto numbers = [&](const char* key, std::size_t n) -> std::optional<std::vector<double>> {
      const auto it = node.find(key);
      if (it == node.end()) return std::nullopt;
      if (!it->is_array() || it->size() != n)
        refuse(gltf, "node '" + out.name + "': \"" + key + "\" must be " + std::to_string(n) + " numbers");
      std::vector<double> v;
      for (const Json& x : *it) {
        if (!x.is_number() || !std::isfinite(x.get<double>()))
          refuse(gltf, "node '" + out.name + "': \"" + key + "\" must be finite numbers");
        v.push_back(x.get<double>());
      }
      return v;
    };
    if (const auto m = numbers("matrix", 16)) {
      Mat4 matrix;
      for (int k = 0; k < 16; ++k) matrix(k % 4, k / 4) = (*m)[k];  // column-major
      out.matrix = matrix;
    }
    if (const auto t = numbers("translation", 3)) out.translation = Vec3((*t)[0], (*t)[1], (*t)[2]);
    if (const auto r = numbers("rotation", 4)) out.rotation = Quat((*r)[3], (*r)[0], (*r)[1], (*r)[2]).normalized();
    if (const auto s = numbers("scale", 3)) out.scale = Vec3((*s)[0], (*s)[1], (*s)[2]);
    for (const Json& c : node.value("children", Json::array())) {
      if (c.is_number_unsigned() && c.get<std::size_t>() < nodes.size())
        model.nodes[c.get<std::size_t>()].parent = static_cast<int>(i);
    }
  }
  for (std::size_t i = 0; i < nodes.size(); ++i) {  // a cycle would make world_transforms recurse forever
    std::size_t steps = 0;
    for (int p = model.nodes[i].parent; p >= 0; p = model.nodes[p].parent) {
      if (++steps > nodes.size()) refuse(gltf, "its node tree has a cycle above '" + model.nodes[i].name + "'");
    }
  }
  // The skinned node whose mesh's primitives are the vertices read.
  const Json meshes = doc.value("meshes", Json::array());
  std::vector<int> skinned;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].is_object() && nodes[i].contains("skin") && nodes[i].contains("mesh"))
      skinned.push_back(static_cast<int>(i));
  }
  if (skinned.empty()) return std::nullopt;
  for (const int node : skinned) {
    const Json* mesh = detail::gltf_element(doc, "meshes", nodes[node]["mesh"]);
    if (mesh == nullptr) continue;
    std::vector<Vec3> positions;
    std::vector<std::array<std::uint16_t, 4>> vj;
    std::vector<std::array<double, 4>> vw;
    bool readable = true;
    for (const Json& prim : mesh->value("primitives", Json::array())) {
      const Json attributes = prim.is_object() && prim.contains("attributes") && prim["attributes"].is_object()
                                  ? prim["attributes"]
                                  : Json::object();
      const auto p = read_numbers(file, attributes.value("POSITION", Json()), 3);
      if (!p) {
        readable = false;
        break;
      }
      const std::size_t count = p->size() / 3;
      for (std::size_t v = 0; v < count; ++v) positions.emplace_back((*p)[3 * v], (*p)[3 * v + 1], (*p)[3 * v + 2]);
      const std::string mesh_name = detail::gltf_string(*mesh, "name", "mesh " + nodes[node]["mesh"].dump(),
                                                        gltf.string() + ": /meshes/" + nodes[node]["mesh"].dump());
      if (attributes.contains("JOINTS_1") || attributes.contains("WEIGHTS_1")) {
        refuse(gltf, "mesh '" + mesh_name +
                         "' has more than 4 joint influences a vertex (JOINTS_1/WEIGHTS_1); "
                         "limit the influences to 4 in the exporter (Blender: \"Limit to 4\" under skinning)");
      }
      const auto j = read_numbers(file, attributes.value("JOINTS_0", Json()), 4);
      const auto w = read_numbers(file, attributes.value("WEIGHTS_0", Json()), 4);
      if (!j || !w || j->size() != 4 * count || w->size() != 4 * count) {
        refuse(gltf, "mesh '" + mesh_name +
                         "' is skinned but its JOINTS_0 and WEIGHTS_0 cannot be read as 4 numbers a vertex");
      }
      for (std::size_t v = 0; v < count; ++v) {
        std::array<std::uint16_t, 4> joints{};
        std::array<double, 4> weights{};
        double sum = 0;
        for (int k = 0; k < 4; ++k) {
          const double jv = (*j)[4 * v + k], wv = (*w)[4 * v + k];
          if (!(wv >= 0) || !std::isfinite(wv))
            refuse(gltf, "mesh '" + mesh_name + "', vertex " + std::to_string(positions.size() - count + v) +
                             ": a negative or non-finite skin weight");
          // A joint is an index (glTF stores it as an unsigned byte or short): a float or signed
          // accessor's negative, fractional or non-finite value names no joint.
          if (!(jv >= 0 && jv <= 65535 && jv == std::floor(jv))) {
            refuse(gltf, "mesh '" + mesh_name + "', vertex " + std::to_string(positions.size() - count + v) +
                             ": joint " + format_number(jv) +
                             " in JOINTS_0 is not a joint index (a whole number from 0)");
          }
          joints[k] = static_cast<std::uint16_t>(jv);
          weights[k] = wv;
          sum += wv;
        }
        if (!(sum > 0))
          refuse(gltf, "mesh '" + mesh_name + "', vertex " + std::to_string(positions.size() - count + v) +
                           ": its skin weights are all 0");
        // glTF asks for weights summing to 1; exporters store them quantized: normalize.
        for (double& x : weights) x /= sum;
        vj.push_back(joints);
        vw.push_back(weights);
      }
    }
    if (!readable || positions.size() != read_positions.size()) continue;
    // The same vertices: POSITION placed by the node's transform is what the importer read.
    double size = 0, worst = 0;
    for (std::size_t v = 0; v < positions.size(); ++v) {
      size = std::max(size, read_positions[v].cwiseAbs().maxCoeff());
      worst = std::max(worst, (to_world * positions[v] - read_positions[v]).cwiseAbs().maxCoeff());
    }
    if (!(worst <= 1e-6 * std::max(size, 1e-30))) continue;
    model.mesh_node = node;
    model.bind_positions = std::move(positions);
    model.vertex_joints = std::move(vj);
    model.vertex_weights = std::move(vw);
    break;
  }
  if (model.mesh_node < 0) {
    fail(ErrorCategory::unsupported, gltf.string() + ": node '" + model.nodes[skinned.front()].name +
                                         "' is skinned, but its mesh is not the mesh read (another mesh of the file, "
                                         "or several): give the rig the skinned mesh's node as its mesh_name");
  }
  const std::string where = "skin of node '" + model.nodes[model.mesh_node].name + "'";
  const Json* skin = detail::gltf_element(doc, "skins", nodes[model.mesh_node]["skin"]);
  if (skin == nullptr || !skin->contains("joints") || !(*skin)["joints"].is_array())
    refuse(gltf, where + ": no joints");
  for (const Json& j : (*skin)["joints"]) {
    if (!j.is_number_unsigned() || j.get<std::size_t>() >= nodes.size())
      refuse(gltf, where + ": a joint is not a node");
    model.joints.push_back(j.get<int>());
  }
  if (skin->contains("inverseBindMatrices")) {
    const auto m = read_numbers(file, (*skin)["inverseBindMatrices"], 16);
    if (!m || m->size() != 16 * model.joints.size())
      refuse(gltf, where + ": its inverseBindMatrices cannot be read as one MAT4 a joint");
    for (std::size_t k = 0; k < model.joints.size(); ++k) {
      Mat4 ibm;
      for (int e = 0; e < 16; ++e) ibm(e % 4, e / 4) = (*m)[16 * k + e];
      const double det = ibm.topLeftCorner<3, 3>().determinant();
      if (!ibm.allFinite() || !(std::abs(det) > 1e-12) ||
          (ibm.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6) {
        refuse(gltf, where + ": the inverse bind matrix of joint '" + model.nodes[model.joints[k]].name +
                         "' is not an invertible affine transform (determinant " + format_number(det) + ")");
      }
      model.inverse_bind.push_back(ibm);
    }
  } else {
    model.inverse_bind.assign(model.joints.size(), Mat4::Identity());
  }
  for (std::size_t v = 0; v < model.vertex_joints.size(); ++v) {
    for (int k = 0; k < 4; ++k) {
      if (model.vertex_weights[v][k] > 0 && model.vertex_joints[v][k] >= model.joints.size()) {
        refuse(gltf, where + ": vertex " + std::to_string(v) + " names joint " +
                         std::to_string(model.vertex_joints[v][k]) + ", but the skin has " +
                         std::to_string(model.joints.size()));
      }
    }
  }
  // The clips.
  const Json animations = doc.value("animations", Json::array());
  for (std::size_t a = 0; animations.is_array() && a < animations.size(); ++a) {
    const Json& anim = animations[a];
    if (!anim.is_object()) continue;
    SkinClip clip;
    const std::string at = gltf.string() + ": /animations/" + std::to_string(a);
    clip.name = detail::gltf_string(anim, "name", "animation " + std::to_string(a), at);
    const Json channels = anim.value("channels", Json::array());
    for (std::size_t ci = 0; channels.is_array() && ci < channels.size(); ++ci) {
      const Json& ch = channels[ci];
      // value() throws on anything but an object: a target that is not one targets nothing.
      const Json target =
          ch.is_object() && ch.contains("target") && ch["target"].is_object() ? ch["target"] : Json::object();
      const std::string path =
          detail::gltf_string(target, "path", "", at + "/channels/" + std::to_string(ci) + "/target");
      if (path != "translation" && path != "rotation" && path != "scale") continue;  // morph weights, pointers
      const Json tn = target.value("node", Json());
      if (!tn.is_number_unsigned() || tn.get<std::size_t>() >= nodes.size()) continue;
      ClipChannel c;
      c.node = tn.get<int>();
      c.path = path == "translation" ? ChannelPath::translation
               : path == "rotation"  ? ChannelPath::rotation
                                     : ChannelPath::scale;
      const std::string what =
          "animation '" + clip.name + "': the " + path + " of node '" + model.nodes[c.node].name + "'";
      const Json* sampler = ch.contains("sampler") ? detail::gltf_element(anim, "samplers", ch["sampler"]) : nullptr;
      if (sampler == nullptr) refuse(gltf, what + " has no sampler");
      const std::string interpolation =
          detail::gltf_string(*sampler, "interpolation", "LINEAR", at + "/samplers/" + ch["sampler"].dump());
      if (interpolation == "STEP")
        c.interpolation = ChannelInterpolation::step;
      else if (interpolation == "CUBICSPLINE")
        c.interpolation = ChannelInterpolation::cubic;
      else if (interpolation != "LINEAR")
        refuse(gltf, what + ": unknown interpolation '" + interpolation + "'");
      const auto input = read_numbers(file, sampler->value("input", Json()), 1);
      const auto output = read_numbers(file, sampler->value("output", Json()), c.width());
      const std::size_t per_key =
          static_cast<std::size_t>(c.width()) * (c.interpolation == ChannelInterpolation::cubic ? 3 : 1);
      if (!input || !output || input->empty() || output->size() != input->size() * per_key) {
        refuse(gltf, what + ": its keys cannot be read (times and values of matching count expected)");
      }
      c.times = *input;
      c.values = *output;
      for (std::size_t k = 0; k < c.times.size(); ++k) {
        if (!std::isfinite(c.times[k]) || c.times[k] < 0 || (k > 0 && !(c.times[k] > c.times[k - 1])))
          refuse(gltf, what + ": key times must be finite, at least 0 and increasing");
      }
      for (double v : c.values)
        if (!std::isfinite(v)) refuse(gltf, what + ": a value is not finite");
      clip.start = clip.channels.empty() ? c.times.front() : std::min(clip.start, c.times.front());
      clip.end = clip.channels.empty() ? c.times.back() : std::max(clip.end, c.times.back());
      clip.channels.push_back(std::move(c));
    }
    model.clips.push_back(std::move(clip));
  }
  return model;
}

}  // namespace sweep::assets
