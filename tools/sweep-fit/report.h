#pragma once
// What sweep-fit tells: the JSON report (--report) and the lines on stdout, for fits and for the
// list of parts found (--list).
#include <filesystem>
#include <string>
#include <vector>

#include "sweep/assets/mesh_io.h"
#include "sweep/core/error.h"
#include "sweep/fit/discover.h"
#include "sweep/fit/fit.h"

namespace sweep::fit_tool {

// What the mesh's numbers are, for a person (-v) and the report ("mesh_summary"): its size, its
// bounding box and the space --tip, --root and --axis are read in (a glTF read after its
// node transforms, an FBX after its unit scale, said out loud).
// Which mesh of the file was taken and why.
struct MeshSummary {
  std::size_t vertices = 0;
  std::size_t faces = 0;
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
  std::string space;                           // how the file's coordinates became the mesh's
  std::string name;                            // the mesh taken ("" = the whole file, or a format of one nameless mesh)
  std::string taken;                           // why: "named by --mesh", "the rig's", "the only one", "the largest",
                                               // "every mesh of the file, as one" (--list, --all), "the whole file"
  std::vector<assets::SceneMeshEntry> meshes;  // all the file's meshes (empty: a format without names)
  assets::MeshUnit unit;                       // the unit the file states (FBX UnitScaleFactor), applied by nothing
  double metres_per_unit = 0;                  // what that unit is in metres (0: the file states none)
  bool seeds_local = false;                    // --space local: --root, --tip and --axis in the mesh's own space
};
MeshSummary summarize_mesh(const std::filesystem::path& path, const assets::SceneMesh& read, const std::string& taken);
void print_mesh_summary(const std::filesystem::path& path, const MeshSummary& m);
// "FILE holds N meshes; took 'X' (V vertices, the largest) ..." or "FILE holds N meshes; searched
// them all as one ..." for a note on stderr, or "" when the file holds one mesh or the mesh was named.
std::string mesh_choice_note(const std::filesystem::path& path, const MeshSummary& m);

// The report of one or more fits: written also when a fit fails (rig_written false), so that a
// script sees the numbers; `failure`, when given, is the error the run ends with ("error":
// message and exit code), `fits` then holding what was fitted before it and, for a FitFailure,
// the fit as far as it got. Format "sweep-fit-report", version 2 (docs/tools.md: sweep-fit's report).
std::string fit_report_text(const std::filesystem::path& mesh, const MeshSummary& summary,
                            const std::filesystem::path& rig, const std::vector<fit::FitResult>& fits, bool rig_written,
                            double seconds, const Error* failure = nullptr);

// The parts found: format "sweep-fit-parts", version 1; "up" the direction the names went by and why.
void write_parts_report(const std::filesystem::path& report, const std::filesystem::path& mesh,
                        const std::vector<fit::FoundPart>& parts, const Vec3& up, const std::string& up_why,
                        double seconds);

// "names go by up +Z (why)": the line --list prints above the parts.
void print_names_up(const Vec3& up, const std::string& why);

// A fit's summary for a person: sections, root, part, error (and the axis with `verbose`).
void print_fit(const fit::FitResult& r, bool verbose);

// "no tubular parts found", with why when the mesh is open (`hole_edges`: hole_edge_count of the
// patched topology, the holes the search left open).
std::string no_parts_found(std::size_t hole_edges);

// The parts found, as a table (or no_parts_found).
void print_parts(const std::vector<fit::FoundPart>& parts, std::size_t hole_edges);

}  // namespace sweep::fit_tool
