// A skinned clip's bake as joints in the character's own skeleton (gltf_character_joints.h).
#include "sweep/assets/gltf_character_joints.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "sweep/assets/gltf_codes_detail.h"
#include "sweep/core/error.h"

namespace sweep::assets::detail {
namespace {

using namespace gltf_codes;

using Json = nlohmann::json;

struct Writer {
  Json& json;
  const AppendBin& put;

  std::size_t view(const BinBlock& block, int target = 0) {
    Json v = {{"buffer", 0}, {"byteOffset", block.offset}, {"byteLength", block.length}};
    if (target != 0) v["target"] = target;
    json["bufferViews"].push_back(std::move(v));
    return json["bufferViews"].size() - 1;
  }
  std::size_t accessor(Json a) {
    json["accessors"].push_back(std::move(a));
    return json["accessors"].size() - 1;
  }
  template <typename T>
  std::size_t data(const std::vector<T>& values, std::size_t count, const char* type, int component, int target = 0) {
    return accessor({{"bufferView", view(put(values.data(), values.size() * sizeof(T)), target)},
                     {"componentType", component},
                     {"count", count},
                     {"type", type}});
  }
  std::size_t times(const std::vector<float>& t) {
    const std::size_t a = data(t, t.size(), "SCALAR", kFloat);
    json["accessors"][a]["min"] = Json::array({t.front()});
    json["accessors"][a]["max"] = Json::array({t.back()});
    return a;
  }
};

void add_channel(Json& animation, std::size_t input, std::size_t output, std::size_t node, const char* path) {
  animation["samplers"].push_back({{"input", input}, {"output", output}, {"interpolation", "LINEAR"}});
  animation["channels"].push_back(
      {{"sampler", animation["samplers"].size() - 1}, {"target", {{"node", node}, {"path", path}}}});
}

// One joint's keys over a track as translation, rotation and scale accessors.
struct Track {
  std::vector<float> t, r, s;
  void add(const JointKey& k) {
    t.insert(t.end(), k.t, k.t + 3);
    r.insert(r.end(), k.r, k.r + 4);
    s.insert(s.end(), k.s, k.s + 3);
  }
};

void key_joints(Writer& w, Json& animation, std::size_t input, const CharacterJoints& cj,
                const std::vector<std::vector<JointKey>>& keys, std::size_t first_node,
                const std::vector<char>& keyed) {
  const std::size_t count = keys.size();
  for (std::size_t k = 0; k < cj.joints().size(); ++k) {
    if (!keyed[k]) continue;
    Track track;
    for (const auto& frame : keys) track.add(frame[k]);
    const int joint = static_cast<int>(k);
    if (cj.is_station(joint)) {
      add_channel(animation, input, w.data(track.t, count, "VEC3", kFloat), first_node + k, "translation");
      add_channel(animation, input, w.data(track.r, count, "VEC4", kFloat), first_node + k, "rotation");
    }
    if (cj.has_scale(joint))
      add_channel(animation, input, w.data(track.s, count, "VEC3", kFloat), first_node + k, "scale");
  }
}

std::string unique_animation_name(const Json& json) {
  std::string name = "sweep bake";
  for (int k = 2;; ++k) {
    bool taken = false;
    for (const Json& a : json["animations"]) taken = taken || (a.is_object() && a.value("name", "") == name);
    if (!taken) return name;
    name = "sweep bake " + std::to_string(k);
  }
}

// Per primitive of the skinned mesh: JOINTS_0 and WEIGHTS_0 accessors of the new weights.
void reweight(Writer& w, const CharacterJoints& cj, std::span<const PrimitiveSource> primitives, std::size_t mesh,
              const std::string& where) {
  const int joint_count = cj.original_joints() + static_cast<int>(cj.joints().size());
  for (const PrimitiveSource& p : primitives) {
    if (p.mesh != mesh || p.source == nullptr) continue;
    const std::vector<std::uint32_t>& source = *p.source;
    if (std::none_of(source.begin(), source.end(), [&](std::uint32_t v) { return cj.reweighted()[v] != 0; })) continue;
    Json& attributes = w.json["meshes"][mesh]["primitives"][p.index]["attributes"];
    const std::string what = where + "mesh " + std::to_string(mesh) + " primitive " + std::to_string(p.index);
    if (!attributes.contains("JOINTS_0") || !attributes.contains("WEIGHTS_0")) {
      fail(ErrorCategory::unsupported, what + " holds a part's vertices and has no JOINTS_0/WEIGHTS_0 of its own");
    }
    auto component_of = [&](const char* name) {
      const Json& index = attributes[name];
      const Json& a = w.json["accessors"].at(index.get<std::size_t>());
      return a.value("componentType", kFloat);
    };
    const std::size_t n = source.size();
    if (component_of("JOINTS_0") == kUnsignedByte && joint_count <= 256) {
      std::vector<std::uint8_t> joints(4 * n);
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t e = 0; e < 4; ++e)
          joints[4 * i + e] = static_cast<std::uint8_t>(cj.vertex_joints()[source[i]][e]);
      attributes["JOINTS_0"] = w.data(joints, n, "VEC4", kUnsignedByte, kArrayBuffer);
    } else {
      std::vector<std::uint16_t> joints(4 * n);
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t e = 0; e < 4; ++e) joints[4 * i + e] = cj.vertex_joints()[source[i]][e];
      attributes["JOINTS_0"] = w.data(joints, n, "VEC4", kUnsignedShort, kArrayBuffer);
    }
    const int weight_type = component_of("WEIGHTS_0");
    if (weight_type == kFloat) {
      std::vector<float> weights(4 * n);
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t e = 0; e < 4; ++e) weights[4 * i + e] = cj.vertex_weights()[source[i]][e];
      attributes["WEIGHTS_0"] = w.data(weights, n, "VEC4", kFloat, kArrayBuffer);
      continue;
    }
    // Normalized integers: rounded; a part's vertex gives its heaviest what rounding took, so that
    // its weights sum to exactly one.
    const double full = weight_type == kUnsignedByte ? 255.0 : 65535.0;
    std::vector<std::uint32_t> q(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t v = source[i];
      long long sum = 0;
      for (std::size_t e = 0; e < 4; ++e) {
        q[4 * i + e] = static_cast<std::uint32_t>(std::lround(cj.vertex_weights()[v][e] * full));
        sum += q[4 * i + e];
      }
      if (cj.reweighted()[v])
        q[4 * i] = static_cast<std::uint32_t>(std::max(0LL, q[4 * i] + static_cast<long long>(full) - sum));
    }
    std::size_t accessor = 0;
    if (weight_type == kUnsignedByte) {
      const std::vector<std::uint8_t> weights(q.begin(), q.end());
      accessor = w.data(weights, n, "VEC4", kUnsignedByte, kArrayBuffer);
    } else {
      const std::vector<std::uint16_t> weights(q.begin(), q.end());
      accessor = w.data(weights, n, "VEC4", kUnsignedShort, kArrayBuffer);
    }
    w.json["accessors"][accessor]["normalized"] = true;
    attributes["WEIGHTS_0"] = accessor;
  }
}

}  // namespace

void add_character_joints(Json& json, const CharacterJoints& cj, std::span<const ResampledChannel> resampled,
                          const BakedFrames& baked, std::span<const PrimitiveSource> primitives, const AppendBin& put,
                          const std::string& where) {
  for (const char* key : {"bufferViews", "accessors", "animations", "nodes", "skins"}) {
    if (!json.contains(key) || !json[key].is_array()) json[key] = Json::array();
  }
  Writer w{json, put};
  const SkinModel& model = cj.clip().model();
  const Json& mesh_node = json["nodes"][static_cast<std::size_t>(model.mesh_node)];
  const std::size_t skin_index = mesh_node.at("skin").get<std::size_t>();
  const std::size_t mesh = mesh_node.at("mesh").get<std::size_t>();

  // The nodes, under their parents.
  const std::size_t first = json["nodes"].size();
  for (std::size_t k = 0; k < cj.joints().size(); ++k) {
    const CharacterJoint& j = cj.joints()[k];
    const JointKey& key = cj.rest_keys()[k];
    Json node = {{"name", j.name}};
    if (key.t[0] != 0 || key.t[1] != 0 || key.t[2] != 0) node["translation"] = {key.t[0], key.t[1], key.t[2]};
    if (key.r[0] != 0 || key.r[1] != 0 || key.r[2] != 0 || key.r[3] != 1)
      node["rotation"] = {key.r[0], key.r[1], key.r[2], key.r[3]};
    if (key.s[0] != 1 || key.s[1] != 1 || key.s[2] != 1) node["scale"] = {key.s[0], key.s[1], key.s[2]};
    json["nodes"].push_back(std::move(node));
    const std::size_t parent = j.parent_joint >= 0 ? first + static_cast<std::size_t>(j.parent_joint)
                                                   : static_cast<std::size_t>(j.parent_node);
    Json& p = json["nodes"][parent];
    if (!p.contains("children") || !p["children"].is_array()) p["children"] = Json::array();
    p["children"].push_back(first + k);
  }

  // The skin: its joints and inverse bind matrices, then the new ones.
  Json& skin = json["skins"][skin_index];
  std::vector<float> ibm;
  for (const Eigen::Matrix4d& m : model.inverse_bind)
    for (int e = 0; e < 16; ++e) ibm.push_back(static_cast<float>(m(e % 4, e / 4)));
  for (std::size_t k = 0; k < cj.joints().size(); ++k) {
    skin["joints"].push_back(first + k);
    for (int e = 0; e < 16; ++e) ibm.push_back(cj.inverse_bind()[k](e % 4, e / 4));
  }
  skin["inverseBindMatrices"] = w.data(ibm, ibm.size() / 16, "MAT4", kFloat);
  reweight(w, cj, primitives, mesh, where);

  // The baked clip.
  const std::size_t frames = static_cast<std::size_t>(baked.frames);
  const std::size_t times = w.accessor({{"bufferView", w.view(baked.times)},
                                        {"componentType", kFloat},
                                        {"count", frames},
                                        {"type", "SCALAR"},
                                        {"min", Json::array({0.0})},
                                        {"max", Json::array({double{baked.last_time}})}});
  Json animation = {{"samplers", Json::array()}, {"channels", Json::array()}};
  for (const ResampledChannel& r : resampled) {
    const bool rotation = r.path == ChannelPath::rotation;
    const std::size_t values = w.accessor({{"bufferView", w.view(r.block)},
                                           {"componentType", kFloat},
                                           {"count", frames},
                                           {"type", rotation ? "VEC4" : "VEC3"}});
    add_channel(animation, times, values, static_cast<std::size_t>(r.node),
                rotation                       ? "rotation"
                : r.path == ChannelPath::scale ? "scale"
                                               : "translation");
  }
  // Station joints always; a ring joint when it leaves its rest.
  std::vector<char> keyed(cj.joints().size(), 0);
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    keyed[k] = cj.is_station(static_cast<int>(k));
    for (std::size_t f = 0; f < cj.keys().size() && !keyed[k]; ++f) keyed[k] = !(cj.keys()[f][k] == cj.rest_keys()[k]);
  }
  key_joints(w, animation, times, cj, cj.keys(), first, keyed);

  // Every other clip: the parts' original skinned motion.
  // The model's clips are the file's animations that are objects, in order.
  const std::size_t animations = json["animations"].size();
  for (std::size_t a = 0, c = 0; a < animations && c < model.clips.size(); ++a) {
    Json& other = json["animations"][a];
    if (!other.is_object()) continue;
    const int clip = static_cast<int>(c++);
    if (!other.contains("channels") || !other.contains("samplers")) continue;
    const CharacterJoints::ClipKeys keys = cj.clip_keys(clip, baked.fps);
    const std::size_t input = w.times(keys.times);
    std::vector<char> stations(cj.joints().size(), 0), rings(cj.joints().size(), 0);
    for (std::size_t k = 0; k < stations.size(); ++k) {
      stations[k] = cj.is_station(static_cast<int>(k));
      rings[k] = keyed[k] && !stations[k];
    }
    key_joints(w, other, input, cj, keys.keys, first, stations);
    // Ring joints keyed in the bake: held at rest, two keys.
    if (std::find(rings.begin(), rings.end(), 1) == rings.end()) continue;
    const std::vector<float> ends = keys.times.size() > 1 ? std::vector<float>{keys.times.front(), keys.times.back()}
                                                          : std::vector<float>{keys.times.front()};
    const std::size_t end_input = w.times(ends);
    std::vector<float> ones(3 * ends.size(), 1.0f);
    const std::size_t held = w.data(ones, ends.size(), "VEC3", kFloat);
    for (std::size_t k = 0; k < rings.size(); ++k)
      if (rings[k]) add_channel(other, end_input, held, first + k, "scale");
  }
  animation["name"] = unique_animation_name(json);
  json["animations"].push_back(std::move(animation));
}

}  // namespace sweep::assets::detail
