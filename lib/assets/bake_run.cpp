#include "sweep/assets/bake_run.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>

#include "sweep/assets/bake.h"
#include "sweep/assets/character_joints.h"
#include "sweep/bind/deform.h"
#include "sweep/bind/fast_deform.h"
#include "sweep/core/error.h"
#include "sweep/core/fold_check.h"
#include "sweep/core/text.h"

using sweep::bind::deform_sweeps;

namespace sweep::assets {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

namespace {

// Engines keep every morph target of a mesh on the GPU: three.js (r133 and later) as one layer
// each of a WebGL 2 texture array, and WebGL 2 promises only 256 layers
// (MAX_ARRAY_TEXTURE_LAYERS, its specification's minimum). Past that a .glb bake may not play.
constexpr int kPortableMorphTargets = 256;
// Many loaders hold a buffer with a signed 32-bit size (a JavaScript ArrayBuffer in most browsers,
// .NET arrays in Unity importers): past 2 GiB few viewers open a .glb, though the format takes 4.
constexpr std::uint64_t kPortableGlbBytes = std::uint64_t{1} << 31;

// A part whose as-modelled rest does not hold under gravity (core/held_rest.h): what it is, what
// the bake does with it, and what would make it hold.
std::string held_rest_warning(const SweepBakeStats& st, sim::Scene::GravityStart start) {
  const HeldRest& held = *st.held_rest;
  std::string text =
      "part \"" + st.name +
      "\" cannot hold its modelled pose under gravity (β = q L³/EI = " + format_number(held.beta, 3) +
      "; its stiffness is " + format_number(held.load_factor, 3) +
      "x too low: nudged, it falls away from it, rolling over or buckling sideways, the nudge growing e-fold every " +
      format_number(1 / held.growth_rate, 3) + " s)";
  const std::string stiffer = "a material " + format_number(held.load_factor, 3) + "x stiffer or a quicker preset";
  if (start == sim::Scene::GravityStart::as_modelled) {
    return text + ": it starts from that pose, as \"gravity_start\": \"as-modelled\" asks; for a pose that holds, " +
           stiffer + ", or \"gravity_start\": \"auto\" to start it unloaded";
  }
  return text + ": it starts unloaded and droops from the modelled pose instead; for the modelled pose to hold, " +
         stiffer + " (\"gravity_start\": \"unloaded\" starts it unloaded without this warning)";
}

std::string megabytes(std::uint64_t bytes) {
  const double mb = static_cast<double>(bytes) / 1e6;
  return mb < 1000 ? format_number(mb, 3) + " MB" : format_number(mb / 1000, 3) + " GB";
}

// Before the simulation: the files' estimated size against the limit, and what engines take.
void check_output_size(const BakeOptions& options, const std::vector<std::unique_ptr<BakeWriter>>& writers) {
  std::uint64_t total = 0;
  std::string each;
  for (std::size_t k = 0; k < writers.size(); ++k) {
    total += writers[k]->estimated_bytes();
    each += (k ? ", " : "") + options.outputs[k].string() + " " + megabytes(writers[k]->estimated_bytes());
    const int targets = writers[k]->morph_targets();
    if (targets > kPortableMorphTargets && options.warn) {
      options.warn(options.outputs[k].string() + ": " + std::to_string(targets) +
                   " morph targets (one a frame); engines keep them all on the GPU, and three.js "
                   "on WebGL 2 is only sure of " +
                   std::to_string(kPortableMorphTargets) +
                   " (texture array layers): it may not play. For Blender, Houdini or 3ds Max "
                   "bake to .pc2; for engines, fewer frames (a lower fps in the scene)");
    }
    if (targets > 0 && writers[k]->estimated_bytes() > kPortableGlbBytes && options.warn) {
      options.warn(options.outputs[k].string() + ": about " + megabytes(writers[k]->estimated_bytes()) +
                   "; past 2 GiB few viewers open a .glb (browsers and Unity hold a buffer with a "
                   "signed 32-bit size). For Blender, Houdini or 3ds Max bake to .pc2");
    }
  }
  if (options.max_output_bytes > 0 && total > options.max_output_bytes) {
    fail(ErrorCategory::output, "the bake would write about " + megabytes(total) + " (" + each +
                                    "), more than the limit of " + megabytes(options.max_output_bytes) +
                                    "; nothing was written");
  }
}

}  // namespace

BakeReport run_bake(const Mesh& mesh, const Rig& rig, const bind::Binding& binding, const sim::Scene& scene,
                    const BakeOptions& options) {
  if (options.outputs.empty()) fail(ErrorCategory::usage, "no output file given");
  if (options.stations_per_span < 1) fail(ErrorCategory::usage, "stations per span must be at least 1");
  if (options.joints != 0) {
    bool glb = false;
    for (const auto& out : options.outputs) glb = glb || lower_extension(out) == "glb";
    if (!glb) fail(ErrorCategory::usage, "--joints: skins a .glb output, and none is given");
  }
  std::vector<SkinSweep> skin_sweeps;
  for (std::size_t i = 0; options.joints != 0 && i < rig.sweeps.size(); ++i)
    skin_sweeps.push_back({rig.sweeps[i].name, &rig.sweeps[i].rest, &binding.sweeps[i]});
  const SkinLayout skin_layout{options.joints, options.ring_joints, options.ring_motion, options.ring_fit};
  if (options.joints != 0) check_skin_joints(skin_layout, skin_sweeps, options.stations_per_span);
  const std::size_t nv = mesh.vertex_count();
  const int sweeps = static_cast<int>(rig.sweeps.size());

  std::vector<bind::Vec3f> rest(nv), positions(nv);
  for (std::size_t v = 0; v < nv; ++v) rest[v] = mesh.positions[v].cast<float>();
  positions = rest;

  if (options.under_skin && options.skinned == nullptr) {
    fail(ErrorCategory::usage,
         "--under-skin: the scene's body plays no skinned mesh's clip, so there is no skin to "
         "write the frames under");
  }
  if (options.morph && options.skinned == nullptr) {
    fail(ErrorCategory::usage,
         "--morph: the scene's body plays no skinned mesh's clip; a .glb bake of any other "
         "mesh is morph targets already");
  }
  if (options.morph && options.joints != 0) {
    fail(ErrorCategory::usage,
         "--morph and --joints ask for two different .glb bakes of a skinned clip (morph "
         "targets under the skin, or joints in its skeleton); give one");
  }
  // A skinned clip with joints: they join the character's own skeleton (character_joints.h).
  std::unique_ptr<CharacterJoints> character;
  if (options.skinned != nullptr && options.joints != 0)
    character = std::make_unique<CharacterJoints>(*options.skinned, skin_sweeps, skin_layout, rest);
  // The simulators: one for the whole rig, or with a skinned clip one a sweep, on its root joint's
  // path (sweep i is sweep of_sweep[i].second of simulator of_sweep[i].first).
  std::vector<Rig> part_rigs;
  std::vector<sim::Scene> part_scenes;
  std::vector<std::unique_ptr<sim::Simulator>> sims;
  std::vector<std::pair<int, int>> of_sweep;
  int preroll_frames = 0;
  if (options.skinned == nullptr) {
    sims.push_back(std::make_unique<sim::Simulator>(rig, scene, options.sleep));
    for (int i = 0; i < sweeps; ++i) of_sweep.emplace_back(0, i);
  } else {
    preroll_frames = options.skinned->preroll_frames();
    const double preroll = preroll_frames / scene.fps;
    double longest = 0;
    for (const SweepDef& def : rig.sweeps) longest = std::max(longest, def.rest.length());
    part_rigs.reserve(sweeps);
    part_scenes.reserve(sweeps);  // the simulators keep references to these
    for (int i = 0; i < sweeps; ++i) {
      Rig r = rig;
      r.sweeps = {rig.sweeps[i]};
      part_rigs.push_back(std::move(r));
      sim::Scene s = scene;
      s.duration = scene.duration + preroll;
      s.body = options.skinned->sweep_path(i, s.duration);
      // The keys' own bend of the part, sampled at the internal step, loads its springs.
      s.keyed_bends.clear();
      s.keyed_bends.push_back(options.skinned->keyed_bend(i, s.duration, s.step_seconds()));
      if (s.teleport_distance == 0) s.teleport_distance = longest;  // as for the whole rig
      s.forces.clear();
      for (sim::SceneForce f : scene.forces) {
        if (f.sweep_index != i) continue;
        f.sweep_index = 0;
        f.start += preroll;
        f.end += preroll;
        s.forces.push_back(f);
      }
      part_scenes.push_back(std::move(s));
      sims.push_back(std::make_unique<sim::Simulator>(part_rigs.back(), part_scenes.back(), options.sleep));
      // The simulator keeps its own copy of the keyed bend (a sample a section an internal step).
      part_scenes.back().keyed_bends = {};
      of_sweep.emplace_back(i, 0);
    }
  }
  auto sim_of = [&](int i) -> sim::Simulator& { return *sims[of_sweep[i].first]; };
  // Only driven sweeps' vertices can ever move: the writers are told, so glTF stores sparse
  // targets and the others skip the rest.
  std::vector<std::uint32_t> animated;
  std::vector<std::unique_ptr<bind::FastDeformer>> fast(sweeps);
  BakeReport report;
  std::vector<std::optional<FoldMeter>> folds(sweeps);
  const Vec3 start_gravity = scene.body.at(0).rotation.conjugate() * scene.gravity;
  for (int i = 0; i < sweeps; ++i) {
    const bind::SweepBinding& table = binding.sweeps[i];
    SweepBakeStats& st = report.sweeps.emplace_back();
    st.name = rig.sweeps[i].name;
    st.driven = sim_of(i).is_driven(of_sweep[i].second);
    st.bound_vertex_count = table.size();
    report.sweeps[i].sway = sway_figures(rig.sweeps[i], start_gravity);
    st.held_rest = sim_of(i).held_rest(of_sweep[i].second);
    st.as_modelled = sim_of(i).starts_as_modelled(of_sweep[i].second);
    if (st.held_rest && !st.held_rest->holds() && options.warn)
      options.warn(held_rest_warning(st, scene.gravity_start));
    if (!report.sweeps[i].driven) continue;
    folds[i].emplace(rig.sweeps[i].rest);
    animated.insert(animated.end(), table.vertices.begin(), table.vertices.end());
    if (options.exact) continue;
    fast[i] = std::make_unique<bind::FastDeformer>(rig.sweeps[i].rest, table, rest, options.stations_per_span);
    report.sweeps[i].work_blocks = fast[i]->block_count();
    report.sweeps[i].blocks_in_place = fast[i]->direct_block_count();
  }
  std::sort(animated.begin(), animated.end());
  // Sweeps are deformed side by side (deform_sweeps): each vertex must belong to one sweep, as
  // bind() and the binding file guarantee; a binding built otherwise is refused, not raced on.
  if (const auto twice = std::adjacent_find(animated.begin(), animated.end()); twice != animated.end()) {
    fail(ErrorCategory::bad_input, "binding: vertex " + std::to_string(*twice) + " is bound by more than one sweep");
  }

  std::vector<std::unique_ptr<BakeWriter>> writers;
  BakeInfo info;
  info.frame_count = scene.frame_count();
  info.fps = scene.fps;
  info.animated_vertices = animated;
  info.body_moves = scene.body.moves();
  if (options.skinned != nullptr) {
    info.animated_vertices.reset();  // the clip moves every vertex
    info.body_moves = false;         // the positions are the world's
    info.skinned = options.skinned;
    info.part_vertices = animated;
    info.character_joints = character.get();
  }
  info.source = options.source;
  info.warn = options.warn;
  std::vector<SkinPoser*> skins;  // the skinned writers among them
  std::vector<char> glb_output;
  for (const auto& out : options.outputs) {
    if (options.joints != 0 && character == nullptr && lower_extension(out) == "glb") {
      SkinBakeWriter skin = make_skin_bake_writer(out, skin_sweeps, skin_layout);
      writers.push_back(std::move(skin.writer));
      skins.push_back(skin.poser);
    } else {
      writers.push_back(make_bake_writer(out));
    }
    writers.back()->begin(mesh, info);
    glb_output.push_back(lower_extension(out) == "glb");
  }
  check_output_size(options, writers);

  const Clock::time_point meter_start = Clock::now();
  const EdgeStretchMeter stretch_meter(mesh, animated, rest);
  report.stretch_edge_count = stretch_meter.edge_count();
  report.stretch_seconds += seconds_since(meter_start);

  // The exact path rebuilds the whole mesh in double from the binding (the reference).
  std::vector<Vec3> exact_out(options.exact ? nv : 0);
  std::vector<const SweepShape*> shapes(sweeps);
  std::vector<bind::DeformJob> jobs;  // the fast path's work this frame
  jobs.reserve(sweeps);

  report.frames = info.frame_count;
  report.fps = scene.fps;
  report.step_seconds = scene.step_seconds();
  double max_displacement = 0;
  double edge_stretch = 1;
  std::vector<bind::Vec3f> world(options.skinned != nullptr ? nv : 0);
  {
    const auto t0 = Clock::now();
    for (int k = 0; k < preroll_frames; ++k)
      for (auto& sim : sims) sim->advance_frame();
    report.simulate_seconds += seconds_since(t0);
  }
  for (int k = 0; k < info.frame_count; ++k) {
    auto t0 = Clock::now();
    if (k > 0) {
      for (auto& sim : sims) {
        const std::size_t told = sim->skipped_colliders().size();
        sim->advance_frame();
        // A teleport that carried a part through a world collider unmet: said as it happens.
        for (std::size_t m = told; m < sim->skipped_colliders().size() && options.warn; ++m)
          options.warn(sim->skipped_colliders()[m]);
      }
    }
    report.simulate_seconds += seconds_since(t0);

    t0 = Clock::now();
    FrameStats stats;
    stats.time = k / scene.fps;
    bool any_moved = false;
    jobs.clear();
    for (int i = 0; i < sweeps; ++i) {
      const sim::Simulator& sim = sim_of(i);
      const int j = of_sweep[i].second;
      shapes[i] = &sim.sweep(j).deformed();
      // After a preroll frame 0 is not the rest pose: every driven sweep is deformed there.
      if (k == 0 ? !(preroll_frames > 0 && report.sweeps[i].driven) : !sim.moved_last_frame(j)) continue;
      any_moved = true;
      ++stats.awake_sweeps;
      ++report.sweeps[i].frames_deformed;
      folds[i]->measure(*shapes[i], k);
      if (rig.sweeps[i].material)
        report.sweeps[i].largest_rotation =
            std::max(report.sweeps[i].largest_rotation, sim.sweep(j).largest_rotation());
      if (fast[i]) jobs.push_back({fast[i].get(), shapes[i]});
    }
    deform_sweeps(jobs, positions);
    if (options.exact && any_moved) {
      bind::deform_exact(binding, shapes, mesh.positions, exact_out);
      for (std::uint32_t v : animated) positions[v] = exact_out[v].cast<float>();
    }
    if (any_moved) {
      max_displacement = 0;
      for (std::uint32_t v : animated)
        max_displacement = std::max(max_displacement, double((positions[v] - rest[v]).norm()));
      const Clock::time_point stretch_start = Clock::now();
      const EdgeStretch now = stretch_meter.measure(positions);
      report.stretch_seconds += seconds_since(stretch_start);
      edge_stretch = now.ratio;
      if (now.ratio > report.max_stretch.ratio) {
        report.max_stretch = now;
        report.max_stretch_frame = k;
      }
    }
    stats.max_displacement = max_displacement;
    stats.edge_stretch = edge_stretch;
    report.deform_seconds += seconds_since(t0);

    t0 = Clock::now();
    BodyPose pose;
    if (info.body_moves) {
      const sim::BodyState body = sims.front()->body();
      pose.rotation = body.rotation;
      pose.translation = body.translation;
    }
    for (SkinPoser* skin : skins) skin->pose(shapes);
    if (options.skinned != nullptr) options.skinned->pose(k / scene.fps, positions, world);
    if (character != nullptr) character->pose(shapes, positions, world, k);
    // A skinned clip: world positions, or (under_skin, .pc2 and .obj) the positions the parts
    // deformed in the rest pose, which are each vertex before skinning: the clip places a bound
    // vertex by its skinning matrix applied to them (SkinnedClip::pose).
    for (std::size_t w = 0; w < writers.size(); ++w) {
      const bool world_frame = options.skinned != nullptr && !(options.under_skin && !glb_output[w]);
      writers[w]->frame(k, world_frame ? world : positions, pose);
    }
    report.write_seconds += seconds_since(t0);
    report.per_frame.push_back(stats);
    if (options.progress) options.progress(k + 1, info.frame_count);
  }
  auto t0 = Clock::now();
  for (auto& w : writers) {
    if (options.publication) {
      w->finish_into(*options.publication);
    } else {
      w->finish();
    }
    for (const auto& f : w->files()) report.files.push_back(f);
  }
  report.write_seconds += seconds_since(t0);
  for (int i = 0; i < sweeps; ++i) {
    SweepBakeStats& st = report.sweeps[i];
    st.steps = sim_of(i).steps_taken(of_sweep[i].second);
    if (const sim::Simulator::ChainSwitch& to_exact = sim_of(i).chain_switch(of_sweep[i].second); to_exact.time >= 0) {
      // On the bake's clock: a skinned clip's preroll ran before its frame 0.
      st.exact_chain_time = to_exact.time - preroll_frames / scene.fps;
      st.exact_chain_angle = to_exact.angle;
    }
    if (!folds[i]) continue;
    const FoldMeter& f = *folds[i];
    st.largest_bend = f.largest_bend;
    st.bend_span = f.bend_span;
    st.bend_frame = f.bend_frame;
    st.fold_frame = f.fold_frame;
    st.fold_span = f.fold_span;
    st.cross_frame = f.cross_frame;
    st.cross_a = f.cross_a;
    st.cross_b = f.cross_b;
    if (!options.warn) continue;
    const auto at = [&](int frame) {
      return "frame " + std::to_string(frame) + ", t = " + format_number(frame / scene.fps, 3) + " s";
    };
    if (f.fold_frame >= 0) {
      options.warn("part \"" + st.name + "\" folds past 90° within one span (sections " +
                   std::to_string(f.fold_span - 1) + "-" + std::to_string(f.fold_span) + ", first at " +
                   at(f.fold_frame) + "; largest bend " + format_number(f.largest_bend * 180 / std::numbers::pi, 3) +
                   "°): stiffer or more damped settings (a \"preset\"), or a gentler motion");
    }
    if (f.cross_frame >= 0) {
      options.warn("part \"" + st.name + "\" passes through itself: the discs of sections " +
                   std::to_string(f.cross_a) + " and " + std::to_string(f.cross_b) + " cross (first at " +
                   at(f.cross_frame) + ")");
    }
  }
  if (!skins.empty()) {
    report.skin_joints = skins.front()->joint_count();
    report.skin_error = skins.front()->skin_error();
  }
  if (character != nullptr) {
    report.skin_joints = static_cast<int>(character->joints().size());
    report.skin_in_character = true;
    report.skin_error = character->error();
  }
  for (const auto& sim : sims) {
    for (const int frame : sim->teleports())
      if (frame >= preroll_frames) report.teleport_times.push_back((frame - preroll_frames) / scene.fps);
  }
  std::sort(report.teleport_times.begin(), report.teleport_times.end());
  report.teleport_times.erase(std::unique(report.teleport_times.begin(), report.teleport_times.end()),
                              report.teleport_times.end());
  return report;
}

}  // namespace sweep::assets
