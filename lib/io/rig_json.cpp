#include "sweep/io/rig_json.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "sweep/core/error.h"
#include "sweep/core/limits.h"
#include "sweep/core/text.h"
#include "sweep/io/atomic_file.h"
#include "sweep/io/json_reader.h"
#include "sweep/io/mesh_names.h"
#include "sweep/io/read_file.h"

namespace sweep::io {
namespace {

using OrderedJson = nlohmann::ordered_json;

constexpr const char* kFormatName = "sweep-rig";
// A stored rotation must be a unit quaternion to this tolerance; it is used as stored, so that a
// rig read and written again keeps every bit (bindings hash the rig's values).
constexpr double kUnitQuaternionTolerance = 1e-9;

// A positive number no larger than `hi`: the sign first (its own message), then the limit.
double positive_at_most(const JsonReader& r, const Json& v, const std::string& ptr, double lo, double hi) {
  r.positive(v, ptr);
  return r.bounded(v, ptr, lo, hi);
}

// --- reading ---------------------------------------------------------------------------------------

void read_spring(const JsonReader& r, const Json& v, const std::string& ptr, SpringSettings& s) {
  r.object(v, ptr, {"mass", "frequency_hz", "damping_ratio"});
  // Physical ranges (core/limits.h): outside them the exact step under- or overflows.
  if (const Json* m = r.optional(v, "mass"))
    s.mass = positive_at_most(r, *m, member(ptr, "mass"), limits::kMinMass, limits::kMaxMass);
  if (const Json* f = r.optional(v, "frequency_hz"))
    s.frequency_hz =
        positive_at_most(r, *f, member(ptr, "frequency_hz"), limits::kMinFrequencyHz, limits::kMaxFrequencyHz);
  if (const Json* z = r.optional(v, "damping_ratio")) {
    r.non_negative(*z, member(ptr, "damping_ratio"));
    s.damping_ratio = r.bounded(*z, member(ptr, "damping_ratio"), 0, limits::kMaxDampingRatio);
  }
}

// Springs given in a file override `s` kind by kind and field by field.
void read_springs(const JsonReader& r, const Json& v, const std::string& ptr, SectionSprings& s) {
  r.object(v, ptr, {"positional", "bend", "twist", "radial"});
  if (const Json* x = r.optional(v, "positional")) read_spring(r, *x, member(ptr, "positional"), s.positional);
  if (const Json* x = r.optional(v, "bend")) read_spring(r, *x, member(ptr, "bend"), s.bend);
  if (const Json* x = r.optional(v, "twist")) read_spring(r, *x, member(ptr, "twist"), s.twist);
  if (const Json* x = r.optional(v, "radial")) read_spring(r, *x, member(ptr, "radial"), s.radial);
}

// A material given in a file overrides `m` field by field (core/material.h). Where a preset may be
// named (a sweep's material, a material file), `preset` takes it: the preset's members go first,
// the members given override them.
void read_material(const JsonReader& r, const Json& v, const std::string& ptr, Material& m,
                   MaterialRequest* preset = nullptr) {
  if (preset == nullptr) {
    r.object(v, ptr,
             {"youngs_modulus_pa", "poisson_ratio", "shear_modulus_pa", "density_kg_m3", "metres_per_unit",
              "damping_ratio"});
  } else {
    r.object(v, ptr,
             {"preset", "youngs_modulus_pa", "poisson_ratio", "shear_modulus_pa", "density_kg_m3", "metres_per_unit",
              "damping_ratio"});
    if (const Json* x = r.optional(v, "preset")) {
      const std::string name = r.string(*x, member(ptr, "preset"));
      preset->preset = find_preset(name);
      if (preset->preset == nullptr)
        r.fail_at(member(ptr, "preset"), "unknown preset \"" + name + "\": one of " + preset_names());
      const double scale = m.metres_per_unit;
      m = preset_base(*preset->preset);
      m.metres_per_unit = scale;
    }
    preset->youngs_modulus_given = preset->youngs_modulus_given || r.optional(v, "youngs_modulus_pa") != nullptr;
  }
  if (r.optional(v, "poisson_ratio") && r.optional(v, "shear_modulus_pa"))
    r.fail_at(ptr, "give either \"poisson_ratio\" or \"shear_modulus_pa\", not both");
  if (const Json* x = r.optional(v, "youngs_modulus_pa"))
    m.youngs_modulus = r.positive(*x, member(ptr, "youngs_modulus_pa"));
  if (const Json* x = r.optional(v, "poisson_ratio")) {
    m.poisson_ratio = r.number(*x, member(ptr, "poisson_ratio"));
    m.shear_modulus = 0;
    if (!(m.poisson_ratio > -1 && m.poisson_ratio < 0.5))
      r.fail_at(member(ptr, "poisson_ratio"), "must be between -1 and 0.5 (exclusive), got " + describe(*x));
  }
  if (const Json* x = r.optional(v, "shear_modulus_pa"))
    m.shear_modulus = r.positive(*x, member(ptr, "shear_modulus_pa"));
  if (const Json* x = r.optional(v, "density_kg_m3")) m.density = r.positive(*x, member(ptr, "density_kg_m3"));
  if (const Json* x = r.optional(v, "metres_per_unit"))
    m.metres_per_unit = r.positive(*x, member(ptr, "metres_per_unit"));
  if (const Json* x = r.optional(v, "damping_ratio"))
    m.damping_ratio = r.non_negative(*x, member(ptr, "damping_ratio"));
  // Each constant finite is not enough: G = E / (2 (1 + ν)) overflows for a large E and ν near -1
  // (compared without computing it, which would overflow).
  const bool shear_finite = m.shear_modulus > 0 || 1 + m.poisson_ratio >= 1 ||
                            m.youngs_modulus / 2 <= std::numeric_limits<double>::max() * (1 + m.poisson_ratio);
  if (!shear_finite) {
    r.fail_at(ptr, "its shear modulus E / (2 (1 + poisson_ratio)) is not finite (E " + format_number(m.youngs_modulus) +
                       ", poisson_ratio " + format_number(m.poisson_ratio, 10) +
                       "): lower youngs_modulus_pa or raise poisson_ratio");
  }
}

Quat read_rotation(const JsonReader& r, const Json& v, const std::string& ptr) {
  if (!v.is_array() || v.size() != 4) r.fail_at(ptr, "must be a quaternion [x, y, z, w], got " + describe(v));
  double c[4];
  for (int i = 0; i < 4; ++i) c[i] = r.number(v[i], element(ptr, i));
  const Quat q(c[3], c[0], c[1], c[2]);
  const double norm = q.norm();
  if (std::abs(norm - 1.0) > kUnitQuaternionTolerance) {
    r.fail_at(ptr, "must be a unit quaternion, its length is " + format_exact(norm));
  }
  return q;
}

SweepDef read_sweep(const JsonReader& r, const Json& v, const std::string& ptr, long long version) {
  r.object(v, ptr, {"name", "radial_samples", "springs", "material", "force_scale", "part", "sections"});
  SweepDef def;
  def.name = r.string(r.required(v, ptr, "name"), member(ptr, "name"));
  if (def.name.empty()) r.fail_at(member(ptr, "name"), "must not be empty");
  const int n = static_cast<int>(r.integer(r.required(v, ptr, "radial_samples"), member(ptr, "radial_samples"),
                                           limits::kMinRadial, limits::kMaxRadial));
  if (const Json* s = r.optional(v, "springs")) read_springs(r, *s, member(ptr, "springs"), def.default_springs);
  MaterialRequest request;  // a preset's E is solved once the sections are read
  if (const Json* m = r.optional(v, "material")) {
    def.material = Material{};
    read_material(r, *m, member(ptr, "material"), *def.material, &request);
  }
  if (const Json* fs = r.optional(v, "force_scale")) {
    const std::string p = member(ptr, "force_scale");
    r.object(*fs, p, {"rotational", "radial"});
    if (const Json* x = r.optional(*fs, "rotational")) {
      r.non_negative(*x, member(p, "rotational"));
      def.rotational_scale = r.bounded(*x, member(p, "rotational"), 0, limits::kMaxForceScale);
    }
    if (const Json* x = r.optional(*fs, "radial")) {
      r.non_negative(*x, member(p, "radial"));
      def.radial_scale = r.bounded(*x, member(p, "radial"), 0, limits::kMaxForceScale);
    }
  }
  if (const Json* part = r.optional(v, "part")) {
    const std::string p = member(ptr, "part");
    r.object(*part, p, {"root", "tip", "tip_cut"});
    def.part = PartSeeds{r.bounded_vec3(r.required(*part, p, "root"), member(p, "root"), limits::kMaxLength),
                         r.bounded_vec3(r.required(*part, p, "tip"), member(p, "tip"), limits::kMaxLength)};
    if (const Json* cut = r.optional(*part, "tip_cut")) {
      const std::string cp = member(p, "tip_cut");
      if (version < Rig::kTipCutFormatVersion) {
        r.fail_at(cp, "needs rig format version " + std::to_string(Rig::kTipCutFormatVersion) +
                          " (the file says version " + std::to_string(version) + ")");
      }
      def.part->tip_cut = r.boolean(*cut, cp);
    }
  }

  const std::string sp = member(ptr, "sections");
  const Json& sections = r.required(v, ptr, "sections");
  r.array(sections, sp);
  if (sections.size() < 2)
    r.fail_at(sp, "a sweep needs at least 2 key sections, got " + std::to_string(sections.size()));
  if (sections.size() > static_cast<std::size_t>(limits::kMaxSections)) {
    r.fail_at(sp, "too many key sections: " + std::to_string(sections.size()) + ", at most " +
                      std::to_string(limits::kMaxSections));
  }
  def.rest.radial_count = n;
  std::set<std::string> names;
  std::vector<std::size_t> own_youngs;  // sections that give their own Young's modulus
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const std::string p = element(sp, i);
    const Json& s = sections[i];
    r.object(s, p, {"name", "t", "center", "rotation", "radii", "springs", "material"});
    std::string name;
    if (const Json* nm = r.optional(s, "name")) {
      name = r.string(*nm, member(p, "name"));
      if (!name.empty() && !names.insert(name).second)
        r.fail_at(member(p, "name"), "duplicate section name \"" + name + "\"");
    }
    const double t = r.bounded(r.required(s, p, "t"), member(p, "t"), -limits::kMaxLength, limits::kMaxLength);
    if (i == 0 && t != 0.0) r.fail_at(member(p, "t"), "the first section's t must be 0, got " + describe(s["t"]));
    if (i > 0 && !(t > def.rest.t.back())) {
      r.fail_at(member(p, "t"),
                "must be greater than the previous section's t (" + format_exact(def.rest.t.back()) + ")");
    }
    const Vec3 c = r.bounded_vec3(r.required(s, p, "center"), member(p, "center"), limits::kMaxLength);
    const Quat q = read_rotation(r, r.required(s, p, "rotation"), member(p, "rotation"));
    const Json& radii = r.required(s, p, "radii");
    const std::string rp = member(p, "radii");
    r.array(radii, rp);
    if (radii.size() != static_cast<std::size_t>(n)) {
      r.fail_at(rp, "expected " + std::to_string(n) + " radii (radial_samples), got " + std::to_string(radii.size()));
    }
    for (std::size_t j = 0; j < radii.size(); ++j) {
      def.rest.radii.push_back(positive_at_most(r, radii[j], element(rp, j), 0, limits::kMaxLength));
    }
    SectionSprings springs = def.default_springs;
    if (const Json* o = r.optional(s, "springs")) read_springs(r, *o, member(p, "springs"), springs);
    def.rest.t.push_back(t);
    def.rest.frames.push_back({q, c});
    def.section_names.push_back(name);
    def.springs.push_back(springs);
    if (const Json* m = r.optional(s, "material")) {
      if (!def.material)
        r.fail_at(member(p, "material"), "a section's material overrides the sweep's; the sweep has no \"material\"");
      Material mat = *def.material;
      read_material(r, *m, member(p, "material"), mat);
      if (r.optional(*m, "youngs_modulus_pa") != nullptr) own_youngs.push_back(i);
      if (mat.metres_per_unit != def.material->metres_per_unit)
        r.fail_at(member(p, "material") + "/metres_per_unit",
                  "the mesh's scale is the sweep's: set it on the sweep's material");
      def.section_materials.push_back(mat);
    } else if (def.material) {
      def.section_materials.push_back(*def.material);
    }
  }
  if (def.material && !request.youngs_modulus_given) {
    // The preset's E for this part, or with no preset the one that makes it sway at the default
    // frequency (a fixed modulus would leave a long part unable to hold itself): every section
    // takes it but those that give their own.
    request.material = *def.material;
    if (const std::string why = check_shape(def.rest); !why.empty()) r.fail_at(ptr, why);
    const double e = resolve_material(request, def.rest).youngs_modulus;
    if (request.preset == nullptr) {
      r.warn_at(member(ptr, "material"), "sweep \"" + def.name + "\" gives no \"youngs_modulus_pa\": it takes " +
                                             format_number(e, 4) + " Pa, which makes it sway at " +
                                             format_number(default_frequency_hz()) +
                                             " Hz (the tail preset's frequency, solved on its own sections)");
    }
    def.material->youngs_modulus = e;
    for (std::size_t i = 0; i < def.section_materials.size(); ++i) {
      if (std::find(own_youngs.begin(), own_youngs.end(), i) == own_youngs.end())
        def.section_materials[i].youngs_modulus = e;
    }
  }
  return def;
}

// --- writing ---------------------------------------------------------------------------------------

OrderedJson spring_json(const SpringSettings& s) {
  return {{"mass", s.mass}, {"frequency_hz", s.frequency_hz}, {"damping_ratio", s.damping_ratio}};
}

OrderedJson springs_json(const SectionSprings& s, const SectionSprings* base) {
  OrderedJson j = OrderedJson::object();
  auto put = [&](const char* key, const SpringSettings& v, const SpringSettings* b) {
    if (!b || !(v == *b)) j[key] = spring_json(v);
  };
  put("positional", s.positional, base ? &base->positional : nullptr);
  put("bend", s.bend, base ? &base->bend : nullptr);
  put("twist", s.twist, base ? &base->twist : nullptr);
  put("radial", s.radial, base ? &base->radial : nullptr);
  return j;
}

OrderedJson material_json(const Material& m, const Material* base) {
  OrderedJson j = OrderedJson::object();
  auto put = [&](const char* key, double v, double b, bool always = false) {
    if (!base || always || v != b) j[key] = v;
  };
  put("youngs_modulus_pa", m.youngs_modulus, base ? base->youngs_modulus : 0);
  // A section that sets its shear modulus another way than the sweep does must say so, even with
  // the same number (the sweep's unused Poisson ratio is no override).
  const bool other_way = base && (m.shear_modulus > 0) != (base->shear_modulus > 0);
  if (m.shear_modulus > 0) {
    put("shear_modulus_pa", m.shear_modulus, base ? base->shear_modulus : 0, other_way);
  } else {
    put("poisson_ratio", m.poisson_ratio, base ? base->poisson_ratio : 0, other_way);
  }
  put("density_kg_m3", m.density, base ? base->density : 0);
  if (!base) j["metres_per_unit"] = m.metres_per_unit;
  put("damping_ratio", m.damping_ratio, base ? base->damping_ratio : 0);
  return j;
}

OrderedJson vec_json(const Vec3& v) {
  return OrderedJson::array({v.x(), v.y(), v.z()});
}

OrderedJson sweep_json(const SweepDef& def) {
  OrderedJson j;
  j["name"] = def.name;
  j["radial_samples"] = def.rest.radial_count;
  j["springs"] = springs_json(def.default_springs, nullptr);
  if (def.material) j["material"] = material_json(*def.material, nullptr);
  j["force_scale"] = {{"rotational", def.rotational_scale}, {"radial", def.radial_scale}};
  if (def.part) {
    j["part"] = {{"root", vec_json(def.part->root)}, {"tip", vec_json(def.part->tip)}};
    if (def.part->tip_cut) j["part"]["tip_cut"] = true;
  }
  OrderedJson sections = OrderedJson::array();
  for (int i = 0; i < def.rest.section_count(); ++i) {
    OrderedJson s;
    if (!def.section_names[i].empty()) s["name"] = def.section_names[i];
    s["t"] = def.rest.t[i];
    s["center"] = vec_json(def.rest.frames[i].center);
    const Quat& q = def.rest.frames[i].rotation;
    s["rotation"] = OrderedJson::array({q.x(), q.y(), q.z(), q.w()});
    const auto radii = def.rest.section_radii(i);
    s["radii"] = OrderedJson(std::vector<double>(radii.begin(), radii.end()));
    OrderedJson overrides = springs_json(def.springs[i], &def.default_springs);
    if (!overrides.empty()) s["springs"] = std::move(overrides);
    if (def.material) {
      OrderedJson m = material_json(def.section_materials[i], &*def.material);
      if (!m.empty()) s["material"] = std::move(m);
    }
    sections.push_back(std::move(s));
  }
  j["sections"] = std::move(sections);
  return j;
}

// "mesh_name": one mesh's name (version 3), or the names of several, in the order their vertices
// are concatenated (version 4), as Rig::mesh_name holds them (mesh_names.h).
std::string read_mesh_names(const JsonReader& r, const Json& v, long long version) {
  const bool list = v.is_array();
  const int needs = list ? kMeshListFormatVersion : Rig::kMeshNameFormatVersion;
  if (version < needs) {
    r.fail_at("/mesh_name", std::string(list ? "a list of meshes needs" : "needs") + " rig format version " +
                                std::to_string(needs) + " (the file says version " + std::to_string(version) + ")");
  }
  std::vector<std::string> names;
  const auto one = [&](const Json& name, const std::string& ptr) {
    names.push_back(r.string(name, ptr));
    if (names.back().empty()) r.fail_at(ptr, "must not be empty (leave mesh_name out for the whole file)");
    if (names.back().find(kMeshNameSeparator) != std::string::npos) r.fail_at(ptr, "must not hold a NUL character");
    for (std::size_t k = 0; k + 1 < names.size(); ++k) {
      if (names[k] == names.back())
        r.fail_at(ptr, "names the mesh '" + names.back() + "' again (it is /mesh_name/" + std::to_string(k) + ")");
    }
  };
  if (!list) {
    one(v, "/mesh_name");
  } else {
    r.array(v, "/mesh_name");
    if (v.empty()) r.fail_at("/mesh_name", "must not be empty (leave it out for the whole file)");
    for (std::size_t i = 0; i < v.size(); ++i) one(v[i], element("/mesh_name", i));
  }
  return join_mesh_names(names);
}

}  // namespace

Rig parse_rig(const std::string& text, const std::string& source, const WarningSink& warn) {
  const Json doc = parse_json_text(text, source);
  const JsonReader r(source, warn);
  // The format and version first: a file that is not a rig (a scene, say) gets one error, not a
  // warning for each of its members before it.
  if (!doc.is_object()) r.fail_at("", "must be an object, got " + describe(doc));
  const std::string format = r.string(r.required(doc, "", "format"), "/format");
  if (format != kFormatName)
    r.fail_at("/format", std::string("must be \"") + kFormatName + "\", got " + describe(doc["format"]));
  const long long version = r.integer(r.required(doc, "", "version"), "/version", 1, 1 << 30);
  if (version < Rig::kFormatVersion || version > kMeshListFormatVersion) {
    fail(ErrorCategory::unsupported, source + ": /version: rig format version " + std::to_string(version) +
                                         " is not supported (this build reads versions " +
                                         std::to_string(Rig::kFormatVersion) + " to " +
                                         std::to_string(kMeshListFormatVersion) + ")");
  }
  r.object(doc, "", {"format", "version", "mesh", "mesh_name", "sweeps", "scene"});
  Rig rig;
  if (const Json* m = r.optional(doc, "mesh")) rig.mesh = r.string(*m, "/mesh");
  if (const Json* m = r.optional(doc, "mesh_name")) rig.mesh_name = read_mesh_names(r, *m, version);
  if (const Json* s = r.optional(doc, "scene")) rig.scene_json = s->dump();
  const Json& sweeps = r.required(doc, "", "sweeps");
  r.array(sweeps, "/sweeps");
  std::set<std::string> names;
  for (std::size_t i = 0; i < sweeps.size(); ++i) {
    SweepDef def = read_sweep(r, sweeps[i], element("/sweeps", i), version);
    if (!names.insert(def.name).second)
      r.fail_at(element("/sweeps", i) + "/name", "duplicate sweep name \"" + def.name + "\"");
    // Whatever the reader let through must satisfy the evaluator's invariants.
    if (const std::string why = check_shape(def.rest); !why.empty()) r.fail_at(element("/sweeps", i), why);
    rig.sweeps.push_back(std::move(def));
  }
  return rig;
}

Rig read_rig(const std::filesystem::path& path, const WarningSink& warn) {
  return parse_rig(read_file(path, limits::kMaxJsonBytes), path.string(), warn);
}

Material parse_material(const std::string& text, const std::string& source, const WarningSink& warn) {
  const Json doc = parse_json_text(text, source);
  const JsonReader r(source, warn);
  if (!doc.is_object()) r.fail_at("", "must be an object of material members, got " + describe(doc));
  Material m;
  read_material(r, doc, "", m);
  return m;
}

Material read_material_file(const std::filesystem::path& path, const WarningSink& warn) {
  return parse_material(read_file(path, limits::kMaxJsonBytes), path.string(), warn);
}

MaterialRequest parse_material_request(const std::string& text, const std::string& source, const Preset* preset,
                                       const WarningSink& warn) {
  const Json doc = parse_json_text(text, source);
  const JsonReader r(source, warn);
  if (!doc.is_object()) r.fail_at("", "must be an object of material members, got " + describe(doc));
  MaterialRequest request;
  request.preset = preset;
  if (preset != nullptr) request.material = preset_base(*preset);
  if (preset != nullptr && r.optional(doc, "preset") != nullptr)
    r.fail_at("/preset", "the preset is given twice (--preset and the file): give it once");
  read_material(r, doc, "", request.material, &request);
  return request;
}

MaterialRequest read_material_request(const std::filesystem::path& path, const Preset* preset,
                                      const WarningSink& warn) {
  return parse_material_request(read_file(path, limits::kMaxJsonBytes), path.string(), preset, warn);
}

std::string format_rig(const Rig& rig) {
  OrderedJson doc;
  doc["format"] = kFormatName;
  // A list of meshes is version 4 (one name is Rig::format_version's 3).
  doc["version"] = several_mesh_names(rig.mesh_name) ? kMeshListFormatVersion : rig.format_version();
  if (!rig.mesh.empty()) doc["mesh"] = rig.mesh;
  if (several_mesh_names(rig.mesh_name)) {
    doc["mesh_name"] = split_mesh_names(rig.mesh_name);
  } else if (!rig.mesh_name.empty()) {
    doc["mesh_name"] = rig.mesh_name;
  }
  OrderedJson sweeps = OrderedJson::array();
  for (const SweepDef& def : rig.sweeps) sweeps.push_back(sweep_json(def));
  doc["sweeps"] = std::move(sweeps);
  if (!rig.scene_json.empty()) doc["scene"] = OrderedJson::parse(rig.scene_json);
  // Names come from the command line too (sweep-fit --name, the mesh path): JSON text must be
  // UTF-8, so other bytes are a usage error, not nlohmann's type_error (an "internal" exit).
  try {
    return doc.dump(2) + "\n";
  } catch (const nlohmann::json::type_error&) {
    fail(ErrorCategory::usage,
         "a sweep name or the mesh path is not valid UTF-8; a rig file is "
         "JSON text and can only hold UTF-8 names");
  }
}

std::filesystem::path resolve_mesh_path(const std::filesystem::path& rig_path, const Rig& rig) {
  const std::filesystem::path mesh(rig.mesh);
  if (mesh.is_absolute()) return mesh;
  return (rig_path.parent_path() / mesh).lexically_normal();
}

std::string mesh_path_for_rig(const std::filesystem::path& rig_path, const std::filesystem::path& mesh_path) {
  namespace fs = std::filesystem;
  const fs::path base = fs::absolute(rig_path).parent_path();
  return fs::absolute(mesh_path).lexically_normal().lexically_relative(base.lexically_normal()).generic_string();
}

void write_rig(const std::filesystem::path& path, const Rig& rig) {
  write_file_atomically(path, format_rig(rig));
}

}  // namespace sweep::io
