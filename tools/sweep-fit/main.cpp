// sweep-fit: fits a sweep (key cross sections and radius samples) to a tubular part of a mesh,
// named by a root point and a tip point, and writes it into a rig file (created, or updated by
// adding or replacing the sweep of that name). The work is in lib/fit/fit.h.
#include <CLI/CLI.hpp>
#include <charconv>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "common/cli_checks.h"
#include "common/tool_main.h"
#include "core/error.h"
#include "core/limits.h"
#include "fit/fit.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/path_checks.h"
#include "io/rig_json.h"

namespace fs = std::filesystem;
using sweep::ErrorCategory;
using sweep::fail;
using sweep::Vec3;

namespace {

struct Settings {
  fs::path mesh;              // input mesh (any format io::read_mesh reads)
  fs::path rig;               // rig file to create or update
  std::string name = "part";  // the sweep's name in the rig
  std::string root, tip;  // X,Y,Z in mesh units (root optional: found where the part meets the body)
  std::int64_t tip_vertex = -1;   // the tip as a vertex index
  bool force = false;             // write the rig even when the fit breaks a limit
  fs::path axis;              // optional axis polyline: "X Y Z" (or X,Y,Z) per line, root first
  int sections = sweep::fit::FitOptions{}.sections;
  int radial = sweep::fit::FitOptions{}.radial;
  double tolerance = 0;  // > 0: fewest sections with fit_rms ≤ tolerance × mean radius
  fs::path report;       // optional JSON report
  bool verbose = false;
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
    ok = !field.empty() && stop == field.c_str() + field.size() && std::isfinite(p[i]) &&
         end != std::string::npos;
    at = end + 1;
  }
  if (!ok) {  // (a fourth number stays in the third field and fails its parse)
    fail(ErrorCategory::usage,
         std::string(flag) + " expects three finite numbers X,Y,Z, got '" + text + "'");
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
      fail(ErrorCategory::bad_input,
           path.string() + ":" + std::to_string(number) + ": expected X Y Z");
    }
    points.push_back(p);
  }
  if (points.size() < 2)
    fail(ErrorCategory::bad_input, path.string() + ": an axis needs at least 2 points");
  return points;
}

// The rig's mesh path: relative to the rig file's folder.
std::string mesh_path_for(const fs::path& rig, const fs::path& mesh) {
  const fs::path rig_dir = fs::weakly_canonical(fs::absolute(rig)).parent_path();
  return fs::weakly_canonical(fs::absolute(mesh)).lexically_relative(rig_dir).generic_string();
}

nlohmann::ordered_json report_entry(const sweep::fit::FitResult& r) {
  nlohmann::ordered_json s;
  s["name"] = r.sweep.name;
  s["sections"] = r.sweep.rest.section_count();
  s["radial"] = r.sweep.rest.radial_count;
  s["ok"] = r.problems.empty();
  s["problems"] = r.problems;
  s["tip_vertex"] = r.tip_vertex;
  s["root"] = {r.root.x(), r.root.y(), r.root.z()};
  s["root_found"] = r.root_found;
  s["root_reason"] = r.root_reason;
  s["part_vertex_count"] = r.part_vertices.size();
  s["measured_vertex_count"] = r.error.measured_count;
  s["beyond_ends_vertex_count"] = r.error.beyond_ends_count;
  s["in_range_share"] = r.in_range_share();
  s["leaked_vertex_count"] = r.leaked_count;
  s["length"] = r.length;
  s["traced_length"] = r.traced_length;
  s["surface_length"] = r.surface_length;
  s["traced_over_surface"] = r.surface_length > 0 ? r.traced_length / r.surface_length : 0.0;
  s["mean_radius"] = r.mean_radius;
  const double mr = r.mean_radius > 0 ? r.mean_radius : 1.0;
  s["fit_rms"] = r.error.rms;
  s["fit_max"] = r.error.max;
  s["fit_rms_relative"] = r.error.rms / mr;
  s["fit_p90_relative"] = r.error.p90 / mr;
  s["fit_max_relative"] = r.error.max / mr;
  s["surface_rms_relative"] = r.error.surface_rms / mr;
  s["surface_max_relative"] = r.error.surface_max / mr;
  s["radial_rms_relative"] = r.error.radial_rms / mr;
  s["axis_points"] = r.axis.points.size();
  auto& v = s["star_violations"] = nlohmann::ordered_json::array();
  for (const auto& x : r.star_violations) {
    v.push_back({{"section", x.section},
                 {"multi_crossing_rays", x.multi_crossing_rays},
                 {"missed_rays", x.missed_rays}});
  }
  s["warnings"] = r.warnings;
  s["seconds"] = r.seconds;
  return s;
}

// The report, also when the fit fails (written = false), so that a script sees the numbers.
void write_report(const Settings& s, const sweep::fit::FitResult& r, bool written, double seconds) {
  nlohmann::ordered_json rep;
  rep["format"] = "sweep-fit-report";
  rep["version"] = 2;
  rep["mesh"] = s.mesh.generic_string();
  rep["rig"] = s.rig.generic_string();
  rep["rig_written"] = written;
  rep["sweeps"] = nlohmann::ordered_json::array({report_entry(r)});
  rep["seconds_total"] = seconds;
  sweep::io::write_file_atomically(s.report, rep.dump(2) + "\n");
}

int run(const Settings& s) {
  const auto start = std::chrono::steady_clock::now();
  sweep::io::check_utf8(s.name, "--name");
  sweep::io::check_paths({{"the mesh", s.mesh}, {"--axis", s.axis}},
                         {{"-o", s.rig}, {"--report", s.report}});
  sweep::fit::FitOptions o;
  o.name = s.name;
  o.sections = s.sections;
  o.radial = s.radial;
  o.tolerance = s.tolerance;
  if (!s.axis.empty()) o.axis = read_axis(s.axis);
  if (!s.root.empty()) o.root = to_point(s.root, "--root");
  if (!s.tip.empty()) o.tip = to_point(s.tip, "--tip");
  o.tip_vertex = s.tip_vertex;

  // Read the existing rig first, so a bad rig fails before any work.
  sweep::Rig rig;
  const std::string mesh_in_rig = mesh_path_for(s.rig, s.mesh);
  const bool updating = fs::exists(s.rig);
  if (updating) {
    rig = sweep::io::read_rig(s.rig, sweep::tools::warn);
    const fs::path rig_dir = fs::absolute(s.rig).parent_path();
    if (fs::weakly_canonical(rig_dir / rig.mesh) != fs::weakly_canonical(fs::absolute(s.mesh))) {
      fail(ErrorCategory::usage, s.rig.string() + " is a rig of mesh '" + rig.mesh + "', not of " +
                                     s.mesh.string() + "; write to another --rig file");
    }
  }
  rig.mesh = mesh_in_rig;

  const sweep::Mesh mesh = sweep::io::read_mesh(s.mesh);
  sweep::io::validate_mesh(mesh, s.mesh.string());
  // Outputs are checked before the fit, so neither is written when the other cannot be.
  sweep::io::check_can_create(s.rig);
  if (!s.report.empty()) sweep::io::check_can_create(s.report);
  const sweep::fit::FitResult r = sweep::fit::fit_sweep(mesh, o);
  for (const std::string& w : r.warnings) sweep::tools::warn(s.name + ": " + w);
  if (!r.problems.empty()) {
    std::string all;
    for (const std::string& p : r.problems) all += "\n  " + p;
    if (!s.force) {
      if (!s.report.empty()) write_report(s, r, false, 0);
      fail(ErrorCategory::bad_input, s.name + ": the fit is not to be trusted:" + all +
                                         "\n  (--force writes the rig anyway)");
    }
    sweep::tools::warn(s.name + ": written anyway (--force):" + all);
  }

  sweep::SweepDef def = r.sweep;
  bool replaced = false;
  for (sweep::SweepDef& old : rig.sweeps) {
    if (old.name != def.name) continue;
    // Keep the user's spring settings and force scales; per-section overrides no longer apply.
    def.default_springs = old.default_springs;
    def.springs.assign(def.springs.size(), def.default_springs);
    def.rotational_scale = old.rotational_scale;
    def.radial_scale = old.radial_scale;
    old = def;
    replaced = true;
  }
  if (!replaced) rig.sweeps.push_back(def);
  sweep::io::write_rig(s.rig, rig);

  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!s.report.empty()) write_report(s, r, true, seconds);

  std::cout << s.name << ": " << r.sweep.rest.section_count() << " sections x "
            << r.sweep.rest.radial_count << " radii, length " << r.length << ", mean radius "
            << r.mean_radius << "\n"
            << "  root " << r.root.x() << "," << r.root.y() << "," << r.root.z()
            << (r.root_found ? " (found: " : " (") << r.root_reason << ")\n"
            << "  part: " << r.part_vertices.size() << " vertices, "
            << 100 * r.in_range_share() << "% between the end sections; axis "
            << r.traced_length << " over a surface distance of " << r.surface_length << "\n"
            << "  fit: rms " << 100 * r.error.rms / r.mean_radius << "%, 90% within "
            << 100 * r.error.p90 / r.mean_radius << "%, max "
            << 100 * r.error.max / r.mean_radius
            << "% of the mean radius (part to surface); surface to part rms "
            << 100 * r.error.surface_rms / r.mean_radius << "%, max "
            << 100 * r.error.surface_max / r.mean_radius << "%\n"
            << "  "
            << (replaced   ? "replaced in "
                : updating ? "added to "
                           : "wrote ")
            << s.rig.string() << " (" << rig.sweeps.size()
            << (rig.sweeps.size() == 1 ? " sweep" : " sweeps") << ") in " << seconds << " s\n";
  if (s.verbose) {
    std::cout << "  axis: " << r.axis.points.size() << " points; tip vertex " << r.tip_vertex
              << "; " << r.error.beyond_ends_count << " part vertices beyond the end sections\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return sweep::tools::guarded_main([&] {
    Settings s;
    CLI::App app{"Fit a sweep (key sections and radius samples) to a tubular part of a mesh"};
    app.set_version_flag("--version", std::string("sweep-fit ") + SWEEP_VERSION);
    app.add_option("mesh", s.mesh, "Input mesh (OFF, PLY, OBJ, STL, glTF/glb, FBX)")->required();
    app.add_option("-o,--rig", s.rig, "Rig file to create, or to add/replace the sweep in")
        ->required();
    app.add_option("--name", s.name, "Name of the sweep in the rig")->capture_default_str();
    app.add_option("--root", s.root,
                   "X,Y,Z: where the part leaves the body (on its axis, its surface or inside the "
                   "body); default: found where the part meets the body");
    auto* tip = app.add_option("--tip", s.tip, "X,Y,Z: on or near the part's end");
    auto* tip_vertex =
        app.add_option("--tip-vertex", s.tip_vertex, "The part's end as a vertex index")
            ->check(CLI::NonNegativeNumber)
            ->excludes(tip);
    app.add_flag("--force", s.force,
                 "Write the rig even when the fit breaks a limit (stops short, leaks into the "
                 "body, error too large)");
    app.add_option("--axis", s.axis,
                   "File of axis points 'X Y Z' per line, root first (instead of tracing)");
    auto* sections =
        app.add_option("-k,--sections", s.sections, "Key sections K (>= 2)")->capture_default_str();
    app.add_option("-n,--radial", s.radial, "Radius samples per section (>= 3)")
        ->capture_default_str();
    auto* tolerance =
        app.add_option("--tolerance", s.tolerance,
                       "Use the fewest sections with fit_rms <= this fraction of the mean radius");
    app.add_option("--report", s.report, "Write a JSON report here")
        ->check(sweep::tools::kNonEmptyName);
    app.add_flag("-v,--verbose", s.verbose, "Say more");
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
      // CLI11's own codes (105, 106, 109, ...) are not ours: a bad command line is usage, 1.
      std::cerr << "error: " << e.what() << " (run with --help for more information)\n";
      return sweep::exit_code(ErrorCategory::usage);
    }
    // Conflicts, once, after parsing.
    if (sections->count() > 0 && tolerance->count() > 0) {
      fail(ErrorCategory::usage,
           "--sections and --tolerance cannot be combined: --tolerance chooses K");
    }
    if (tolerance->count() > 0 && !(s.tolerance > 0))
      fail(ErrorCategory::usage, "--tolerance must be > 0");
    if (s.axis.empty() && tip->count() == 0 && tip_vertex->count() == 0) {
      fail(ErrorCategory::usage, "give --tip X,Y,Z or --tip-vertex N (or --axis FILE)");
    }
    if (s.sections < 2)
      fail(ErrorCategory::usage,
           "--sections must be at least 2, got " + std::to_string(s.sections));
    if (s.radial < 3)
      fail(ErrorCategory::usage, "--radial must be at least 3, got " + std::to_string(s.radial));
    // The rig reader's limits (core/limits.h): never write a rig that sweep-bind refuses.
    if (s.sections > sweep::limits::kMaxSections || s.radial > sweep::limits::kMaxRadial) {
      fail(ErrorCategory::usage,
           "--sections must be at most " + std::to_string(sweep::limits::kMaxSections) +
               " and --radial at most " + std::to_string(sweep::limits::kMaxRadial));
    }
    if (s.name.empty()) fail(ErrorCategory::usage, "--name must not be empty");
    return run(s);
  });
}
