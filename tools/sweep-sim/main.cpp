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
#include <optional>
#include <string>
#include <vector>

#include "sweep/assets/authored_scene.h"
#include "sweep/assets/bake.h"
#include "sweep/assets/bake_run.h"
#include "sweep/assets/bake_summary.h"
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

int run(Settings s) {
  const Clock::time_point start = Clock::now();
  // Named for an interrupt's message ("not written: ...") from the start: a signal while the rig,
  // mesh and binding load says what it stopped too.
  std::vector<fs::path> declared = s.outputs;
  if (!s.report.empty()) declared.push_back(s.report);
  sweep::io::declare_outputs(declared);
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
    const sweep::assets::DefaultSkinJoints chosen = sweep::assets::default_skin_joints(rig.sweeps, s.stations);
    s.joints = chosen.joints;
    if (const sweep::SweepDef* fewest = chosen.fewest) {
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
  sweep::assets::BakeSummarySettings told{.rig = s.rig,
                                          .outputs = s.outputs,
                                          .report = s.report,
                                          .exact = s.exact,
                                          .joints = s.joints,
                                          .ring_joints = s.ring_joints,
                                          .ring_fit = s.ring_fit,
                                          .load_seconds = since(start)};

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
  told.total_seconds = since(start);
  if (!s.report.empty()) publication.add(s.report, sweep::assets::bake_report_json(report, told));
  publication.commit();
  if (!s.quiet) sweep::assets::print_bake_summary(std::cout, report, told);
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
