// sweep-fit: fits a sweep (key cross sections and radius samples) to a tubular part of a mesh,
// named by a tip point (and optionally a root point), and writes it into a rig file (created, or
// updated by adding or replacing the sweep of that name). --list finds the mesh's parts, --all
// fits them all. The work is in lib/fit/ (fit.h, discover.h); report.h prints and reports.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <chrono>
#include <filesystem>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "common/cli_checks.h"
#include "common/tool_main.h"
#include "sweep-fit/report.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/core/error.h"
#include "sweep/core/held_rest.h"
#include "sweep/core/limits.h"
#include "sweep/core/presets.h"
#include "sweep/core/sway.h"
#include "sweep/core/text.h"
#include "sweep/fit/discover.h"
#include "sweep/fit/fit.h"
#include "sweep/fit/hole_patches.h"
#include "sweep/fit/offered_parts.h"
#include "sweep/io/atomic_file.h"
#include "sweep/io/interrupt.h"
#include "sweep/io/mesh_names.h"
#include "sweep/io/read_file.h"
#include "sweep/io/rig_json.h"
#include "sweep/preview/png.h"
#include "sweep/preview/render.h"
#include "tools/common/path_checks.h"
#include "tools/common/update_lock.h"

namespace fs = std::filesystem;
using sweep::ErrorCategory;
using sweep::fail;
using sweep::Vec3;

namespace {

struct Settings {
  fs::path mesh;  // input mesh (any format assets::read_mesh reads)
  // --mesh, once or more: which meshes of the file, as one (joined: io/mesh_names.h; "" = the rig's,
  // or the only or largest one).
  std::vector<std::string> mesh_names;
  std::string mesh_name;
  std::string space = "world";   // --space: what --root, --tip and --axis are in (world, local)
  fs::path rig;                  // rig file to create or update
  std::string name = "part";     // the sweep's name in the rig
  std::string root, tip;         // X,Y,Z in mesh units (root optional: found where the part meets the body)
  std::int64_t tip_vertex = -1;  // the tip as a vertex index
  std::string tip_vertex_text;   // --tip-vertex as given (read by tip_vertex_index)
  bool root_given = false, tip_given = false;  // --root, --tip given (even empty: refused)
  bool quiet = false;                          // -q: no notes
  bool force = false;                          // write the rig even when the fit breaks a limit
  fs::path axis;                               // optional axis polyline: "X Y Z" (or X,Y,Z) per line, root first
  int sections = sweep::fit::FitOptions{}.sections;
  int radial = sweep::fit::FitOptions{}.radial;
  double tolerance = 0;  // > 0: fewest sections with fit_rms ≤ tolerance × mean radius
  fs::path report;       // optional JSON report
  bool verbose = false;
  bool list = false;       // --list: print the parts found, write no rig
  bool all = false;        // --all: fit every part found into the rig
  std::string names;       // --names a,b,c for --all
  std::string only, skip;  // --only / --skip a,b,c for --all: parts by their suggested names
  std::string up = "Y";    // --up: the up axis the suggested names go by
  bool up_given = false;   // else the file's own (assets::FileUp)
  fs::path preview;        // optional PNG: the fit drawn over the mesh from three sides
  fs::path material;       // optional material file: the fitted sweeps move in material mode
  std::string preset;      // --preset: a material preset (core/presets.h), the file's members over it
  bool springs = false;    // --springs: the paper's springs, not a preset chosen by the part's name
  fs::path export_obj;     // --export-obj: the mesh as read, to this OBJ (no fit)
};

// "X,Y,Z" → a point; our own parse so that the message names the flag and the text given.
Vec3 to_point(const std::string& text, const char* flag) {
  Vec3 p;
  std::size_t at = 0;
  bool ok = true;
  for (int i = 0; i < 3 && ok; ++i) {
    const std::size_t end = i < 2 ? text.find(',', at) : text.size();
    const std::string field = text.substr(at, end == std::string::npos ? end : end - at);
    char* stop = nullptr;
    p[i] = field.empty() ? 0 : std::strtod(field.c_str(), &stop);
    ok = !field.empty() && stop == field.c_str() + field.size() && std::isfinite(p[i]) && end != std::string::npos;
    at = end + 1;
  }
  if (!ok) {  // (a fourth number stays in the third field and fails its parse)
    fail(ErrorCategory::usage, std::string(flag) + " expects three finite numbers X,Y,Z, got '" + text + "'");
  }
  return p;
}

std::vector<Vec3> read_axis(const fs::path& path) {
  std::istringstream in(sweep::io::read_text_file(path));
  std::vector<Vec3> points;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    for (char& c : line)
      if (c == ',') c = ' ';
    std::istringstream fields(line);
    Vec3 p;
    if (!(fields >> p.x())) continue;  // blank line
    if (!(fields >> p.y() >> p.z()) || !p.allFinite()) {
      fail(ErrorCategory::bad_input, path.string() + ":" + std::to_string(number) + ": expected X Y Z");
    }
    points.push_back(p);
  }
  if (points.size() < 2) fail(ErrorCategory::bad_input, path.string() + ": an axis needs at least 2 points");
  return points;
}

// "a,b,c" → names (empty: none given); each must be a non-empty UTF-8 name, given once.
std::vector<std::string> split_names(const std::string& text, const std::string& flag = "--names") {
  std::vector<std::string> names;
  if (text.empty()) return names;
  std::size_t at = 0;
  for (;;) {
    const std::size_t comma = text.find(',', at);
    names.push_back(text.substr(at, comma == std::string::npos ? comma : comma - at));
    if (names.back().empty()) fail(ErrorCategory::usage, flag + ": an empty name in '" + text + "'");
    sweep::tools::check_utf8(names.back(), flag);
    // Two parts of one name would be one sweep in the rig: the second would replace the first.
    for (std::size_t k = 0; k + 1 < names.size(); ++k) {
      if (names[k] == names.back()) {
        fail(ErrorCategory::usage, flag + ": '" + names.back() + "' is given twice (parts " + std::to_string(k + 1) +
                                       " and " + std::to_string(names.size()) + " in '" + text +
                                       "'); a rig holds one sweep a name");
      }
    }
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  return names;
}

// The rig's mesh path: relative to the rig file's folder.
std::string mesh_path_for(const fs::path& rig, const fs::path& mesh) {
  const fs::path rig_dir = fs::weakly_canonical(fs::absolute(rig)).parent_path();
  return fs::weakly_canonical(fs::absolute(mesh)).lexically_relative(rig_dir).generic_string();
}

// --tip-vertex's text as a vertex index: a whole number below the vertex limit (core/limits.h),
// the text quoted back as given when it is not one.
std::int64_t tip_vertex_index(const std::string& text) {
  std::string why;
  const std::optional<std::uint64_t> v = sweep::tools::read_whole(text, why);
  if (!v) fail(ErrorCategory::usage, "--tip-vertex " + why);
  if (*v > sweep::limits::kMaxVertices) {
    fail(ErrorCategory::usage, "--tip-vertex " + text + " is past the vertices of any mesh (a mesh has at most " +
                                   std::to_string(sweep::limits::kMaxVertices) + ")");
  }
  return static_cast<std::int64_t>(*v);
}

// Reads the rig to update (when -o exists), so that a bad rig fails before any work; checks that
// it is a rig of this mesh (file, and the mesh of it --mesh names).
sweep::Rig open_rig(const Settings& s, bool& updating) {
  sweep::Rig rig;
  // A folder, FIFO or device under the rig's name is an output that cannot be written (exit 4),
  // not a rig to read (exit 2): TempFile's check says so.
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(s.rig, ec);
  if (!ec && fs::exists(st) && !fs::is_regular_file(st)) sweep::io::check_can_create(s.rig);
  updating = !s.rig.empty() && fs::exists(s.rig);
  if (updating) {
    rig = sweep::io::read_rig(s.rig, sweep::tools::warn);
    const fs::path rig_dir = fs::absolute(s.rig).parent_path();
    if (fs::weakly_canonical(rig_dir / rig.mesh) != fs::weakly_canonical(fs::absolute(s.mesh))) {
      fail(ErrorCategory::usage, s.rig.string() + " is a rig of mesh '" + rig.mesh + "', not of " + s.mesh.string() +
                                     "; write to another --rig file");
    }
    // (--mesh against the rig's mesh: read_checked_mesh, once the name is resolved to a node.)
  }
  rig.mesh = mesh_path_for(s.rig, s.mesh);
  return rig;
}

// Two runs updating one rig take turns from reading it to writing it back, so neither drops the
// sweep the other adds (io/update_lock.h). The rig's folder is checked first, for the message
// every output gives when it cannot be written there.
struct RigUpdate {
  explicit RigUpdate(const Settings& s) : lock((sweep::io::check_can_create(s.rig), s.rig)) {}
  sweep::tools::UpdateLock lock;
};

// Gives every section of `def` the sweep's material `m` (or none).
void set_material(sweep::SweepDef& def, const std::optional<sweep::Material>& m) {
  def.material = m;
  def.section_materials.assign(m ? def.rest.section_count() : 0, m.value_or(sweep::Material{}));
}

// Adds `def` to the rig, or replaces the sweep of its name keeping the user's spring settings,
// material and force scales (per-section overrides no longer apply: the sections are new). A
// material given now (--material, --preset, or the preset its name chose) replaces the sweep's;
// `springs` (--springs) drops it. A part whose stiffness was solved for a preset's frequency and
// that must hold its modelled pose is stiffened to hold it under `gravity` (core/held_rest.h);
// `stiffened` then gets its held rest as the frequency left it. True when it replaced one.
bool put_sweep(sweep::Rig& rig, sweep::SweepDef def, const std::optional<sweep::MaterialRequest>& request, bool springs,
               const Vec3& gravity, std::optional<sweep::HeldRest>& stiffened) {
  // A preset's stiffness is the part's own: solved on this sweep's sections.
  const std::optional<sweep::Material> material =
      request ? std::optional(sweep::resolve_material(*request, def.rest)) : std::nullopt;
  set_material(def, material);
  if (material && !request->youngs_modulus_given && material->shear_modulus <= 0 &&
      (request->preset == nullptr || request->preset->holds_its_pose)) {
    const sweep::HeldRest given = sweep::stiffen_to_hold(def, gravity, sweep::kPresetLoadFactor);
    if (given.load_factor > sweep::kPresetLoadFactor) stiffened = given;
  }
  for (sweep::SweepDef& old : rig.sweeps) {
    if (old.name != def.name) continue;
    def.default_springs = old.default_springs;
    def.springs.assign(def.springs.size(), def.default_springs);
    if (!material && !springs) set_material(def, old.material);
    def.rotational_scale = old.rotational_scale;
    def.radial_scale = old.radial_scale;
    old = std::move(def);
    return true;
  }
  rig.sweeps.push_back(std::move(def));
  return false;
}

std::optional<sweep::MaterialRequest> read_material_option(const Settings& s) {
  const sweep::Preset* preset = nullptr;
  if (!s.preset.empty()) {
    preset = sweep::find_preset(s.preset);
    if (preset == nullptr)
      fail(ErrorCategory::usage, "--preset: unknown preset '" + s.preset + "': one of " + sweep::preset_names());
  }
  if (s.material.empty()) {
    if (preset == nullptr) return std::nullopt;
    return sweep::MaterialRequest{sweep::preset_base(*preset), preset, false};
  }
  return sweep::io::read_material_request(s.material, preset, sweep::tools::warn);
}

// The direction the suggested names go by: --up, else the file's own up (glTF's +Y, an FBX's
// GlobalSettings, a Collada file's up_axis, a Z-up format's convention; +Y when neither the file
// nor its format states one), and why.
struct NamesUp {
  Vec3 direction;
  std::string why;
};
NamesUp names_up(const Settings& s, const sweep::assets::SceneMesh& read) {
  if (!s.up_given) return {read.up.direction, read.up.why};
  return {s.up == "X" ? Vec3::UnitX() : s.up == "Z" ? Vec3::UnitZ() : Vec3::UnitY(), "given by --up"};
}

sweep::fit::DiscoverOptions discover_options(const NamesUp& up) {
  sweep::fit::DiscoverOptions o;
  o.up = up.direction;
  return o;
}

// The parts --all fits: those --only names, or all but those --skip names (by the names --list
// suggests). A name no part has is refused with the names there are.
std::vector<sweep::fit::FoundPart> chosen_parts(const Settings& s, std::vector<sweep::fit::FoundPart> parts) {
  const bool only = !s.only.empty();
  const std::vector<std::string> given = split_names(only ? s.only : s.skip, only ? "--only" : "--skip");
  if (given.empty()) return parts;
  std::string found;
  for (const sweep::fit::FoundPart& p : parts) found += (found.empty() ? "" : ", ") + p.name;
  for (const std::string& name : given) {
    if (std::none_of(parts.begin(), parts.end(), [&](const sweep::fit::FoundPart& p) { return p.name == name; })) {
      fail(ErrorCategory::usage, std::string(only ? "--only" : "--skip") + ": no part found is named '" + name +
                                     "' (the parts found: " + found + "; see --list)");
    }
  }
  std::erase_if(parts, [&](const sweep::fit::FoundPart& p) {
    return (std::find(given.begin(), given.end(), p.name) != given.end()) != only;
  });
  if (parts.empty()) fail(ErrorCategory::usage, "--skip leaves no part to fit (the parts found: " + found + ")");
  return parts;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

sweep::fit::FitOptions fit_options(const Settings& s) {
  sweep::fit::FitOptions o;
  o.name = s.name;
  o.sections = s.sections;
  o.radial = s.radial;
  o.tolerance = s.tolerance;
  return o;
}

// The mesh read, and what the report and -v say about it.
struct ReadMesh {
  sweep::assets::SceneMesh read;
  sweep::fit_tool::MeshSummary summary;
  const sweep::Mesh& mesh() const { return read.mesh; }
};

// The mesh of the file to fit: --mesh, else the rig's being updated (the whole file for a rig
// that names none), else the only one, else of several: for --list and --all all of them as one
// (a creature whose legs are meshes of their own is searched whole), for one part the largest
// (said in a note). Records it in `rig`.
ReadMesh read_checked_mesh(const Settings& s, sweep::Rig* rig = nullptr, bool updating = false) {
  const bool rigs = updating && rig != nullptr;
  const std::string name = !s.mesh_name.empty() ? s.mesh_name : rigs ? rig->mesh_name : "";
  ReadMesh m;
  // Several --mesh are taken in the file's order, whatever order they were given in; a rig's list
  // in its own.
  const sweep::assets::MeshPick pick = rigs              ? sweep::assets::MeshPick::whole_file
                                       : s.list || s.all ? sweep::assets::MeshPick::every_mesh
                                                         : sweep::assets::MeshPick::only_or_largest;
  m.read = sweep::assets::read_scene_mesh(s.mesh, name, pick, /*file_order=*/!s.mesh_name.empty());
  sweep::assets::validate_mesh(m.read.mesh, s.mesh.string());
  std::string taken;
  if (!s.mesh_name.empty())
    taken = "named by --mesh";
  else if (rigs && !name.empty())
    taken = "the rig's mesh";
  else if (m.read.largest)
    taken = "the largest";
  else if (m.read.every)
    taken = "every mesh of the file, as one";
  else if (!m.read.name.empty())
    taken = "the only one";
  else if (m.read.meshes.size() > 1)
    taken = "the whole file: the rig being updated names no mesh";
  m.summary = sweep::fit_tool::summarize_mesh(s.mesh, m.read, taken);
  m.summary.seeds_local = s.space == "local";
  if (s.verbose) sweep::fit_tool::print_mesh_summary(s.mesh, m.summary);
  if (const std::string note = sweep::fit_tool::mesh_choice_note(s.mesh, m.summary); !note.empty()) {
    sweep::io::note(note);
  }
  // --mesh may name the rig's mesh by its node's name (what the rig records) or by its mesh's.
  if (rigs && !s.mesh_name.empty() && m.read.name != rig->mesh_name && s.mesh_name != rig->mesh_name) {
    fail(ErrorCategory::usage,
         "--mesh " + (s.mesh_names.size() > 1 ? sweep::io::quoted_mesh_names(s.mesh_name) : s.mesh_name) + ": " +
             s.rig.string() + " is a rig of " +
             (rig->mesh_name.empty() ? "the whole file" : "its " + sweep::assets::asked_meshes(rig->mesh_name)) +
             "; write to another --rig file");
  }
  if (rig != nullptr) rig->mesh_name = m.read.name;
  return m;
}

// The report and the preview (--report, --preview), which are written also when a fit fails, to
// show what went wrong; with the rig when it is written, all in place together or none.
void add_report_and_preview(sweep::io::Publication& outputs, const Settings& s, const ReadMesh& read,
                            const std::vector<sweep::fit::FitResult>& fits, bool rig_written, double seconds,
                            const sweep::Error* failure = nullptr) {
  const sweep::Mesh& mesh = read.mesh();
  if (!s.report.empty()) {
    outputs.add(s.report,
                sweep::fit_tool::fit_report_text(s.mesh, read.summary, s.rig, fits, rig_written, seconds, failure));
  }
  if (!s.preview.empty()) {
    std::vector<sweep::preview::Overlay> parts;
    for (const sweep::fit::FitResult& r : fits) {
      parts.push_back({r.part_vertices, r.axis.points, sweep::preview::section_outlines(r.sweep.rest)});
    }
    outputs.add(s.preview, sweep::preview::encode_png(sweep::preview::render_views(mesh, parts)));
  }
}

// Warnings, then the problems: a fit that breaks a limit fails (exit 2) with the numbers and
// what to try, after writing the report, unless --force.
void check_problems(const Settings& s, const ReadMesh& mesh, const std::vector<sweep::fit::FitResult>& fits,
                    double seconds) {
  std::string all;
  for (const sweep::fit::FitResult& r : fits) {
    for (const std::string& w : r.warnings) sweep::tools::warn(r.sweep.name + ": " + w);
    if (r.problems.empty()) continue;
    all += "\n" + r.sweep.name + ": the fit is not to be trusted:";
    for (const std::string& p : r.problems) all += "\n  " + p;
  }
  if (all.empty()) return;
  if (!s.force) {
    sweep::io::Publication outputs;
    add_report_and_preview(outputs, s, mesh, fits, false, seconds);
    outputs.commit();
    fail(ErrorCategory::bad_input, all.substr(1) + "\n  (--force writes the rig anyway)");
  }
  sweep::tools::warn("written anyway (--force):" + all);
}

// Runs `fit` (the work once the mesh is read and the outputs checked), which appends to `fits`. A
// run that fails there still writes the report (and preview) with the error and what was fitted:
// for a FitFailure, the fit as far as it got. Output errors are left as they are (the report
// could not be written either).
void fitting(const Settings& s, const ReadMesh& mesh, std::vector<sweep::fit::FitResult>& fits,
             std::chrono::steady_clock::time_point start, const std::function<void()>& fit) {
  try {
    fit();
  } catch (const sweep::Error& e) {
    if (e.category() == ErrorCategory::output || (s.report.empty() && s.preview.empty())) throw;
    std::vector<sweep::fit::FitResult> shown = fits;
    if (const auto* failure = dynamic_cast<const sweep::fit::FitFailure*>(&e)) {
      shown.push_back(failure->partial());
      shown.back().problems.push_back(e.what());
    }
    try {
      sweep::io::Publication outputs;
      add_report_and_preview(outputs, s, mesh, shown, false, seconds_since(start), &e);
      outputs.commit();
    } catch (const sweep::Error& not_written) {
      sweep::tools::warn(std::string("the report of the failure was not written: ") + not_written.what());
    }
    throw;
  }
}

// The material a fitted part takes: --material or --preset as given; none with --springs or for a
// sweep the rig already holds (it keeps its own settings); else the preset its name chooses, with
// why in `chosen` (printed).
std::optional<sweep::MaterialRequest> material_for(const Settings& s, const sweep::Rig& rig, const std::string& name,
                                                   const std::optional<sweep::MaterialRequest>& given,
                                                   std::string& chosen) {
  if (given || s.springs || rig.find(name) != nullptr) return given;
  const sweep::PresetChoice choice = sweep::preset_for_name(name);
  chosen = "  " + name + ": preset " + std::string(choice.preset->name) + " (" + choice.why +
           "; --preset or --material choose another, --springs keeps the paper's springs)";
  return sweep::MaterialRequest{sweep::preset_base(*choice.preset), choice.preset, false};
}

void write_outputs(const Settings& s, const ReadMesh& mesh, sweep::Rig& rig, bool updating,
                   const std::optional<sweep::MaterialRequest>& material,
                   const std::vector<sweep::fit::FitResult>& fits, std::chrono::steady_clock::time_point start) {
  int replaced = 0;
  std::vector<std::string> chosen(fits.size());
  std::vector<std::optional<sweep::HeldRest>> stiffened(fits.size());
  const NamesUp up = names_up(s, mesh.read);
  const Vec3 gravity = -sweep::kStandardGravity * up.direction;
  for (std::size_t i = 0; i < fits.size(); ++i) {
    const std::optional<sweep::MaterialRequest> request = material_for(s, rig, fits[i].sweep.name, material, chosen[i]);
    replaced += put_sweep(rig, fits[i].sweep, request, s.springs, gravity, stiffened[i]);
    if (request && request->preset == nullptr && !request->youngs_modulus_given) {
      sweep::tools::warn(s.material.string() + " gives no youngs_modulus_pa: sweep \"" + fits[i].sweep.name +
                         "\" takes " + sweep::format_number(rig.find(fits[i].sweep.name)->material->youngs_modulus, 4) +
                         " Pa, which makes it sway at " + sweep::format_number(sweep::default_frequency_hz()) +
                         " Hz (the tail preset's frequency, solved on its own sections)");
    }
  }
  const double seconds = seconds_since(start);
  const std::string text = sweep::io::format_rig(rig);
  // Never write a rig that sweep-bind refuses: one read back through the rig reader's limits
  // (a mesh a glTF node scales by 1e30 gives sections far past the ±1e9 of any length).
  try {
    sweep::io::parse_rig(text, s.rig.string());
  } catch (const sweep::Error& e) {
    fail(ErrorCategory::bad_input, s.mesh.string() + ": the fitted rig would break the rig format's limits (" +
                                       e.what() + "); nothing written. Scale the mesh into range first");
  }
  sweep::io::Publication outputs;
  outputs.add(s.rig, text);
  add_report_and_preview(outputs, s, mesh, fits, true, seconds);
  outputs.commit();
  if (s.quiet) return;  // -q: nothing on success, as the other tools
  for (std::size_t i = 0; i < fits.size(); ++i) {
    const sweep::fit::FitResult& r = fits[i];
    sweep::fit_tool::print_fit(r, s.verbose);
    if (!chosen[i].empty()) std::cout << chosen[i] << "\n";
    if (const auto& held = stiffened[i]) {
      std::cout << "  " << r.sweep.name << ": stiffened "
                << sweep::format_number(held->load_factor / sweep::kPresetLoadFactor, 3)
                << "x to hold its modelled pose under its own weight twice over (solved for its sway frequency alone, "
                << "it would need " << sweep::format_number(held->load_factor, 3)
                << "x its stiffness just to hold it; gravity against the mesh's up, " << up.why << ")\n";
    }
    // What a material gives it (a preset's E was solved for its frequency): how fast it sways.
    const sweep::SweepDef* def = rig.find(r.sweep.name);
    if (def == nullptr || !def->material) continue;
    const sweep::SwayFigures sway = sweep::sway_figures(*def, Vec3::Zero());
    std::cout << "  " << def->name << ": material E " << sweep::format_number(def->material->youngs_modulus, 4)
              << " Pa, first sway";
    for (std::size_t m = 0; m < sway.frequencies_hz.size(); ++m)
      std::cout << (m ? ", " : " ") << sweep::format_number(sway.frequencies_hz[m], 3);
    std::cout << " Hz\n";
  }
  std::cout << (replaced > 0 ? "replaced in "
                : updating   ? "added to "
                             : "wrote ")
            << s.rig.string() << " (" << rig.sweeps.size() << (rig.sweeps.size() == 1 ? " sweep" : " sweeps") << ") in "
            << sweep::format_number(seconds, 3) << " s\n";
}

// The rig, report and preview are checked before the fit, so none is written when another cannot
// be, and named for an interrupt's message ("not written: ...").
void check_outputs(const Settings& s) {
  sweep::io::check_can_create(s.rig);
  if (!s.report.empty()) sweep::io::check_can_create(s.report);
  if (!s.preview.empty()) sweep::io::check_can_create(s.preview);
  sweep::io::declare_outputs({s.rig, s.report, s.preview});
}

// One part, named by its tip (and root, or an axis).
int run_one(const Settings& s) {
  const auto start = std::chrono::steady_clock::now();
  sweep::tools::check_utf8(s.name, "--name");
  sweep::tools::check_paths({{"the mesh", s.mesh}, {"--axis", s.axis}, {"--material", s.material}},
                            {{"-o", s.rig}, {"--report", s.report}, {"--preview", s.preview}});
  const std::optional<sweep::MaterialRequest> material = read_material_option(s);
  sweep::fit::FitOptions o = fit_options(s);
  if (!s.axis.empty()) o.axis = read_axis(s.axis);
  if (s.root_given) o.root = to_point(s.root, "--root");
  if (s.tip_given) o.tip = to_point(s.tip, "--tip");
  o.tip_vertex = s.tip_vertex;
  bool updating = false;
  const RigUpdate lock(s);
  sweep::Rig rig = open_rig(s, updating);
  const ReadMesh mesh = read_checked_mesh(s, &rig, updating);
  if (s.space == "local") {
    // A rig that names no mesh reads the whole of a scene file: many nodes, no one local space.
    if (sweep::io::several_mesh_names(mesh.read.name)) {
      fail(ErrorCategory::usage, "--space local: " + s.mesh.string() + "'s " +
                                     sweep::assets::asked_meshes(mesh.read.name) +
                                     " are read as one in world space, each placed by its own node; there is no one "
                                     "local space: give the points in world space");
    }
    if (mesh.read.name.empty() && !mesh.read.meshes.empty()) {
      fail(ErrorCategory::usage, "--space local: " + s.rig.string() + " names no mesh, so it reads the whole of " +
                                     s.mesh.string() + " in world space (" +
                                     sweep::assets::list_scene_meshes(mesh.read.meshes) +
                                     "); give the points in world space, or fit into a new rig with --mesh NAME");
    }
    // The points are in the mesh's own space: its node's world transform takes them to the world
    // space the mesh (and the rig) are in.
    const Eigen::Affine3d& to_world = mesh.read.to_world;
    if (o.root) o.root = to_world * *o.root;
    if (s.tip_given) o.tip = to_world * o.tip;
    for (Vec3& p : o.axis) p = to_world * p;
  }
  check_outputs(s);
  std::vector<sweep::fit::FitResult> fits;
  fitting(s, mesh, fits, start, [&] { fits.push_back(sweep::fit::fit_sweep(mesh.mesh(), o)); });
  check_problems(s, mesh, fits, seconds_since(start));
  write_outputs(s, mesh, rig, updating, material, fits, start);
  return 0;
}

// Every part find_parts finds, into one rig.
int run_all(const Settings& s) {
  const auto start = std::chrono::steady_clock::now();
  sweep::tools::check_paths({{"the mesh", s.mesh}, {"--material", s.material}},
                            {{"-o", s.rig}, {"--report", s.report}, {"--preview", s.preview}});
  const std::optional<sweep::MaterialRequest> material = read_material_option(s);
  const std::vector<std::string> names = split_names(s.names);
  bool updating = false;
  const RigUpdate lock(s);
  sweep::Rig rig = open_rig(s, updating);
  const ReadMesh mesh = read_checked_mesh(s, &rig, updating);
  check_outputs(s);
  std::vector<sweep::fit::FitResult> fits;
  fitting(s, mesh, fits, start, [&] {
    const sweep::fit::SweepFitter fitter(mesh.mesh());
    // The parts --list offers, each fitted once while they are found (fit/offered_parts.h).
    sweep::fit::OfferedParts offered =
        sweep::fit::find_fitting_parts(mesh.mesh(), fitter, discover_options(names_up(s, mesh.read)), fit_options(s));
    const std::vector<sweep::fit::FoundPart>& found = offered.parts;
    if (found.empty()) {
      fail(ErrorCategory::bad_input,
           s.mesh.string() + ": " + sweep::fit_tool::no_parts_found(sweep::hole_edge_count(fitter.patched_topology())));
    }
    const std::vector<sweep::fit::FoundPart> parts = chosen_parts(s, found);
    if (!names.empty() && names.size() != parts.size()) {
      fail(ErrorCategory::usage,
           "--names gives " + std::to_string(names.size()) + " names for the " + std::to_string(parts.size()) +
               " parts " + (parts.size() == found.size() ? "found (see --list)" : "chosen by --only or --skip"));
    }
    for (std::size_t i = 0; i < parts.size(); ++i) {
      const auto k = static_cast<std::size_t>(
          std::find_if(found.begin(), found.end(),
                       [&](const sweep::fit::FoundPart& p) { return p.tip_vertex == parts[i].tip_vertex; }) -
          found.begin());
      sweep::fit::FitResult& fit = offered.fits[k];
      if (!names.empty()) fit.sweep.name = names[i];
      if (s.verbose) std::cout << "fitted " << fit.sweep.name << " (" << i + 1 << "/" << parts.size() << ")\n";
      fits.push_back(std::move(fit));
    }
    if (fits.empty()) fail(ErrorCategory::bad_input, s.mesh.string() + ": no part could be fitted");
  });
  check_problems(s, mesh, fits, seconds_since(start));
  write_outputs(s, mesh, rig, updating, material, fits, start);
  return 0;
}

// The mesh as the tools read it (world space, their vertex order, polygons as read) to an OBJ, for
// a viewer that reads no FBX (tools/sweep-preview.py); no fit.
int run_export(const Settings& s) {
  sweep::tools::check_paths({{"the mesh", s.mesh}}, {{"--export-obj", s.export_obj}});
  const ReadMesh read = read_checked_mesh(s);
  sweep::io::check_can_create(s.export_obj);
  sweep::assets::write_obj(s.export_obj, read.mesh());
  if (!s.quiet) std::cout << "wrote " << s.export_obj.string() << " (" << read.mesh().vertex_count() << " vertices)\n";
  return 0;
}

// The parts found, as a table (and JSON with --report); no rig.
int run_list(const Settings& s) {
  const auto start = std::chrono::steady_clock::now();
  sweep::tools::check_paths({{"the mesh", s.mesh}}, {{"--report", s.report}});
  const ReadMesh read = read_checked_mesh(s);
  const sweep::Mesh& mesh = read.mesh();
  if (!s.report.empty()) sweep::io::check_can_create(s.report);
  const NamesUp up = names_up(s, read.read);
  const sweep::fit::SweepFitter fitter(mesh);
  const sweep::Topology& searched = fitter.patched_topology();
  std::vector<std::string> passed_over;
  // Only parts whose fit --all would then take (fit/offered_parts.h).
  const std::vector<sweep::fit::FoundPart> parts =
      sweep::fit::find_fitting_parts(mesh, fitter, discover_options(up), fit_options(s),
                                     s.verbose ? &passed_over : nullptr)
          .parts;
  sweep::fit_tool::print_names_up(up.direction, up.why);
  sweep::fit_tool::print_parts(parts, sweep::hole_edge_count(searched));
  for (const std::string& x : passed_over) std::cout << "  passed over " << x << "\n";
  if (!s.report.empty())
    sweep::fit_tool::write_parts_report(s.report, s.mesh, parts, up.direction, up.why, seconds_since(start));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return sweep::tools::guarded_main([&] {
    Settings s;
    CLI::App app{"Fit a sweep (key sections and radius samples) to a tubular part of a mesh"};
    app.set_version_flag("--version", std::string("sweep-fit ") + SWEEP_VERSION);
    app.add_option("mesh", s.mesh, "Input mesh (OFF, PLY, OBJ, STL, glTF/glb, FBX)")->required();
    app.add_option("--mesh", s.mesh_names,
                   "Which mesh of a file of several (glTF, FBX, ...): a node's or a mesh's name; given "
                   "more than once (or 'all'), those meshes as one, in the file's order (default: a rig "
                   "being updated keeps its own, else the only or the largest one)")
        ->expected(1)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->check(sweep::tools::kNonEmptyName);
    auto* rig = app.add_option("-o,--rig", s.rig, "Rig file to create, or to add/replace the sweep(s) in");
    auto* list = app.add_flag("--list", s.list, "Find the mesh's tubular parts and list them (no rig is written)");
    auto* all = app.add_flag("--all", s.all, "Find the mesh's tubular parts and fit every one")->excludes(list);
    auto* names = app.add_option("--names", s.names,
                                 "With --all: the parts' names, comma-separated, in --list's order "
                                 "(default: the suggested names)");
    auto* only = app.add_option("--only", s.only,
                                "With --all: fit only these parts, comma-separated, by the names --list "
                                "suggests");
    auto* skip = app.add_option("--skip", s.skip,
                                "With --all: fit every part but these, comma-separated, by the names "
                                "--list suggests")
                     ->excludes(only);
    auto* up = app.add_option("--up", s.up,
                              "With --list or --all: the mesh's up axis, which the suggested names go by "
                              "(a leg points down, a neck rises); default: the file's own (glTF: Y; FBX, "
                              "Collada: as the file says; Blender, Quake formats: as their convention, Z; else Y)")
                   ->check(CLI::IsMember({"X", "Y", "Z"}))
                   ->capture_default_str();
    auto* name = app.add_option("--name", s.name, "Name of the sweep in the rig")->capture_default_str();
    auto* root = app.add_option("--root", s.root,
                                "X,Y,Z: where the part leaves the body (on its axis, its surface or "
                                "inside the body); default: found where the part meets the body");
    auto* tip = app.add_option("--tip", s.tip, "X,Y,Z: on or near the part's end");
    auto* tip_vertex =
        app.add_option("--tip-vertex", s.tip_vertex_text, "The part's end as a vertex index")->excludes(tip);
    app.add_flag("--force", s.force,
                 "Write the rig even when the fit breaks a limit (stops short, leaks into the "
                 "body, error too large)");
    auto* axis =
        app.add_option("--axis", s.axis, "File of axis points 'X Y Z' per line, root first (instead of tracing)");
    // The rig reader's limits (core/limits.h): never write a rig that sweep-bind refuses.
    auto* sections = app.add_option("-k,--sections", s.sections, "Key sections K")
                         ->check(CLI::Range(2, sweep::limits::kMaxSections))
                         ->capture_default_str();
    app.add_option("-n,--radial", s.radial, "Radius samples per section")
        ->check(CLI::Range(3, sweep::limits::kMaxRadial))
        ->capture_default_str();
    app.add_option("--tolerance", s.tolerance,
                   "Use the fewest sections with fit_rms <= this fraction of the mean radius "
                   "(--tolerance chooses K)")
        ->check(sweep::tools::kPositive)
        ->excludes(sections);
    app.add_option("--report", s.report, "Write a JSON report here")->check(sweep::tools::kNonEmptyName);
    auto* preview =
        app.add_option("--preview", s.preview, "Draw the fit over the mesh from three sides into this PNG file")
            ->check(sweep::tools::kNonEmptyName);
    auto* material = app.add_option("--material", s.material,
                                    "JSON file of a material (youngs_modulus_pa, density_kg_m3, "
                                    "metres_per_unit, ...): the fitted sweeps move in material mode")
                         ->check(sweep::tools::kNonEmptyName);
    auto* preset = app.add_option("--preset", s.preset,
                                  "A material preset (tail, neck, ear, tentacle, strand): the part's stiffness "
                                  "solved for the preset's sway frequency; --material's members override it "
                                  "(default: the preset the part's name chooses, see --springs)");
    auto* springs = app.add_flag("--springs", s.springs,
                                 "Keep the paper's springs (bend and positional springs at 1.5 Hz, "
                                 "damping 0.3, no gravity) instead of the preset the part's name "
                                 "chooses (tail, neck, ear, tentacle, strand; any other part: " +
                                     std::string(sweep::kFallbackPreset) + ")")
                        ->excludes(material)
                        ->excludes(preset);
    auto* space = app.add_option("--space", s.space,
                                 "What --root, --tip and --axis are in: world (the mesh's points after "
                                 "its node transforms) or local (the mesh's own, as stored)")
                      ->check(CLI::IsMember({"world", "local"}))
                      ->capture_default_str();
    auto* export_obj = app.add_option("--export-obj", s.export_obj,
                                      "Write the mesh as read (world space, the tools' vertex order) to this "
                                      ".obj, and nothing else")
                           ->check(sweep::tools::kNonEmptyName);
    app.add_flag("-v,--verbose", s.verbose, "Say more");
    app.add_flag("-q,--quiet", s.quiet, "Print nothing on success (no summary, no notes)");
    if (const auto stop = sweep::tools::parse_command_line(app, argc, argv)) return *stop;
    if (s.quiet) sweep::io::set_note_sink(nullptr);
    for (const std::string& m : s.mesh_names) sweep::tools::check_utf8(m, "--mesh");
    s.mesh_name = sweep::io::join_mesh_names(s.mesh_names);
    s.root_given = root->count() > 0;
    s.tip_given = tip->count() > 0;
    s.up_given = up->count() > 0;
    if (tip_vertex->count() > 0) s.tip_vertex = tip_vertex_index(s.tip_vertex_text);
    // The modes: one part (named by --tip, --tip-vertex or --axis), --all, --list.
    const bool finding = list->count() > 0 || all->count() > 0;
    for (const CLI::Option* one : {tip, tip_vertex, root, axis, name}) {
      if (finding && one->count() > 0) {
        fail(ErrorCategory::usage,
             one->get_name() + " names one part: it does not go with " + (s.list ? "--list" : "--all"));
      }
    }
    if (names->count() > 0 && !s.all) fail(ErrorCategory::usage, "--names goes with --all");
    for (const CLI::Option* choice : {only, skip}) {
      if (choice->count() > 0 && !s.all) fail(ErrorCategory::usage, choice->get_name() + " goes with --all");
    }
    if (up->count() > 0 && !finding)
      fail(ErrorCategory::usage, "--up names the parts --list and --all find: it goes with them");
    if (space->count() > 0 && finding) {
      fail(ErrorCategory::usage,
           std::string("--space says what --root, --tip and --axis are in: it does not go with ") +
               (s.list ? "--list" : "--all"));
    }
    if (material->count() > 0 && s.list) fail(ErrorCategory::usage, "--material goes with a fit or --all, not --list");
    if (preset->count() > 0 && s.list) fail(ErrorCategory::usage, "--preset goes with a fit or --all, not --list");
    if (springs->count() > 0 && s.list) fail(ErrorCategory::usage, "--springs goes with a fit or --all, not --list");
    if (preview->count() > 0 && s.list) {
      fail(ErrorCategory::usage, "--preview draws fitted parts: use it with a fit or --all, not --list");
    }
    if (preview->count() > 0 && s.preview.extension() != ".png") {
      fail(ErrorCategory::usage, "--preview writes a PNG: its name must end in .png, got '" + s.preview.string() + "'");
    }
    if (export_obj->count() > 0) {
      for (const CLI::Option* other :
           {list, all, rig, tip, tip_vertex, root, axis, name, material, preset, springs, preview, up, space}) {
        if (other->count() > 0) {
          fail(ErrorCategory::usage,
               "--export-obj writes the mesh alone: " + other->get_name() + " does not go with it");
        }
      }
      if (s.export_obj.extension() != ".obj") {
        fail(ErrorCategory::usage,
             "--export-obj writes an OBJ: its name must end in .obj, got '" + s.export_obj.string() + "'");
      }
      return run_export(s);
    }
    if (!s.list && rig->count() == 0) fail(ErrorCategory::usage, "-o RIG is required (except with --list)");
    if (s.list && rig->count() > 0) fail(ErrorCategory::usage, "--list writes no rig: drop -o");
    if (!finding && s.axis.empty() && tip->count() == 0 && tip_vertex->count() == 0) {
      fail(ErrorCategory::usage,
           "give --tip X,Y,Z or --tip-vertex N (or --axis FILE), or --list "
           "or --all to find the parts");
    }
    if (s.name.empty()) fail(ErrorCategory::usage, "--name must not be empty");
    if (s.list) return run_list(s);
    if (s.all) return run_all(s);
    return run_one(s);
  });
}
