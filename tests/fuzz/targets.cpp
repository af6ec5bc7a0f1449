#include "targets.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

#include "sweep/assets/gltf_document.h"
#include "sweep/assets/gltf_motion.h"
#include "sweep/assets/gltf_skin.h"
#include "sweep/assets/mesh_checks.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/core/error.h"
#include "sweep/core/hash.h"
#include "sweep/fit/discover.h"
#include "sweep/fit/fit.h"
#include "sweep/io/binding_file.h"
#include "sweep/io/rig_json.h"
#include "sweep/io/scene_authoring_detail.h"
#include "sweep/io/scene_json.h"
#include "sweep/sim/scene.h"

namespace sweep::fuzz {
namespace {

// The rig the scene target resolves forces against: one sweep "tube" with named sections.
constexpr const char* kRig = R"({"format": "sweep-rig", "version": 1, "mesh": "tube.obj",
  "sweeps": [{"name": "tube", "radial_samples": 4,
    "sections": [
      {"name": "root", "t": 0, "center": [0, 0, 0], "rotation": [0, 0, 0, 1], "radii": [0.1, 0.1, 0.1, 0.1]},
      {"name": "mid", "t": 0.5, "center": [0, 0, 0.5], "rotation": [0, 0, 0, 1], "radii": [0.1, 0.1, 0.1, 0.1]},
      {"name": "tip", "t": 1, "center": [0, 0, 1], "rotation": [0, 0, 0, 1], "radii": [0.05, 0.05, 0.05, 0.05]}]}]})";

const Rig& fixed_rig() {
  static const Rig rig = io::parse_rig(kRig, "fixed-rig");
  return rig;
}

// The rig the material target resolves scenes against: two material sweeps, named as the
// diplodocus scenes of rigs/ name them, one with a section overriding its sweep's material.
constexpr const char* kMaterialRig = R"({"format": "sweep-rig", "version": 1, "mesh": "body.obj",
  "sweeps": [
    {"name": "neck", "radial_samples": 4,
     "material": {"youngs_modulus_pa": 5e7, "poisson_ratio": 0.45, "density_kg_m3": 1000, "metres_per_unit": 25},
     "sections": [
      {"name": "root", "t": 0, "center": [0, 0, 0], "rotation": [0, 0, 0, 1], "radii": [0.1, 0.1, 0.1, 0.1]},
      {"name": "tip", "t": 1, "center": [0, 0, 1], "rotation": [0, 0, 0, 1], "radii": [0.05, 0.05, 0.05, 0.05],
       "material": {"youngs_modulus_pa": 1e7}}]},
    {"name": "tail", "radial_samples": 4,
     "material": {"shear_modulus_pa": 2e7, "density_kg_m3": 600, "damping_ratio": 0.1},
     "sections": [
      {"name": "root", "t": 0, "center": [0, 0, 0], "rotation": [0, 0, 0, 1], "radii": [0.1, 0.1, 0.1, 0.1]},
      {"name": "mid", "t": 0.5, "center": [0, 0, -0.5], "rotation": [0, 0, 0, 1], "radii": [0.1, 0.1, 0.1, 0.1]},
      {"name": "tip", "t": 1, "center": [0, 0, -1], "rotation": [0, 0, 0, 1], "radii": [0.05, 0.05, 0.05, 0.05]}]}]})";

const Rig& material_rig() {
  static const Rig rig = io::parse_rig(kMaterialRig, "material-rig");
  return rig;
}

// A folder of this process's own for the targets whose readers take a path: a glTF's relative
// buffer URIs then resolve inside it. Removed when the process ends.
struct ScratchDir {
  std::filesystem::path path;
  ScratchDir() : path(std::filesystem::temp_directory_path() / ("sweep_fuzz_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

// `data` written to the file `name` of the scratch folder.
std::filesystem::path scratch_file(const std::string& name, std::string_view data) {
  static const ScratchDir dir;
  const std::filesystem::path path = dir.path / name;
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data.data(), 1, data.size(), f);
    std::fclose(f);
  }
  return path;
}

// A mesh for check_binding: a triangle (the binding's own checks come first anyway).
const Mesh& fixed_mesh() {
  static const Mesh mesh = [] {
    Mesh m;
    m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    m.face_vertices = {0, 1, 2};
    m.face_offsets = {0, 3};
    return m;
  }();
  return mesh;
}

// A parser's answer to bad bytes: any category but internal, which means a bug (core/error.h).
void ignore(const Error& e) {
  if (e.category() == ErrorCategory::internal) {
    throw std::logic_error(std::string("internal error on input: ") + e.what());
  }
}

void put_u64(std::string& s, std::size_t at, std::uint64_t v) {
  for (int b = 0; b < 8; ++b) s[at + b] = static_cast<char>((v >> (8 * b)) & 0xffu);
}

void parse_and_check_binding(std::string_view data) {
  try {
    const bind::Binding b = io::parse_binding(data, "fuzz.bind");
    io::check_binding(b, fixed_mesh(), fixed_rig(), "fuzz.bind");
  } catch (const Error& e) {
    ignore(e);
  }
}

}  // namespace

void rig_json(std::string_view data) {
  Rig rig;
  try {
    rig = io::parse_rig(std::string(data), "fuzz.json", [](const std::string&) {});
  } catch (const Error& e) {
    ignore(e);
    return;
  }
  // Whatever was accepted must write, and read back to the same bytes (bindings hash the values):
  // an Error here is a bug, so it is not caught.
  const std::string text = io::format_rig(rig);
  if (io::format_rig(io::parse_rig(text, "fuzz-again.json")) != text) {
    throw std::logic_error("rig_json: a rig read back from its own text writes other bytes");
  }
}

void scene(std::string_view data) {
  // read_scene takes a path (it tells a scene file from a rig file carrying one), so the input is
  // written to a file of this process's own.
  const std::filesystem::path path = scratch_file("scene.json", data);
  try {
    // The tools' reader: the runtime's, and the keys that need the mesh file too.
    io::SceneAuthoring authoring;
    const sim::Scene s = io::read_scene(
        path, fixed_rig(), [](const std::string&) {}, authoring);
    (void)s.frame_count();
  } catch (const Error& e) {
    ignore(e);
  }
  std::filesystem::remove(path);
}

void binding(std::string_view data) {
  parse_and_check_binding(data);
  // A checksum guards everything behind it, so random bytes rarely get past it: the same input
  // again with the payload size and the checksum made to agree with the bytes.
  constexpr std::size_t kHeader = 48, kTrailer = 8;
  if (data.size() < kHeader + kTrailer) return;
  std::string fixed(data);
  put_u64(fixed, 40, fixed.size() - kHeader - kTrailer);
  const std::size_t end = fixed.size() - kTrailer;
  put_u64(fixed, end, fnv1a(std::string_view(fixed).substr(0, end)));
  parse_and_check_binding(fixed);
}

namespace {

// ---- An independent reading of the vertex lines, for the mesh targets ----
// Whatever a reader accepts must hold exactly the vertices the file's lines hold, in their order:
// counted here line by line with strtod, a way unrelated to the readers' own (a BOM
// once made the OBJ reader skip the first `v`, a lying PLY header had face lines read as vertices).

std::string_view without_bom(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return text;
}

// Lines ending at "\n", "\r\n" or a lone "\r" (what the readers accept), '#' comments removed.
std::vector<std::vector<std::string>> lines_of(std::string_view text, bool lone_cr_ends_line) {
  std::vector<std::vector<std::string>> lines;
  std::vector<std::string> words;
  std::string word;
  bool comment = false;
  auto end_word = [&] {
    if (!word.empty()) words.push_back(word);
    word.clear();
  };
  for (std::size_t i = 0; i <= text.size(); ++i) {
    const char c = i < text.size() ? text[i] : '\n';
    if (c == '\n' || (c == '\r' && lone_cr_ends_line)) {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      end_word();
      lines.push_back(std::move(words));
      words.clear();
      comment = false;
    } else if (comment || c == '#') {
      comment = true;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      end_word();
    } else {
      word += c;
    }
  }
  return lines;
}

Vec3 strtod3(const std::vector<std::string>& w, std::size_t first) {
  Vec3 p;
  for (int k = 0; k < 3; ++k) p[k] = std::strtod(w.at(first + k).c_str(), nullptr);
  return p;
}

void expect_vertices(const Mesh& m, const std::vector<Vec3>& expected, const char* target) {
  if (m.positions.size() != expected.size()) {
    throw std::logic_error(std::string(target) + ": the reader holds " + std::to_string(m.positions.size()) +
                           " vertices, the file's lines " + std::to_string(expected.size()));
  }
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (!(m.positions[i] == expected[i])) {
      throw std::logic_error(std::string(target) + ": vertex " + std::to_string(i) + " differs from its line");
    }
  }
}

}  // namespace

void off_mesh(std::string_view data) {
  Mesh m;
  try {
    m = assets::parse_off(data, "fuzz.off");
    assets::validate_mesh(m, "fuzz.off");
  } catch (const Error& e) {
    ignore(e);
    return;
  }
  // Accepted: the header word, the counts (on its line or the next), then one vertex a line.
  std::vector<std::vector<std::string>> lines;
  for (auto& l : lines_of(without_bom(data), false)) {
    if (!l.empty()) lines.push_back(std::move(l));
  }
  std::size_t at = 0;
  std::vector<std::string> counts(lines.at(0).begin() + 1, lines.at(0).end());
  if (counts.empty()) counts = lines.at(++at);
  const std::size_t nv = std::stoull(counts.at(0));
  std::vector<Vec3> expected;
  for (std::size_t i = 0; i < nv; ++i) expected.push_back(strtod3(lines.at(++at), 0));
  expect_vertices(m, expected, "off_mesh");
}

void obj_mesh(std::string_view data) {
  Mesh m;
  try {
    m = assets::parse_obj(std::string(data), "fuzz.obj");
    assets::validate_mesh(m, "fuzz.obj");
  } catch (const Error& e) {
    ignore(e);
    return;
  }
  std::vector<Vec3> expected;
  for (const auto& l : lines_of(without_bom(data), true)) {
    if (!l.empty() && l[0] == "v") expected.push_back(strtod3(l, 1));
  }
  expect_vertices(m, expected, "obj_mesh");
}

void ply_mesh(std::string_view data) {
  Mesh m;
  try {
    m = assets::parse_ply(data, "fuzz.ply");
    assets::validate_mesh(m, "fuzz.ply");
  } catch (const Error& e) {
    ignore(e);
    return;
  }
  // ASCII with "vertex" first and x y z its first properties: the vertex lines follow the header
  // one a line, as single-precision values (assimp stores floats).
  const auto lines = lines_of(without_bom(data), false);
  std::size_t at = 0;
  std::vector<std::string> props;
  bool ascii = false, vertex_first = false;
  std::size_t nv = 0, elements = 0;
  for (; at < lines.size(); ++at) {
    const auto& l = lines[at];
    if (l.empty()) continue;
    if (l[0] == "end_header") break;
    if (l[0] == "format" && l.size() > 1) ascii = l[1] == "ascii";
    if (l[0] == "element" && l.size() > 2 && elements++ == 0 && l[1] == "vertex") {
      vertex_first = true;
      nv = std::stoull(l[2]);
    }
    if (l[0] == "property" && elements == 1 && l.size() > 2) props.push_back(l.back());
  }
  if (!ascii || !vertex_first || props.size() < 3 || props[0] != "x" || props[1] != "y" || props[2] != "z") {
    return;
  }
  std::vector<Vec3> expected;
  while (expected.size() < nv) {
    const auto& l = lines.at(++at);
    if (!l.empty()) expected.push_back(strtod3(l, 0).cast<float>().cast<double>());
  }
  expect_vertices(m, expected, "ply_mesh");
}

void fit_off(std::string_view data) {
  Mesh m;
  try {
    m = assets::parse_off(data, "fuzz.off");
    assets::validate_mesh(m, "fuzz.off");
  } catch (const Error& e) {
    ignore(e);
    return;
  }
  if (m.vertex_count() > 2000) return;  // keeps each run short; size is not what is tested
  try {
    const fit::SweepFitter fitter(m);
    fit::DiscoverOptions discover;
    discover.samples = 4;
    const std::vector<fit::FoundPart> parts = fit::find_parts(m, fitter.topology(), discover);
    fit::FitOptions o;
    o.sections = 8;
    o.radial = 8;
    o.tip_vertex = parts.empty() ? 0 : static_cast<std::int64_t>(parts.front().tip_vertex);
    const fit::FitResult r = fitter.fit(o);
    const SweepShape& shape = r.sweep.rest;
    bool finite = std::isfinite(r.mean_radius) && std::isfinite(r.length);
    for (const double x : shape.radii) finite = finite && std::isfinite(x) && x > 0;
    for (std::size_t i = 0; i < shape.frames.size(); ++i) {
      finite = finite && shape.frames[i].center.allFinite() && std::isfinite(shape.t[i]);
    }
    if (!finite) throw std::logic_error("fit_off: a fit returned a non-finite or non-positive number");
    for (const std::uint32_t v : r.part_vertices) {
      if (v >= m.vertex_count()) throw std::logic_error("fit_off: a part vertex outside the mesh");
    }
  } catch (const Error& e) {
    ignore(e);
  }
}

namespace {

void expect(bool holds, const std::string& what) {
  if (!holds) throw std::logic_error(what);
}

// The POSITION of the first node with a skin and a mesh, its primitives in order, read through
// read_float_accessor (not read_gltf_skin's own reader): the vertices the importer would have read,
// so that read_gltf_skin gets past its mesh match. Empty when they cannot be read that way.
std::vector<Vec3> skinned_positions(const std::filesystem::path& file) {
  using Json = nlohmann::json;
  const assets::detail::GltfDocument doc = assets::detail::read_gltf_document(file);
  std::vector<Vec3> out;
  const auto nodes = doc.json.is_object() ? doc.json.find("nodes") : doc.json.end();
  if (!doc.json.is_object() || nodes == doc.json.end() || !nodes->is_array()) return out;
  for (const Json& node : *nodes) {
    if (!node.is_object() || !node.contains("skin") || !node.contains("mesh")) continue;
    const Json* mesh = assets::detail::gltf_element(doc.json, "meshes", node.at("mesh"));
    const auto prims = mesh != nullptr ? mesh->find("primitives") : Json::const_iterator();
    if (mesh == nullptr || prims == mesh->end() || !prims->is_array()) return out;
    for (const Json& prim : *prims) {
      const auto attributes = prim.is_object() ? prim.find("attributes") : prim.end();
      if (!prim.is_object() || attributes == prim.end() || !attributes->is_object() ||
          !attributes->contains("POSITION")) {
        return {};
      }
      const auto p = assets::detail::read_float_accessor(doc, attributes->at("POSITION"), 3);
      if (!p) return {};
      for (std::size_t v = 0; v + 2 < p->size(); v += 3) out.emplace_back((*p)[v], (*p)[v + 1], (*p)[v + 2]);
    }
    return out;
  }
  return out;
}

// What read_gltf_skin promises of a model it returns, then its skinning at rest and at each clip's
// start, middle and end (out-of-range indices are ASan's to see).
void check_skin_model(const assets::SkinModel& m) {
  const std::size_t nodes = m.nodes.size(), joints = m.joints.size();
  expect(m.mesh_node >= 0 && static_cast<std::size_t>(m.mesh_node) < nodes, "gltf: the skinned node is not a node");
  expect(m.inverse_bind.size() == joints, "gltf: not one inverse bind matrix a joint");
  for (const int j : m.joints) expect(j >= 0 && static_cast<std::size_t>(j) < nodes, "gltf: a joint is not a node");
  for (const Eigen::Matrix4d& ibm : m.inverse_bind) expect(ibm.allFinite(), "gltf: a non-finite inverse bind matrix");
  const std::size_t n = m.bind_positions.size();
  expect(m.vertex_joints.size() == n && m.vertex_weights.size() == n,
         "gltf: not one joint set and weight set a vertex");
  for (std::size_t v = 0; v < n; ++v) {
    expect(m.bind_positions[v].allFinite(), "gltf: a non-finite bind position");
    double sum = 0;
    for (int k = 0; k < 4; ++k) {
      const double w = m.vertex_weights[v][k];
      expect(std::isfinite(w) && w >= 0, "gltf: a negative or non-finite weight");
      expect(w == 0 || m.vertex_joints[v][k] < joints, "gltf: a weighted joint past the skin's joints");
      sum += w;
    }
    expect(std::abs(sum - 1) < 1e-9, "gltf: weights that do not sum to 1");
  }
  for (const assets::SkinClip& clip : m.clips) {
    for (const assets::ClipChannel& c : clip.channels) {
      expect(c.node >= 0 && static_cast<std::size_t>(c.node) < nodes, "gltf: a channel of no node");
      const std::size_t per_key =
          static_cast<std::size_t>(c.width()) * (c.interpolation == assets::ChannelInterpolation::cubic ? 3 : 1);
      expect(!c.times.empty() && c.values.size() == c.times.size() * per_key, "gltf: keys and values do not match");
      for (std::size_t k = 0; k < c.times.size(); ++k) {
        expect(std::isfinite(c.times[k]) && (k == 0 || c.times[k] > c.times[k - 1]), "gltf: key times not increasing");
      }
      for (const double x : c.values) expect(std::isfinite(x), "gltf: a non-finite key value");
    }
  }
  const std::size_t skinned = std::min<std::size_t>(n, 256);  // bounded: size is not what is tested
  auto skin_at = [&](int clip, double t) {
    const std::vector<Eigen::Matrix4d> joint = assets::joint_matrices(m, assets::world_transforms(m, clip, t));
    for (std::size_t v = 0; v < skinned; ++v) (void)assets::skin_vertex(m, joint, v);
  };
  skin_at(-1, 0);
  for (std::size_t c = 0; c < std::min<std::size_t>(m.clips.size(), 8); ++c) {
    const assets::SkinClip& clip = m.clips[c];
    for (const double t : {clip.start, 0.5 * (clip.start + clip.end), clip.end}) skin_at(static_cast<int>(c), t);
  }
}

// What read_gltf_body_path promises of a path it returns: keys at finite, increasing times, finite
// translations, unit rotations; and the motion between them finite.
void check_body_path(const sim::BodyPath& path) {
  const std::vector<sim::BodyKey>& keys = path.keys();
  expect(!keys.empty(), "gltf: a body path without keys");
  for (std::size_t k = 0; k < keys.size(); ++k) {
    expect(std::isfinite(keys[k].time) && (k == 0 || keys[k].time > keys[k - 1].time),
           "gltf: body key times not increasing");
    expect(keys[k].translation.allFinite(), "gltf: a non-finite body translation");
    expect(std::abs(keys[k].rotation.norm() - 1) < 1e-6, "gltf: a body rotation that is not a unit quaternion");
  }
  for (const double t : {keys.front().time, 0.5 * (keys.front().time + keys.back().time), keys.back().time}) {
    const sim::BodyState s = path.at(t);
    expect(s.translation.allFinite() && s.rotation.coeffs().allFinite() && s.velocity.allFinite() &&
               s.angular_velocity.allFinite(),
           "gltf: a body path whose motion is not finite");
  }
}

// The names of the file's first nodes (those that are strings), for read_gltf_body_path.
std::vector<std::string> first_node_names(const std::filesystem::path& file) {
  std::vector<std::string> names;
  const assets::detail::GltfDocument doc = assets::detail::read_gltf_document(file);
  if (!doc.json.is_object()) return names;
  const auto nodes = doc.json.find("nodes");
  if (nodes == doc.json.end() || !nodes->is_array()) return names;
  for (const nlohmann::json& node : *nodes) {
    if (names.size() == 3) break;
    const auto name = node.is_object() ? node.find("name") : node.end();
    if (node.is_object() && name != node.end() && name->is_string()) names.push_back(name->get<std::string>());
  }
  return names;
}

}  // namespace

void gltf(std::string_view data) {
  const bool binary = data.substr(0, 4) == "glTF";
  const std::filesystem::path path = scratch_file(binary ? "fuzz.glb" : "fuzz.gltf", data);
  try {
    (void)assets::detail::check_gltf_indices(path);
  } catch (const Error& e) {
    ignore(e);
  }
  std::vector<std::string> names;
  try {
    names = first_node_names(path);
    const std::vector<Vec3> positions = skinned_positions(path);
    if (const std::optional<assets::SkinModel> model =
            assets::read_gltf_skin(path, positions, Eigen::Affine3d::Identity())) {
      check_skin_model(*model);
    }
  } catch (const Error& e) {
    ignore(e);
  }
  for (const std::string& name : names) {
    try {
      check_body_path(assets::read_gltf_body_path(path, name));
    } catch (const Error& e) {
      ignore(e);
    }
  }
  std::filesystem::remove(path);
}

void material(std::string_view data) {
  try {
    const Material m = io::parse_material(std::string(data), "fuzz.material.json", [](const std::string&) {});
    const bool finite = std::isfinite(m.youngs_modulus) && m.youngs_modulus > 0 && std::isfinite(m.density) &&
                        m.density > 0 && std::isfinite(m.metres_per_unit) && m.metres_per_unit > 0 &&
                        std::isfinite(m.damping_ratio) && m.damping_ratio >= 0 && std::isfinite(m.shear()) &&
                        m.shear() > 0;
    expect(finite, "material: an accepted material with a constant that is not finite and positive");
  } catch (const Error& e) {
    ignore(e);
  }
  const std::filesystem::path path = scratch_file("material-scene.json", data);
  try {
    const sim::Scene s = io::read_scene(path, material_rig(), [](const std::string&) {});
    (void)s.frame_count();
  } catch (const Error& e) {
    ignore(e);
  }
  std::filesystem::remove(path);
}

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {{"rig_json", rig_json}, {"scene", scene},       {"binding", binding},
                                          {"off_mesh", off_mesh}, {"obj_mesh", obj_mesh}, {"ply_mesh", ply_mesh},
                                          {"fit_off", fit_off},   {"gltf", gltf},         {"material", material}};
  return all;
}

}  // namespace sweep::fuzz
