#include "sweep/assets/gltf_motion.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <vector>

#include "sweep/assets/file_error_detail.h"
#include "sweep/assets/gltf_document.h"
#include "sweep/core/error.h"
#include "sweep/core/limits.h"
#include "sweep/core/text.h"

namespace sweep::assets {
namespace {

using detail::GltfDocument;
using Json = nlohmann::json;
using Affine = Eigen::Affine3d;

using detail::refuse;

// A node's rest transform: its "matrix", or its translation, rotation and scale.
Affine rest_transform(const Json& node) {
  Affine a = Affine::Identity();
  if (const auto m = node.find("matrix"); m != node.end() && m->is_array() && m->size() == 16) {
    Eigen::Matrix4d matrix;
    for (int k = 0; k < 16; ++k)
      matrix(k % 4, k / 4) = (*m)[k].is_number() ? (*m)[k].get<double>() : 0.0;  // column-major
    a.matrix() = matrix;
    return a;
  }
  auto vec = [&](const char* key, int n, std::array<double, 4> fallback) {
    if (const auto v = node.find(key); v != node.end() && v->is_array() && static_cast<int>(v->size()) == n) {
      for (int i = 0; i < n; ++i) fallback[i] = (*v)[i].is_number() ? (*v)[i].get<double>() : fallback[i];
    }
    return fallback;
  };
  const auto t = vec("translation", 3, {0, 0, 0, 0});
  const auto r = vec("rotation", 4, {0, 0, 0, 1});
  const auto s = vec("scale", 3, {1, 1, 1, 0});
  a.translate(Vec3(t[0], t[1], t[2]));
  a.rotate(Quat(r[3], r[0], r[1], r[2]).normalized());
  a.scale(Vec3(s[0], s[1], s[2]));
  return a;
}

// One channel of the node: its sampler's times and values (3 or 4 floats a key).
struct Channel {
  std::vector<double> times;
  std::vector<float> values;
  int width = 0;
};

// Linear interpolation of a channel at t (held before the first key and after the last).
Vec3 translation_at(const Channel& c, double t) {
  auto at = [&](std::size_t k) { return Vec3(c.values[3 * k], c.values[3 * k + 1], c.values[3 * k + 2]); };
  if (t <= c.times.front()) return at(0);
  if (t >= c.times.back()) return at(c.times.size() - 1);
  const std::size_t k = std::upper_bound(c.times.begin(), c.times.end(), t) - c.times.begin() - 1;
  const double u = (t - c.times[k]) / (c.times[k + 1] - c.times[k]);
  return at(k) + u * (at(k + 1) - at(k));
}
Quat rotation_at(const Channel& c, double t) {
  auto at = [&](std::size_t k) {
    return Quat(c.values[4 * k + 3], c.values[4 * k], c.values[4 * k + 1], c.values[4 * k + 2]).normalized();
  };
  if (t <= c.times.front()) return at(0);
  if (t >= c.times.back()) return at(c.times.size() - 1);
  const std::size_t k = std::upper_bound(c.times.begin(), c.times.end(), t) - c.times.begin() - 1;
  const double u = (t - c.times[k]) / (c.times[k + 1] - c.times[k]);
  return at(k).slerp(u, at(k + 1));  // the shortest arc, as glTF's LINEAR rotation
}

}  // namespace

sim::BodyPath read_gltf_body_path(const std::filesystem::path& gltf, const std::string& node_name,
                                  const std::string& animation_name) {
  if (const std::string ext = lower_extension(gltf); ext != "gltf" && ext != "glb") {
    refuse(gltf, "the scene's body follows node '" + node_name +
                     "' of a glTF animation, but the mesh is not a glTF file (.gltf or .glb)");
  }
  const GltfDocument file = detail::read_gltf_document(gltf);
  const Json& doc = file.json;
  if (!doc.is_object()) refuse(gltf, "not a glTF document (its JSON could not be read)");
  // The node, and its parent chain (glTF nodes name their children).
  const Json nodes = doc.value("nodes", Json::array());
  std::optional<std::size_t> node;
  std::vector<std::optional<std::size_t>> parent(nodes.is_array() ? nodes.size() : 0);
  for (std::size_t i = 0; i < parent.size(); ++i) {
    if (!nodes[i].is_object()) continue;
    if (detail::gltf_string(nodes[i], "name", "", gltf.string() + ": /nodes/" + std::to_string(i)) == node_name &&
        !node)
      node = i;
    for (const Json& c : nodes[i].value("children", Json::array())) {
      if (c.is_number_unsigned() && c.get<std::size_t>() < parent.size()) parent[c.get<std::size_t>()] = i;
    }
  }
  if (!node) refuse(gltf, "no node is named '" + node_name + "'");
  std::set<std::size_t> ancestors;
  Affine P = Affine::Identity();
  for (auto p = parent[*node]; p; p = parent[*p]) {
    if (!ancestors.insert(*p).second) refuse(gltf, "its node tree has a cycle above '" + node_name + "'");
    P = rest_transform(nodes[*p]) * P;
  }
  // The animation: the named one, or the first that moves the node.
  const Json animations = doc.value("animations", Json::array());
  Channel channels[2];  // translation, rotation
  std::string used;
  for (std::size_t a = 0; animations.is_array() && a < animations.size() && used.empty(); ++a) {
    const Json& anim = animations[a];
    if (!anim.is_object()) continue;
    const std::string at = gltf.string() + ": /animations/" + std::to_string(a);
    const std::string name = detail::gltf_string(anim, "name", "animation " + std::to_string(a), at);
    if (!animation_name.empty() && name != animation_name) continue;
    bool moves = false;
    const Json anim_channels = anim.value("channels", Json::array());
    for (std::size_t ci = 0; anim_channels.is_array() && ci < anim_channels.size(); ++ci) {
      const Json& ch = anim_channels[ci];
      // value() throws on anything but an object: a target that is not one targets nothing.
      const Json target =
          ch.is_object() && ch.contains("target") && ch["target"].is_object() ? ch["target"] : Json::object();
      const Json target_node = target.value("node", Json());
      if (!target_node.is_number_unsigned()) continue;
      const std::size_t n = target_node.get<std::size_t>();
      const std::string path =
          detail::gltf_string(target, "path", "", at + "/channels/" + std::to_string(ci) + "/target");
      if (ancestors.count(n) && path != "weights") {
        refuse(gltf, "animation '" + name + "' moves node '" +
                         detail::gltf_string(nodes[n], "name", std::to_string(n),
                                             gltf.string() + ": /nodes/" + std::to_string(n)) +
                         "', above '" + node_name +
                         "': only the body node's own animation is read; "
                         "animate '" +
                         node_name + "' itself");
      }
      if (n != *node || path == "weights") continue;
      if (path == "scale")
        refuse(gltf, "animation '" + name + "' scales node '" + node_name +
                         "': a body moves and turns, it does not change size");
      if (path != "translation" && path != "rotation") continue;
      const Json* sampler = ch.contains("sampler") ? detail::gltf_element(anim, "samplers", ch["sampler"]) : nullptr;
      if (sampler == nullptr)
        refuse(gltf, "animation '" + name + "': a channel of node '" + node_name + "' has no sampler");
      const std::string interpolation =
          detail::gltf_string(*sampler, "interpolation", "LINEAR", at + "/samplers/" + ch["sampler"].dump());
      if (interpolation != "LINEAR") {
        refuse(gltf, "animation '" + name + "' moves node '" + node_name + "' with " + interpolation +
                         " interpolation; only LINEAR is read (export the animation baked, with linear keys)");
      }
      const int width = path == "translation" ? 3 : 4;
      const auto input = detail::read_float_accessor(file, sampler->value("input", Json()), 1);
      const auto output = detail::read_float_accessor(file, sampler->value("output", Json()), width);
      if (!input || !output || input->empty() || output->size() != input->size() * width) {
        refuse(gltf, "animation '" + name + "': the " + path + " keys of node '" + node_name +
                         "' cannot be read (float times and values of matching count expected)");
      }
      Channel& c = channels[width == 3 ? 0 : 1];
      c.width = width;
      c.times.assign(input->begin(), input->end());
      c.values = *output;
      for (std::size_t k = 0; k < c.times.size(); ++k) {
        if (!std::isfinite(c.times[k]) || c.times[k] < 0 || (k > 0 && !(c.times[k] > c.times[k - 1]))) {
          refuse(gltf, "animation '" + name + "': the " + path + " key times of node '" + node_name +
                           "' must be finite, at least 0 and increasing");
        }
      }
      for (float v : c.values) {
        if (!std::isfinite(v))
          refuse(gltf, "animation '" + name + "': a " + path + " value of node '" + node_name + "' is not finite");
      }
      // A translation past the limit of any length (core/limits.h) is no body's path: a key of
      // 1e35 is finite, but the motion it asks for is not, and the run would stop halfway.
      for (std::size_t k = 0; width == 3 && k < c.times.size(); ++k) {
        for (int i = 0; i < 3; ++i) {
          if (std::abs(c.values[3 * k + i]) > limits::kMaxLength) {
            fail(ErrorCategory::bad_input,
                 gltf.string() + ": animation '" + name + "': translation key " + std::to_string(k) + " of node '" +
                     node_name + "' (at " + format_number(c.times[k]) + " s) is " + format_number(c.values[3 * k + i]) +
                     " along " + "xyz"[i] + ", past the limit of 1e9 mesh units");
          }
        }
      }
      // A rotation key of no length (a zero quaternion) names no rotation: normalizing it gives
      // NaN, and taking it as "no rotation" would be a guess.
      for (std::size_t k = 0; width == 4 && k < c.times.size(); ++k) {
        const double length =
            Eigen::Vector4d(c.values[4 * k], c.values[4 * k + 1], c.values[4 * k + 2], c.values[4 * k + 3]).norm();
        if (!(length > 1e-6)) {
          fail(ErrorCategory::bad_input,
               gltf.string() + ": animation '" + name + "': rotation key " + std::to_string(k) + " of node '" +
                   node_name + "' (at " + format_number(c.times[k]) + " s) is a quaternion of length " +
                   format_number(length) + ", not a rotation (a unit quaternion [x, y, z, w])");
        }
      }
      moves = true;
    }
    if (moves) used = name;
  }
  if (used.empty()) {
    refuse(gltf, animation_name.empty() ? "no animation moves node '" + node_name + "'"
                                        : "no animation named '" + animation_name + "' moves node '" + node_name + "'");
  }
  // The keys: the union of both channels' times, each channel evaluated there by its own linear
  // interpolation (a linear piece split at a time of the other channel stays the same line, and
  // a slerp split stays the same arc at the same speed: the path is exactly the file's).
  const Affine L0 = rest_transform(nodes[*node]);
  const Json& rest = nodes[*node];
  std::vector<double> times;
  for (const Channel& c : channels) times.insert(times.end(), c.times.begin(), c.times.end());
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  const Affine rest_local = L0;
  std::vector<sim::BodyKey> keys;
  for (double t : times) {
    Affine L = Affine::Identity();
    const Vec3 translation = channels[0].width ? translation_at(channels[0], t) : Vec3(rest_local.translation());
    Quat rotation = channels[1].width ? rotation_at(channels[1], t) : Quat(rest_local.rotation());
    L.translate(translation);
    L.rotate(rotation);
    // The rest scale stays (only translation and rotation are animated).
    if (!rest.contains("matrix")) {
      const auto s = rest.value("scale", Json::array({1, 1, 1}));
      if (s.is_array() && s.size() == 3 && s[0].is_number() && s[1].is_number() && s[2].is_number())
        L.scale(Vec3(s[0].get<double>(), s[1].get<double>(), s[2].get<double>()));
    }
    const Affine B = P * L * L0.inverse() * P.inverse();
    const Eigen::Matrix3d R = B.linear();
    if (!((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-6)) {
      refuse(gltf, "node '" + node_name + "' does not move rigidly at " + format_number(t) +
                       " s (a non-uniform scale above it turns its rotation into a shear)");
    }
    // The key is the node's own origin in world axes, p(t) = P · T(t): linear where T is, while
    // the translation of B (where the mesh's origin goes) swings with the rotation.
    sim::BodyKey key;
    key.time = t;
    key.translation = (P * L).translation();
    key.rotation = Quat(R).normalized();
    keys.push_back(key);
  }
  return sim::BodyPath(std::move(keys), sim::BodyInterpolation::linear, (P * L0).translation());
}

}  // namespace sweep::assets
