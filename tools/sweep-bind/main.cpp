// sweep-bind: reads a rig and its mesh, binds every vertex of each sweep's part to its sweep
// coordinates (lib/bind/bind.h: part selection, ownership and blend rules) and writes the binding
// file (lib/io/binding_file.h: layout). With --check it instead verifies an existing binding
// against the rig and mesh. Exit codes as in core/error.h: 1 usage, 2 bad input (including a
// stale or damaged binding), 3 unsupported, 4 output.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "sweep/assets/mesh_io.h"
#include "sweep/bind/bind.h"
#include "sweep/core/text.h"
#include "sweep/io/atomic_file.h"
#include "sweep/io/binding_file.h"
#include "sweep/io/interrupt.h"
#include "sweep/io/mesh_names.h"
#include "sweep/io/rig_json.h"
#include "tools/common/cli_checks.h"
#include "tools/common/path_checks.h"
#include "tools/common/tool_main.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Settings {
  fs::path rig;                      // input rig (JSON); its mesh path is relative to it
  fs::path output;                   // binding file; empty = the rig's path with ".bind"
  fs::path report;                   // JSON report; empty = none
  fs::path check;                    // verify this binding instead of binding; empty = bind
  sweep::bind::BindOptions options;  // blend distance (mesh units) and locator settings
  bool quiet = false;
};

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string format_ms(double seconds) {
  return sweep::format_number(seconds * 1e3, 3) + " ms";
}

std::string report_text(const Settings& s, const fs::path& mesh_path, const std::string& mesh_name,
                        const fs::path& output, const sweep::bind::BindResult& r, double load_seconds,
                        double write_seconds) {
  nlohmann::ordered_json doc;
  doc["format"] = "sweep-bind-report";
  doc["version"] = 1;
  doc["rig"] = s.rig.string();
  doc["mesh"] = mesh_path.string();
  if (sweep::io::several_mesh_names(mesh_name)) {
    doc["mesh_name"] = sweep::io::split_mesh_names(mesh_name);
  } else if (!mesh_name.empty()) {
    doc["mesh_name"] = mesh_name;
  }
  doc["binding"] = output.string();
  doc["binding_format_version"] = sweep::io::kBindingFormatVersion;
  doc["vertex_count"] = r.binding.vertex_count;
  doc["unbound_vertex_count"] = r.unbound_vertex_count;
  doc["blend"] = s.options.blend;
  doc["warnings"] = r.warnings;
  nlohmann::ordered_json sweeps = nlohmann::ordered_json::array();
  for (const sweep::bind::SweepBindStats& st : r.sweeps) {
    nlohmann::ordered_json j;
    j["name"] = st.name;
    j["part_vertex_count"] = st.part_vertex_count;
    j["bound_vertex_count"] = st.bound_vertex_count;
    j["blended_vertex_count"] = st.blended_vertex_count;
    j["loose_piece_count"] = st.loose_piece_count;
    j["loose_vertex_count"] = st.loose_vertex_count;
    j["length"] = st.length;
    j["rest_max_error"] = st.rest_max_error;
    j["rest_max_error_relative"] = st.length > 0 ? st.rest_max_error / st.length : 0.0;
    j["seconds"] = st.seconds;
    sweeps.push_back(std::move(j));
  }
  doc["sweeps"] = std::move(sweeps);
  doc["seconds"] = {{"load", load_seconds}, {"bind", r.seconds}, {"write", write_seconds}};
  return doc.dump(2) + "\n";
}

int run(const Settings& s) {
  const Clock::time_point load_start = Clock::now();
  const sweep::Rig rig = sweep::io::read_rig(s.rig, sweep::tools::warn);
  const fs::path mesh_path = sweep::io::resolve_mesh_path(s.rig, rig);
  // The rig's mesh of that file (the whole file for a rig that names none).
  const sweep::Mesh mesh =
      sweep::assets::read_scene_mesh(mesh_path, rig.mesh_name, sweep::assets::MeshPick::whole_file).mesh;
  const double load_seconds = since(load_start);

  if (!s.check.empty()) {
    const sweep::bind::Binding b = sweep::io::load_binding(s.check, mesh, rig);
    if (!s.quiet) {
      std::cout << s.check.string() << ": matches " << s.rig.string() << " and " << mesh_path.string() << " ("
                << b.bound_count() << " of " << b.vertex_count << " vertices bound)\n";
    }
    return 0;
  }

  const fs::path output = s.output.empty() ? sweep::io::default_binding_path(s.rig) : s.output;
  sweep::tools::check_paths({{"the rig", s.rig}, {"the mesh", mesh_path}},
                            {{"the binding", output}, {"--report", s.report}});
  // Every output is checked before any work, so a report that cannot be written does not leave a
  // binding behind (nor a binding that cannot be written cost a bind).
  sweep::io::check_can_create(output);
  if (!s.report.empty()) sweep::io::check_can_create(s.report);
  sweep::io::declare_outputs({output, s.report});
  sweep::bind::BindResult r;
  try {
    r = sweep::bind::bind(rig, mesh, s.options);
  } catch (const sweep::Error& e) {
    throw sweep::Error(e.category(), s.rig.string() + ": " + e.what());
  }
  for (const std::string& w : r.warnings) sweep::tools::warn(w);
  const Clock::time_point write_start = Clock::now();
  // The binding and its report go into place together, or neither.
  sweep::io::Publication outputs;
  outputs.add(output, sweep::io::binding_bytes(r.binding));
  const double write_seconds = since(write_start);
  if (!s.report.empty()) {
    outputs.add(s.report, report_text(s, mesh_path, rig.mesh_name, output, r, load_seconds, write_seconds));
  }
  outputs.commit();

  if (!s.quiet) {
    std::cout << s.rig.string() << ": " << mesh_path.string()
              << (rig.mesh_name.empty() ? "" : " " + sweep::assets::asked_meshes(rig.mesh_name)) << ", "
              << mesh.vertex_count() << " vertices\n";
    for (const sweep::bind::SweepBindStats& st : r.sweeps) {
      std::cout << "  " << st.name << ": " << st.bound_vertex_count << " vertices bound";
      if (st.bound_vertex_count != st.part_vertex_count) {
        std::cout << " (" << st.part_vertex_count - st.bound_vertex_count << " of its part went to a nearer sweep)";
      }
      if (st.loose_piece_count > 0) {
        std::cout << ", " << st.loose_piece_count << (st.loose_piece_count == 1 ? " loose piece (" : " loose pieces (")
                  << st.loose_vertex_count << " vertices) with it";
      }
      if (st.blended_vertex_count > 0) std::cout << ", " << st.blended_vertex_count << " blended";
      std::cout << ", rest error max " << sweep::format_number(st.rest_max_error) << " ("
                << sweep::format_number(st.length > 0 ? st.rest_max_error / st.length : 0.0) << " of its length)\n";
      if (st.bound_vertex_count == 0) {
        sweep::tools::warn("sweep '" + st.name + "' binds no vertices");
      }
    }
    // A part cut at its tip too (the tube goes on past it) meets the unbound surface there: without
    // a blend that cut is a seam that opens as soon as the tip moves.
    for (const sweep::SweepDef& def : rig.sweeps) {
      if (def.part && def.part->tip_cut && s.options.blend == 0) {
        sweep::tools::warn("sweep '" + def.name +
                           "' is cut at its tip too (the tube goes on past "
                           "it): with no --blend the cut opens as the tip moves; bind with --blend "
                           "of about a radius");
      }
    }
    std::cout << "  unbound: " << r.unbound_vertex_count << " vertices\n"
              << "wrote " << output.string() << " (bound in " << format_ms(r.seconds) << ", loaded in "
              << format_ms(load_seconds) << ")\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return sweep::tools::guarded_main([&] {
    Settings s;
    CLI::App app{"Bind every vertex of each sweep's part to its sweep coordinates", "sweep-bind"};
    app.add_option("rig", s.rig, "Rig file (JSON) written by sweep-fit")->required();
    auto* output = app.add_option("-o,--output", s.output, "Binding file (default: the rig's path with .bind)")
                       ->check(sweep::tools::kNonEmptyName);
    auto* report = app.add_option("--report", s.report, "Write a JSON report (counts, rest error, timings)")
                       ->check(sweep::tools::kNonEmptyName);
    app.add_option("--blend", s.options.blend,
                   "Depth of the blend zone beyond each part's root plane, and before its tip-side cut if it has one "
                   "(mesh units; 0 = none)")
        ->check(sweep::tools::kNonNegative)
        ->capture_default_str();
    app.add_option("--check", s.check, "Verify this existing binding against the rig and its mesh instead of binding")
        ->excludes(output)
        ->excludes(report);
    app.add_flag("-q,--quiet", s.quiet, "Print nothing on success");
    app.set_version_flag("--version", std::string("sweep-bind ") + SWEEP_VERSION + " (binding format " +
                                          std::to_string(sweep::io::kBindingFormatVersion) + ")");
    if (const auto stop = sweep::tools::parse_command_line(app, argc, argv)) return *stop;
    if (s.quiet) sweep::io::set_note_sink(nullptr);
    return run(s);
  });
}
