// sweep-sim: simulates the forces of a scene on a rig and bakes the animation of its bound mesh
// to .glb (glTF 2.0 morph targets + animation), .pc2 (point cache) and/or .obj (a sequence).
// Exit codes as in core/error.h: 1 usage, 2 bad input (including a stale binding), 3 unsupported,
// 4 cannot write output, 5 simulation diverged.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "sweep/assets/authored_scene.h"
#include "sweep/assets/bake.h"
#include "sweep/assets/bake_run.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/assets/skinned_clip.h"
#include "sweep/core/limits.h"
#include "sweep/core/text.h"
#include "sweep/io/atomic_file.h"
#include "sweep/io/binding_file.h"
#include "sweep/io/interrupt.h"
#include "sweep/io/rig_json.h"
#include "sweep/sim/scene.h"
#include "tools/common/cli_checks.h"
#include "tools/common/path_checks.h"
#include "tools/common/tool_main.h"
#include "tools/sweep-sim/progress.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Settings {
  fs::path rig;                   // input rig (JSON); its mesh path is relative to it
  fs::path binding;               // empty = the rig's path with ".bind" (as sweep-bind writes it)
  fs::path scene;                 // empty = the rig file's own "scene"
  fs::path report;                // JSON report; empty = none
  std::vector<fs::path> outputs;  // .glb / .pc2 / .obj
  std::string integrator;         // overrides the scene's; empty = the scene's
  int substeps = 0;               // overrides the scene's; 0 = the scene's
  double step = 0;                // s; overrides the scene's step and substeps; 0 = the scene's
  int threads = 0;                // OpenMP threads; 0 = OpenMP's default
  bool exact = false;             // per-vertex reference deformation instead of the fast path
  bool under_skin = false;        // --under-skin: a skinned clip's .pc2/.obj before skinning
  bool morph = false;             // --morph: a skinned clip's .glb as morph targets under the skin
  int stations = 8;               // fast path: stations per span
  bool sleep = true;
  bool quiet = false;
  std::uint64_t max_output_bytes = 0;  // --max-output-size: refuse a bake that would write more
  std::string max_output_text;         // --max-output-size as given (checked by read_byte_size)
  int joints = 0;                      // --joints: skinned .glb with this many joints a sweep; 0 = morph targets
  bool joints_given = false;
  std::string joints_text;                              // --joints as given: "" alone (the default, see run)
  int ring_joints = sweep::assets::kDefaultRingJoints;  // --ring-joints: ring joints a station (1: none)
  bool ring_fit = false;                                // --ring-fit: least-squares ring keys
  bool ring_given = false;
};

// `text` as a whole number (an option's value CLI11 was given as text), or a usage error naming
// `option`.
int whole_number(const std::string& text, const std::string& option) {
  int value = 0;
  const char* end = text.data() + text.size();
  const auto [at, error] = std::from_chars(text.data(), end, value);
  if (error != std::errc{} || at != end) {
    sweep::fail(sweep::ErrorCategory::usage, option + ": expected a whole number, got '" + text + "'");
  }
  return value;
}

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A frame number, or null for −1 (never).
nlohmann::ordered_json frame_or_null(int frame) {
  return frame >= 0 ? nlohmann::ordered_json(frame) : nlohmann::ordered_json();
}

std::string report_text(const Settings& s, const sweep::assets::BakeReport& r, double load_seconds,
                        double total_seconds) {
  nlohmann::ordered_json doc;
  doc["format"] = "sweep-sim-report";
  doc["version"] = 1;
  doc["rig"] = s.rig.string();
  doc["frames"] = r.frames;
  doc["fps"] = r.fps;
  doc["step_seconds"] = r.step_seconds;
  doc["deformation"] = s.exact ? "exact" : "fast";
  nlohmann::ordered_json sweeps = nlohmann::ordered_json::array();
  for (const auto& st : r.sweeps) {
    sweeps.push_back(
        {{"name", st.name},
         {"driven", st.driven},
         {"steps", st.steps},
         {"frames_deformed", st.frames_deformed},
         {"bound_vertex_count", st.bound_vertex_count},
         {"work_blocks", st.work_blocks},
         {"blocks_in_place", st.blocks_in_place},
         {"sway_frequencies_hz", st.sway.frequencies_hz},
         {"feels_gravity", st.sway.feels_gravity},
         {"droop", st.sway.droop},
         {"largest_span_bend_degrees", st.largest_bend * 180 / std::numbers::pi},
         {"largest_bend_span", st.bend_span},
         {"largest_bend_frame", st.bend_frame},
         {"fold_frame", frame_or_null(st.fold_frame)},
         {"fold_span", st.fold_frame >= 0 ? nlohmann::ordered_json(st.fold_span) : nlohmann::ordered_json()},
         {"self_cross_frame", frame_or_null(st.cross_frame)},
         {"self_cross_sections",
          st.cross_frame >= 0 ? nlohmann::ordered_json::array({st.cross_a, st.cross_b}) : nlohmann::ordered_json()}});
  }
  doc["sweeps"] = std::move(sweeps);
  nlohmann::ordered_json frames = nlohmann::ordered_json::array();
  for (const auto& f : r.per_frame) {
    frames.push_back({{"time", f.time},
                      {"max_displacement", f.max_displacement},
                      {"awake_sweeps", f.awake_sweeps},
                      {"edge_stretch", f.edge_stretch}});
  }
  doc["per_frame"] = std::move(frames);
  // The bake's quality figure: the largest deformed / rest length of any edge in any frame.
  const sweep::assets::EdgeStretch& worst = r.max_stretch;
  doc["max_edge_stretch"] = {
      {"ratio", worst.ratio},
      {"edge", worst.found ? nlohmann::ordered_json::array({worst.a, worst.b}) : nlohmann::ordered_json()},
      {"frame", r.max_stretch_frame},
      {"time", r.max_stretch_frame / r.fps},
      {"edges_measured", r.stretch_edge_count},
      {"seconds", r.stretch_seconds}};
  // Times at which the body jumped (a cut, a respawn) and the parts were put to rest there.
  doc["teleports"] = r.teleport_times;
  doc["seconds"] = {{"load", load_seconds},
                    {"simulate", r.simulate_seconds},
                    {"deform", r.deform_seconds},
                    {"write", r.write_seconds},
                    {"total", total_seconds}};
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const auto& f : r.files) files.push_back(f.string());
  doc["files"] = std::move(files);
  if (r.skin_joints > 0) {
    // The skinned .glb against the bake's positions, as fractions of the part's length.
    doc["joints_per_sweep"] = s.joints;
    doc["ring_joints"] = s.ring_joints;
    doc["ring_fit"] = s.ring_fit;
    doc["skin_joints"] = r.skin_joints;
    if (r.skin_in_character) doc["skin_joints_in_character"] = true;  // added to the character's skeleton
    doc["skin_error_max_relative"] = r.skin_error.max_relative;
    doc["skin_error_rms_relative"] = r.skin_error.rms_relative;
    doc["skin_error_max_frame"] = r.skin_error.max_frame;
    doc["skin_error_max_vertex"] = r.skin_error.max_vertex;
  }
  return doc.dump(2) + "\n";
}

int run(Settings s) {
  const Clock::time_point start = Clock::now();
  if (s.threads > 0) omp_set_num_threads(s.threads);
  if (s.joints_given) {  // the ranges, before any work
    sweep::assets::check_skin_joints({.stations = s.joints, .ring = s.ring_joints}, {}, 1);
  }
  const sweep::Rig rig = sweep::io::read_rig(s.rig, sweep::tools::warn);
  const fs::path mesh_path = sweep::io::resolve_mesh_path(s.rig, rig);
  // The rig's mesh of that file (the whole file for a rig that names none).
  const sweep::assets::SceneMesh read =
      sweep::assets::read_scene_mesh(mesh_path, rig.mesh_name, sweep::assets::MeshPick::whole_file);
  const sweep::Mesh& mesh = read.mesh;
  const fs::path binding_path = s.binding.empty() ? sweep::io::default_binding_path(s.rig) : s.binding;
  const sweep::bind::Binding binding = sweep::io::load_binding(binding_path, mesh, rig);
  // The scene as authored, resolved on the mesh: a glTF node's motion or a skinned clip, the body proxy.
  sweep::assets::ResolvedScene resolved = sweep::assets::resolve_scene(
      sweep::assets::read_authored_scene(s.scene.empty() ? s.rig : s.scene, rig, sweep::tools::warn), mesh_path, read,
      rig, binding, sweep::tools::warn);
  sweep::sim::Scene& scene = resolved.scene;
  const std::optional<sweep::assets::SkinnedClip>& skinned = resolved.skinned;
  if (s.ring_given && !s.joints_given && !(skinned && !s.morph)) {
    sweep::fail(sweep::ErrorCategory::usage,
                "--ring-joints: lays out the joints of --joints or of a skinned clip's .glb, and neither is asked for");
  }
  // A skinned clip's .glb is by default its character with the parts' joints added to its
  // skeleton, laid out as --joints alone lays them out; --morph keeps the morph targets.
  if (skinned && !s.morph && !s.joints_given && std::any_of(s.outputs.begin(), s.outputs.end(), [](const fs::path& o) {
        return sweep::lower_extension(o) == "glb";
      })) {
    s.joints_given = true;
    s.joints_text.clear();
  }
  if (s.joints_given && s.joints_text.empty()) {
    // --joints alone: the default, or, where a sweep has fewer stations, as many as the fewest any
    // sweep has (one N serves every sweep), said in a note. A number given is taken as asked, and
    // refused past a sweep's stations.
    const sweep::SweepDef* fewest = nullptr;
    for (const sweep::SweepDef& def : rig.sweeps) {
      const int stations = sweep::assets::skin_stations(def.rest, s.stations);
      if (stations < s.joints) {
        s.joints = std::max(sweep::assets::kMinSkinJoints, stations);
        fewest = &def;
      }
    }
    if (fewest != nullptr) {
      sweep::io::note("--joints: " + std::to_string(s.joints) + " joints a sweep, not " +
                      std::to_string(sweep::assets::kDefaultSkinJoints) + ": sweep \"" + fewest->name + "\" has " +
                      std::to_string(s.joints) + " stations");
    }
  }
  if (!s.integrator.empty() && !sweep::parse_integrator(s.integrator, &scene.integrator)) {
    sweep::fail(sweep::ErrorCategory::usage,
                "--integrator: expected exact, semi-implicit-euler or rk4, got \"" + s.integrator + "\"");
  }
  if (s.substeps > 0 && s.step > 0)
    sweep::fail(sweep::ErrorCategory::usage, "--step and --substeps: give one or the other");
  if (s.substeps > 0) {
    scene.substeps = s.substeps;
    scene.step = 0;  // --substeps means step = 1 / (fps · substeps), as it always did
  }
  if (s.step > 0) scene.step = s.step;
  // No output may be an input or another output (an .obj sequence: each frame's file).
  std::vector<sweep::tools::NamedPath> outputs;
  for (const fs::path& out : s.outputs) {
    for (const fs::path& f : sweep::assets::bake_files(out, scene.frame_count())) {
      outputs.push_back({"-o", f});
    }
  }
  if (!s.report.empty()) outputs.push_back({"--report", s.report});
  sweep::tools::check_paths(
      {{"the rig", s.rig}, {"the mesh", mesh_path}, {"the binding", binding_path}, {"the scene", s.scene}}, outputs);
  // Every output is checked before any is written: a report that cannot be written is found
  // before the bake is, so a failure leaves nothing behind.
  for (const fs::path& out : s.outputs) sweep::io::check_can_create(out);
  if (!s.report.empty()) sweep::io::check_can_create(s.report);
  std::vector<fs::path> declared = s.outputs;
  if (!s.report.empty()) declared.push_back(s.report);
  sweep::io::declare_outputs(declared);
  const double load_seconds = since(start);

  sweep::assets::BakeOptions options;
  options.outputs = s.outputs;
  options.source = {mesh_path, read.name, read.parts, read.to_world};
  options.exact = s.exact;
  options.stations_per_span = s.stations;
  options.joints = s.joints_given ? s.joints : 0;
  options.ring_joints = s.ring_joints;
  options.ring_fit = s.ring_fit;
  options.sleep.enabled = s.sleep;
  options.under_skin = s.under_skin;
  options.morph = s.morph;
  if (skinned) options.skinned = &*skinned;
  sweep::tools::ProgressBar bar("baking");
  if (!s.quiet) options.progress = [&](int done, int total) { bar.update(done, total); };
  // The bake's files and the report go into place together, or none of them.
  sweep::io::Publication publication;
  options.publication = &publication;
  options.max_output_bytes = s.max_output_bytes;
  options.warn = sweep::tools::warn;
  const sweep::assets::BakeReport report = sweep::assets::run_bake(mesh, rig, binding, scene, options);
  bar.finish();
  const double total = since(start);
  if (!s.report.empty()) publication.add(s.report, report_text(s, report, load_seconds, total));
  publication.commit();

  if (!s.quiet) {
    using sweep::format_number;
    std::cout << "baked " << report.frames << " frames (" << format_number((report.frames - 1) / report.fps, 3)
              << " s at " << format_number(report.fps) << " fps, step " << format_number(report.step_seconds, 3)
              << " s) in " << format_number(total, 3) << " s: simulate "
              << format_number(report.simulate_seconds * 1e3, 3) << " ms, deform "
              << format_number(report.deform_seconds * 1e3, 3) << " ms, write "
              << format_number(report.write_seconds * 1e3, 3) << " ms\n";
    for (const auto& st : report.sweeps) {
      std::cout << "  " << st.name << std::string(st.name.size() < 12 ? 12 - st.name.size() : 0, ' ') << " "
                << (st.driven ? "driven" : "no force reaches it: skipped") << ", " << st.steps << " steps, deformed in "
                << st.frames_deformed << " frames, " << st.bound_vertex_count << " vertices\n";
      std::cout << "    sways at";
      for (std::size_t m = 0; m < st.sway.frequencies_hz.size(); ++m)
        std::cout << (m ? ", " : " ") << format_number(st.sway.frequencies_hz[m], 3);
      std::cout << " Hz, "
                << (st.sway.feels_gravity ? "droops " + format_number(st.sway.droop * 100, 3) + " % of its length"
                                          : std::string("feels no gravity (the paper's springs)"));
      if (st.driven) {
        std::cout << "; largest bend of a span " << format_number(st.largest_bend * 180 / std::numbers::pi, 3)
                  << "° (sections " << st.bend_span - 1 << "-" << st.bend_span << ", frame " << st.bend_frame << ")";
      }
      std::cout << "\n";
    }
    std::cout << "largest edge stretch " << format_number(report.max_stretch.ratio, 4) << "x";
    if (report.max_stretch.found) {
      std::cout << " (edge " << report.max_stretch.a << "-" << report.max_stretch.b << ", frame "
                << report.max_stretch_frame << " at t = " << format_number(report.max_stretch_frame / report.fps, 3)
                << " s)";
    }
    std::cout << " over " << report.stretch_edge_count << " edges, measured in "
              << format_number(report.stretch_seconds * 1e3, 3) << " ms\n";
    if (report.skin_joints > 0 && report.skin_in_character) {
      std::cout << "skinned .glb: " << report.skin_joints << " joints added to the character's skeleton (" << s.joints
                << " a part";
      if (s.ring_joints > 1) std::cout << ", " << s.ring_joints << " around each station but the root";
      std::cout << "); against the bake: max " << format_number(report.skin_error.max_relative * 100, 3)
                << " % of the part's length (frame " << report.skin_error.max_frame << ", vertex "
                << report.skin_error.max_vertex << "), RMS " << format_number(report.skin_error.rms_relative * 100, 3)
                << " %\n";
    } else if (report.skin_joints > 0) {
      std::cout << "skinned .glb: " << report.skin_joints << " joints (" << s.joints << " a sweep";
      if (s.ring_joints > 1) std::cout << ", " << s.ring_joints << " around each but the root";
      std::cout << ", and the body); against the bake: max " << format_number(report.skin_error.max_relative * 100, 3)
                << " % of the part's length (frame " << report.skin_error.max_frame << ", vertex "
                << report.skin_error.max_vertex << "), RMS " << format_number(report.skin_error.rms_relative * 100, 3)
                << " %\n";
    }
    for (const double t : report.teleport_times) {
      std::cout << "  the body jumped at t = " << format_number(t)
                << " s (a cut or respawn): the parts were put to rest there\n";
    }
    // One line an output: an .obj sequence as its pattern and count, not a line a frame.
    for (const fs::path& out : s.outputs) {
      const std::vector<fs::path> files = sweep::assets::bake_files(out, report.frames);
      if (files.size() == 1) {
        std::cout << "wrote " << files[0].string() << "\n";
      } else {
        std::cout << "wrote " << files.size() << " files " << files.front().string() << " ... "
                  << files.back().filename().string() << " (" << out.stem().string() << "_"
                  << std::string(files.front().stem().string().size() - out.stem().string().size() - 1, '#')
                  << out.extension().string() << ", one a frame)\n";
      }
    }
    if (!s.report.empty()) std::cout << "report " << s.report.string() << "\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return sweep::tools::guarded_main([&] {
    Settings s;
    CLI::App app{"Simulate a scene's forces on a rig and bake the animation of its mesh", "sweep-sim"};
    app.set_version_flag("--version", std::string("sweep-sim ") + SWEEP_VERSION);
    app.add_option("rig", s.rig, "Rig file (from sweep-fit)")->required();
    app.add_option("-o,--output", s.outputs,
                   "Output: .glb, .pc2 or .obj (a numbered sequence); repeatable. When the scene's "
                   "body plays a skinned glTF mesh's clip, .pc2 and .obj hold world positions and the "
                   ".glb is the asset whole (skeleton, clips, materials) with the parts' motion as "
                   "joints added to its skeleton (--morph: morph targets under its skin) and a "
                   "\"sweep bake\" animation playing both")
        ->required()
        ->check(sweep::tools::kNonEmptyName);
    app.add_option("-b,--binding", s.binding, "Binding file (default: the rig's path with .bind)")
        ->check(sweep::tools::kNonEmptyName);
    app.add_option("-s,--scene", s.scene, "Scene file (default: the rig file's own \"scene\")")
        ->check(sweep::tools::kNonEmptyName);
    app.add_option("--max-output-size", s.max_output_text,
                   "Refuse, before simulating, a bake whose files would take more than this many "
                   "bytes (suffixes K, M, G: powers of 1000; KiB, MiB, GiB: of 1024)")
        // Our own parse: CLI11's AsNumberWithUnit reads 0, -1 and an overflow as "no limit".
        ->check(CLI::Validator(
            [](std::string& text) {
              std::string why;
              return sweep::tools::read_byte_size(text, why) ? std::string() : why;
            },
            "SIZE", "BYTES"));
    app.add_option("--report", s.report, "Write a JSON report: frames, per-frame displacement, timings")
        ->check(sweep::tools::kNonEmptyName);
    app.add_option("--integrator", s.integrator, "Override the scene's integrator: exact, semi-implicit-euler, rk4");
    app.add_option("--substeps", s.substeps, "Override the scene's internal steps per frame")
        ->check(CLI::Range(1, 100000));
    app.add_option("--step", s.step, "Override the scene's internal step, seconds (independent of the frame rate)")
        ->check(sweep::tools::finite_range(sweep::limits::kMinStep, sweep::limits::kMaxStep));
    app.add_option("--threads", s.threads, "Threads for stepping and deforming (default: all cores)")
        ->check(CLI::Range(1, 1024));
    app.add_option("--stations", s.stations, "Fast path: stations per span (error falls as its square)")
        ->check(CLI::Range(1, 1024));
    auto* joints = app.add_option("--joints", s.joints_text,
                                  "Write each .glb as a skinned mesh instead of morph targets: N joints along "
                                  "each sweep (2 to 255, at most the sweep's stations; --joints alone, last or "
                                  "before another option: " +
                                      std::to_string(sweep::assets::kDefaultSkinJoints) +
                                      " or the fewest stations of any sweep where that is fewer, with --ring-joints " +
                                      std::to_string(sweep::assets::kDefaultRingJoints) +
                                      " by default, within 1 % of the length on the demo's scene); the summary "
                                      "and report give its error against the bake")
                       ->expected(0, 1);
    auto* ring =
        app.add_option("--ring-joints", s.ring_joints,
                       "With --joints: M joints around each station but the root, carrying the radial "
                       "change at their angles (1 to 64; 1: none, each station joint scales its whole "
                       "section; default " +
                           std::to_string(sweep::assets::kDefaultRingJoints) + "); also for a skinned clip's .glb");
    app.add_flag("--ring-fit", s.ring_fit,
                 "With --joints: fit the ring joints' keys by least squares over the vertices they "
                 "weigh (less error; every ring joint is keyed, a larger file)")
        ->needs(joints);
    app.add_flag("--morph", s.morph,
                 "When the scene's body plays a skinned glTF mesh's clip: write the .glb's parts' "
                 "motion as one morph target a frame under the skin instead of joints added to its "
                 "skeleton (the default)");
    app.add_flag("--under-skin", s.under_skin,
                 "When the scene's body plays a skinned glTF mesh's clip: .pc2 and .obj frames hold "
                 "each vertex before skinning, in the mesh's bind space (the parts' motion alone), "
                 "for a Mesh Cache modifier above the Armature modifier in Blender");
    app.add_flag("--exact", s.exact, "Deform with the exact per-vertex path (the reference; slower)");
    app.add_flag(
        "--no-sleep", [&](std::int64_t) { s.sleep = false; }, "Keep stepping sweeps whose motion has died out");
    app.add_flag("-q,--quiet", s.quiet, "No summary and no progress bar");
    if (const auto stop = sweep::tools::parse_command_line(app, argc, argv)) return *stop;
    if (s.quiet) sweep::io::set_note_sink(nullptr);
    if (!s.max_output_text.empty()) {
      std::string why;
      s.max_output_bytes = *sweep::tools::read_byte_size(s.max_output_text, why);
    }
    s.joints_given = joints->count() > 0;
    s.ring_given = ring->count() > 0;
    s.joints = sweep::assets::kDefaultSkinJoints;
    if (s.joints_given && !s.joints_text.empty()) s.joints = whole_number(s.joints_text, "--joints");
    return run(s);
  });
}
