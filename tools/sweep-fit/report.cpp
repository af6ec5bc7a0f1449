#include "sweep-fit/report.h"

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "sweep/core/rig.h"
#include "sweep/core/text.h"
#include "sweep/fit/hole_patches.h"
#include "sweep/io/atomic_file.h"
#include "sweep/io/mesh_names.h"

namespace sweep::fit_tool {
namespace {

using Json = nlohmann::ordered_json;

Json point(const Vec3& p) {
  return Json::array({p.x(), p.y(), p.z()});
}

Json fit_entry(const fit::FitResult& r) {
  Json s;
  s["name"] = r.sweep.name;
  s["sections"] = r.sweep.rest.section_count();
  s["radial"] = r.sweep.rest.radial_count;
  s["ok"] = r.problems.empty();
  s["problems"] = r.problems;
  s["tip_vertex"] = r.tip_vertex;
  s["root"] = point(r.root);
  s["root_found"] = r.root_found;
  s["root_reason"] = r.root_reason;
  s["tip_cut"] = r.tip_cut;
  if (r.tip_cut) s["tip_cut_reason"] = r.tip_cut_reason;
  s["end_cut"] = r.end_cut;
  if (r.end_cut) s["end_cut_reason"] = r.end_cut_reason;
  s["part_vertex_count"] = r.part_vertices.size();
  s["measured_vertex_count"] = r.error.measured_count;
  s["beyond_ends_vertex_count"] = r.error.beyond_ends_count;
  s["protrusion_vertex_count"] = r.error.protrusion_count;
  s["beyond_root_vertex_count"] = r.error.beyond_root_count;
  s["in_range_share"] = r.in_range_share();
  s["leaked_vertex_count"] = r.leaked_count;
  s["length"] = r.length;
  s["traced_length"] = r.traced_length;
  s["surface_length"] = r.surface_length;
  s["traced_over_surface"] = r.surface_length > 0 ? r.traced_length / r.surface_length : 0.0;
  s["tip_gap_relative"] = r.mean_radius > 0 ? r.tip_gap / r.mean_radius : 0.0;
  s["trace_end_reason"] = r.axis.end_reason;
  s["tip_off_surface"] = r.tip_off_surface;
  s["root_off_surface"] = r.root_off_surface;
  s["seed_limit"] = r.seed_limit;
  s["mean_radius"] = r.mean_radius;
  const double mr = r.mean_radius > 0 ? r.mean_radius : 1.0;
  s["fit_rms"] = r.error.rms;
  s["fit_max"] = r.error.max;
  s["fit_rms_relative"] = r.error.rms / mr;
  s["fit_p90_relative"] = r.error.p90 / mr;
  s["fit_max_relative"] = r.error.max / mr;
  s["surface_rms_relative"] = r.error.surface_rms / mr;
  s["surface_max_relative"] = r.error.surface_max / mr;
  s["surface_p90_relative"] = r.error.surface_p90 / mr;
  s["radial_rms_relative"] = r.error.radial_rms / mr;
  s["axis_points"] = r.axis.points.size();
  auto& v = s["star_violations"] = Json::array();
  for (const auto& x : r.star_violations) {
    v.push_back(
        {{"section", x.section}, {"multi_crossing_rays", x.multi_crossing_rays}, {"missed_rays", x.missed_rays}});
  }
  s["warnings"] = r.warnings;
  s["seconds"] = r.seconds;
  return s;
}

// The FBX units people use, in centimetres, as a person says one and names them.
struct NamedUnit {
  double cm;
  const char* words;   // "100 cm = 1 m"
  const char* plural;  // "metres"
};
constexpr NamedUnit kNamedUnits[] = {{1, "1 cm", "centimetres"},
                                     {100, "100 cm = 1 m", "metres"},
                                     {0.1, "0.1 cm = 1 mm", "millimetres"},
                                     {2.54, "2.54 cm, an inch", "inches"},
                                     {30.48, "30.48 cm, a foot", "feet"},
                                     {100000, "100000 cm = 1 km", "kilometres"}};
const NamedUnit* named_unit(double cm) {
  for (const NamedUnit& u : kNamedUnits) {
    if (u.cm == cm) return &u;
  }
  return nullptr;
}

// A length of `cm` centimetres as a person says it: "1 cm", "100 cm = 1 m", "2.54 cm, an inch".
std::string unit_words(double cm) {
  const NamedUnit* u = named_unit(cm);
  return u ? u->words : format_number(cm) + " cm";
}

// The coordinates' unit in the plural: "centimetres", "units of 5 cm".
std::string unit_plural(double cm) {
  const NamedUnit* u = named_unit(cm);
  return u ? u->plural : "units of " + format_number(cm) + " cm";
}

}  // namespace

MeshSummary summarize_mesh(const std::filesystem::path& path, const assets::SceneMesh& read, const std::string& taken) {
  const Mesh& mesh = read.mesh;
  MeshSummary m;
  m.vertices = mesh.vertex_count();
  m.faces = mesh.face_count();
  if (!mesh.positions.empty()) m.min = m.max = mesh.positions.front();
  for (const Vec3& p : mesh.positions) {
    m.min = m.min.cwiseMin(p);
    m.max = m.max.cwiseMax(p);
  }
  m.name = read.name;
  m.taken = taken;
  m.meshes = read.meshes;
  m.unit = read.unit;
  const std::string ext = lower_extension(path);
  if (ext == "gltf" || ext == "glb") {
    m.space =
        "the scene's world space: each mesh placed by its node's transforms (glTF units are "
        "metres)";
  } else if (ext == "off" || ext == "obj" || ext == "ply" || ext == "stl") {
    m.space = "the file's coordinates as stored (the format states no unit)";
  } else {
    // assimp reads with no post-processing, so no unit scale is applied (measured on FBX files
    // Blender writes: UnitScaleFactor 1 with the coordinates × 100, and 100 with them as they are).
    m.space =
        "the scene's world space as assimp reads it: node transforms applied (axis conversion "
        "included), no unit scale; ";
    const double cm = read.unit.unit_scale_factor;
    if (cm > 0) {
      m.metres_per_unit = cm / 100;
      m.space += "FBX UnitScaleFactor " + format_number(cm) + " (the file's unit is " + unit_words(cm) +
                 "): points are in " +
                 (cm == 100 ? std::string("metres")
                            : unit_plural(cm) + " (× " + format_number(m.metres_per_unit) +
                                  " → metres; a material's metres_per_unit " + format_number(m.metres_per_unit) + ")");
    } else {
      m.space += "the file states no unit (no UnitScaleFactor)";
    }
  }
  return m;
}

void print_mesh_summary(const std::filesystem::path& path, const MeshSummary& m) {
  std::cout << "mesh " << path.string();
  if (!m.name.empty()) std::cout << " " << io::shown_mesh_names(m.name) << " (" << m.taken << ")";
  std::cout << ": " << m.vertices << " vertices, " << m.faces << " faces, bounding box " << format_point(m.min)
            << " to " << format_point(m.max) << " (size " << format_point(m.max - m.min) << ")\n"
            << "  points" << (m.seeds_local ? "" : " (and --tip, --root, --axis)") << " are in " << m.space << "\n";
  if (m.seeds_local) {
    std::cout << "  --tip, --root and --axis are in the mesh's own space (--space local): its node's world "
                 "transform takes them there"
              << (m.name.empty() ? " (none here: the file's coordinates are the mesh's own)" : "") << "\n";
  }
  if (m.meshes.size() > 1) {
    std::cout << "  the file's meshes (--mesh NAME takes one): " << assets::list_scene_meshes(m.meshes) << "\n";
  } else if (m.name.empty() && !m.taken.empty()) {
    std::cout << "  " << m.taken << "\n";
  }
}

std::string mesh_choice_note(const std::filesystem::path& path, const MeshSummary& m) {
  if (m.meshes.size() >= 2 && m.taken == "every mesh of the file, as one") {
    return path.string() + " holds " + std::to_string(m.meshes.size()) + " meshes; searched them all as one (" +
           std::to_string(m.vertices) + " vertices; --mesh NAME takes one): " + assets::list_scene_meshes(m.meshes);
  }
  if (m.meshes.size() < 2 || m.taken != "the largest") return "";
  std::vector<assets::SceneMeshEntry> others;
  for (const assets::SceneMeshEntry& e : m.meshes) {
    if (e.name != m.name) others.push_back(e);
  }
  return path.string() + " holds " + std::to_string(m.meshes.size()) + " meshes; took '" + m.name + "' (" +
         std::to_string(m.vertices) +
         " vertices, the largest; --mesh NAME takes another); the others: " + assets::list_scene_meshes(others);
}

std::string fit_report_text(const std::filesystem::path& mesh, const MeshSummary& summary,
                            const std::filesystem::path& rig, const std::vector<fit::FitResult>& fits, bool rig_written,
                            double seconds, const Error* failure) {
  Json rep;
  rep["format"] = "sweep-fit-report";
  rep["version"] = 2;
  rep["mesh"] = mesh.generic_string();
  rep["mesh_summary"] = {{"vertices", summary.vertices},
                         {"faces", summary.faces},
                         {"bounding_box", {{"min", point(summary.min)}, {"max", point(summary.max)}}},
                         {"space", summary.space},
                         // several meshes: their names, in the order their vertices are concatenated
                         {"mesh_name", io::several_mesh_names(summary.name) ? Json(io::split_mesh_names(summary.name))
                                                                            : Json(summary.name)},
                         {"taken", summary.taken},
                         {"seeds_space", summary.seeds_local ? "local" : "world"}};
  Json meshes = Json::array();
  for (const assets::SceneMeshEntry& e : summary.meshes) {
    meshes.push_back({{"name", e.name}, {"mesh_name", e.mesh_name}, {"vertices", e.vertex_count}});
  }
  rep["mesh_summary"]["meshes"] = std::move(meshes);
  // The file's stated unit (FBX), which nothing applies: what a point of the mesh is in metres.
  rep["mesh_summary"]["unit"] = summary.unit.unit_scale_factor > 0
                                    ? Json{{"unit_scale_factor", summary.unit.unit_scale_factor},
                                           {"original_unit_scale_factor", summary.unit.original_unit_scale_factor},
                                           {"metres_per_unit", summary.metres_per_unit}}
                                    : Json();
  rep["rig"] = rig.generic_string();
  rep["rig_written"] = rig_written;
  auto& sweeps = rep["sweeps"] = Json::array();
  for (const fit::FitResult& r : fits) sweeps.push_back(fit_entry(r));
  if (failure) {
    rep["error"] = {{"message", failure->what()}, {"exit_code", exit_code(failure->category())}};
  }
  rep["seconds_total"] = seconds;
  return rep.dump(2) + "\n";
}

void print_names_up(const Vec3& up, const std::string& why) {
  std::cout << "names go by up " << assets::direction_name(up) << " (" << why << "; --up X|Y|Z gives another)\n";
}

void write_parts_report(const std::filesystem::path& report, const std::filesystem::path& mesh,
                        const std::vector<fit::FoundPart>& parts, const Vec3& up, const std::string& up_why,
                        double seconds) {
  Json rep;
  rep["format"] = "sweep-fit-parts";
  rep["version"] = 1;
  rep["mesh"] = mesh.generic_string();
  rep["up"] = {{"direction", point(up)}, {"axis", assets::direction_name(up)}, {"why", up_why}};
  auto& list = rep["parts"] = Json::array();
  for (const fit::FoundPart& p : parts) {
    Json e;
    e["name"] = p.name;
    e["tip_vertex"] = p.tip_vertex;
    e["tip"] = point(p.tip);
    e["root"] = point(p.root);
    e["length"] = p.length;
    e["mean_radius"] = p.mean_radius;
    e["vertex_count"] = p.vertex_count;
    e["junction"] = p.junction_reason;
    list.push_back(e);
  }
  rep["seconds_total"] = seconds;
  io::write_file_atomically(report, rep.dump(2) + "\n");
}

void print_fit(const fit::FitResult& r, bool verbose) {
  const double mr = r.mean_radius > 0 ? r.mean_radius : 1.0;
  std::cout << r.sweep.name << ": " << r.sweep.rest.section_count() << " sections x " << r.sweep.rest.radial_count
            << " radii, length " << format_number(r.length) << " (along its axis, root section to last), mean radius "
            << format_number(r.mean_radius) << "\n"
            << "  root " << format_point(r.root) << (r.root_found ? " (found: " : " (") << r.root_reason << ")\n"
            << (r.tip_cut ? "  tip-side cut at the last section (" + r.tip_cut_reason + ")\n" : "")
            << (r.end_cut ? "  the sweep ends before the part does (" + r.end_cut_reason + ")\n" : "")
            << "  part: " << r.part_vertices.size() << " vertices, " << format_percent(r.in_range_share())
            << " between the end sections; the axis traced " << format_number(r.traced_length)
            << " (root to the end's cap), the surface distance " << format_number(r.surface_length)
            << " (root ring to tip)\n"
            << "  fit: rms " << format_percent(r.error.rms / mr) << ", 90% within " << format_percent(r.error.p90 / mr)
            << ", max " << format_percent(r.error.max / mr)
            << " of the mean radius (part to surface); surface to part rms " << format_percent(r.error.surface_rms / mr)
            << ", 90% within " << format_percent(r.error.surface_p90 / mr) << ", max "
            << format_percent(r.error.surface_max / mr) << "\n";
  if (verbose) {
    std::cout << "  axis: " << r.axis.points.size() << " points, ending " << format_number(r.tip_gap / mr)
              << " mean radii from tip vertex " << r.tip_vertex << " ("
              << (r.axis.end_reason.empty() ? "the axis given" : r.axis.end_reason) << "); "
              << r.error.beyond_ends_count << " part vertices beyond the end sections, " << r.error.protrusion_count
              << " in protrusions carried along (more than " << format_number(kPartReachRadii)
              << " radii from the axis)\n";
  }
}

std::string no_parts_found(std::size_t hole_edges) {
  std::string m = "no tubular parts found";
  if (hole_edges > 0) {
    m += " (the mesh is open: " + std::to_string(hole_edges) +
         " edges rim holes the search left open — it patches a hole of up to " +
         std::to_string(fit::kMaxTriangulatedRim) + " edges round and " + format_percent(fit::kMaxPatchedHoleShare) +
         " of the mesh's size across — and a ring of surface distance that runs into one measures "
         "no tube, so such holes can hide a part; fill them first)";
  }
  return m;
}

void print_parts(const std::vector<fit::FoundPart>& parts, std::size_t hole_edges) {
  if (parts.empty()) {
    std::cout << no_parts_found(hole_edges) << "\n";
    return;
  }
  std::printf("%-8s %8s  %-28s %-28s %10s %10s %8s\n", "name", "tip", "tip at", "root at", "length", "radius",
              "vertices");
  for (const fit::FoundPart& p : parts) {
    const std::string tip = format_point(p.tip, 4), root = format_point(p.root, 4);
    std::printf("%-8s %8u  %-28s %-28s %10.4g %10.4g %8zu\n", p.name.c_str(), p.tip_vertex, tip.c_str(), root.c_str(),
                p.length, p.mean_radius, p.vertex_count);
  }
  // Parts found on an open mesh (a tube whose ends are open rims) are measured up to the rims: say
  // that the mesh is open, as when no part is found.
  if (hole_edges > 0) {
    std::printf(
        "the mesh is open: %zu edges rim holes the search left open (a hole of up to %d edges "
        "round and %s of the mesh's size across is patched); a part that ends at one ends at "
        "its rim\n",
        hole_edges, static_cast<int>(fit::kMaxTriangulatedRim), format_percent(fit::kMaxPatchedHoleShare).c_str());
  }
  std::fflush(stdout);
}

}  // namespace sweep::fit_tool
