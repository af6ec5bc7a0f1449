// Frame cost: one frame of the diplodocus with tail and neck moving (step plus deform), and
// skipping — four sweeps with a force on 1, 2, 3 or all 4 of them, and all four asleep.
//
// A frame is what sweep-sim does per output frame (lib/assets/bake_run.cpp): Simulator::advance_frame
// (a step of 1/480 s, exact integrator; sweeps side by side on the threads) and the fast path
// (8 stations per span) on every sweep that moved (deform_sweeps: side by side too). Time: median
// over the frames after the first 5, wall clock, per frame.
#include <thread>

#include "bench_common.h"
#include "sweep/assets/body_proxy.h"
#include "sweep/bind/fast_deform.h"
#include "sweep/sim/simulator.h"

namespace sweep::bench {
namespace {

// The internal step of every frame measured here: 16 steps a 30 fps frame (sweep-sim's default,
// Scene::kDefaultStep, today), fixed so that the tables compare across runs.
constexpr double kStep = 1.0 / 480;

using bind::FastDeformer;
using bind::Vec3f;

struct FrameCost {
  double median_us = 0;
  double step_us = 0;    // median of the simulation part
  double deform_us = 0;  // median of the deformation part
  int awake_at_end = 0;
};

// Runs `frames` frames of `scene` on `rig`, returning the median frame cost over frames [skip,
// end). Frames run back to back (a bake), or `pause` seconds apart (a runtime paced by its display:
// between frames the threads go to sleep and the caches cool down).
FrameCost frame_cost(const RealRig& rig, const sim::Scene& scene, int frames, int skip, double pause = 0) {
  const std::size_t nv = rig.mesh.vertex_count();
  std::vector<Vec3f> positions(nv);
  for (std::size_t v = 0; v < nv; ++v) positions[v] = rig.mesh.positions[v].cast<float>();
  sim::Simulator sim(rig.rig, scene);
  std::vector<std::unique_ptr<FastDeformer>> fast;
  for (int i = 0; i < sim.sweep_count(); ++i) {
    fast.push_back(std::make_unique<FastDeformer>(rig.rig.sweeps[i].rest, rig.binding.sweeps[i], positions, 8));
  }
  std::vector<double> total, step, deform;
  std::vector<bind::DeformJob> jobs;
  for (int k = 0; k < frames; ++k) {
    if (pause > 0) std::this_thread::sleep_for(std::chrono::duration<double>(pause));
    const auto t0 = Clock::now();
    sim.advance_frame();
    const auto t1 = Clock::now();
    jobs.clear();
    for (int i = 0; i < sim.sweep_count(); ++i) {
      if (sim.moved_last_frame(i)) jobs.push_back({fast[i].get(), &sim.sweep(i).deformed()});
    }
    bind::deform_sweeps(jobs, positions);
    const auto t2 = Clock::now();
    if (k < skip) continue;
    step.push_back(std::chrono::duration<double>(t1 - t0).count());
    deform.push_back(std::chrono::duration<double>(t2 - t1).count());
    total.push_back(std::chrono::duration<double>(t2 - t0).count());
  }
  FrameCost c{1e6 * median(total), 1e6 * median(step), 1e6 * median(deform), 0};
  for (int i = 0; i < sim.sweep_count(); ++i) c.awake_at_end += sim.is_awake(i);
  return c;
}

// Each field's median over several measurements of one case.
FrameCost median_cost(const std::vector<FrameCost>& runs) {
  const auto pick = [&](double FrameCost::*field) {
    std::vector<double> v;
    for (const FrameCost& c : runs) v.push_back(c.*field);
    return median(v);
  };
  return {pick(&FrameCost::median_us), pick(&FrameCost::step_us), pick(&FrameCost::deform_us),
          runs.back().awake_at_end};
}

sim::SceneForce tip_force(const RealRig& rig, int i, double start, double end, double magnitude) {
  sim::SceneForce f;
  f.sweep = rig.rig.sweeps[i].name;
  f.sweep_index = i;
  f.spec.t = 0.9 * rig.rig.sweeps[i].rest.length();
  f.spec.vector = Vec3(magnitude, 0, magnitude);
  f.spec.target = RotationTarget::chain;
  f.start = start;
  f.end = end;
  return f;
}

// Four bent, tapered tubes side by side in one mesh, each with ~6,000 vertices (like a diplodocus
// part), K = 16, n = 16 sweeps, every vertex bound.
RealRig four_tubes() {
  RealRig r;
  r.binding.sweeps.resize(4);
  for (int i = 0; i < 4; ++i) {
    tube::TubeParams p;
    p.length = 0.4;
    p.radius = 0.04;
    p.taper = 0.3;
    p.bend = 0.8;
    p.rings = 250;
    p.segments = 24;
    Mesh m = tube::make_tube(p);
    const Vec3 offset(0.3 * i, 0, 0);
    for (Vec3& v : m.positions) v += offset;
    SweepShape s = tube_sweep(p, 16, 16);
    for (Frame& f : s.frames) f.center += offset;
    SweepDef def = make_sweep("tube" + std::to_string(i), s);
    bind::SweepBinding b = locate_all(def.rest, m);
    const std::uint32_t base = static_cast<std::uint32_t>(r.mesh.vertex_count());
    for (auto& v : b.vertices) v += base;
    b.name = def.name;
    r.binding.sweeps[i] = b;
    r.rig.sweeps.push_back(def);
    for (const Vec3& v : m.positions) r.mesh.positions.push_back(v);  // faces are not needed here
  }
  r.binding.vertex_count = r.mesh.vertex_count();
  return r;
}

}  // namespace
}  // namespace sweep::bench

int main(int argc, char** argv) {
  using namespace sweep;
  using namespace sweep::bench;
  const Args args = parse_args(argc, argv);
  const int frames = args.quick ? 60 : 300;
  const int rounds = args.quick ? 3 : 9;  // each case measured once a round; median over rounds
  const int max_threads = omp_get_max_threads();
  std::string csv = "case,threads,frame_us,step_us,deform_us,ratio,awake_at_end\n";
  std::string md =
      "| case | threads | frame µs (median) | step µs | deform µs | × all driven "
      "|\n|---|---|---|---|---|---|\n";

  // ---- the diplodocus, tail and neck driven all the time --------------------------------------
  {
    const RealRig dino = diplodocus_rig();
    sim::Scene scene;  // 30 fps, exact integrator
    scene.step = kStep;
    scene.duration = frames / scene.fps + 1;
    scene.forces = {tip_force(dino, 0, 0, 1e9, 2.0), tip_force(dino, 1, 0, 1e9, 2.0)};
    std::size_t bound = 0;
    for (const auto& s : dino.binding.sweeps) bound += s.size();
    const std::string name = fmt("diplodocus tail + neck (%zu vertices), step 1/480 s", bound);
    // Rounds alternate the thread counts (see the four-sweep cases below); median over rounds.
    for (const double pause : {0.0, 1 / 60.0}) {
      const std::string label = pause > 0 ? name + ", frames 1/60 s apart" : name;
      const int threads = std::min(2, max_threads);
      std::vector<std::vector<FrameCost>> runs(threads);
      for (int r = 0; r < rounds; ++r) {
        for (int th = 1; th <= threads; ++th) {
          omp_set_num_threads(th);
          runs[th - 1].push_back(pause > 0 ? frame_cost(dino, scene, 30, 5, pause)
                                           : frame_cost(dino, scene, frames, 5));
        }
      }
      for (int th = 1; th <= threads; ++th) {
        const FrameCost c = median_cost(runs[th - 1]);
        csv += fmt("\"%s\",%d,%.4g,%.4g,%.4g,1,%d\n", label.c_str(), th, c.median_us, c.step_us, c.deform_us,
                   c.awake_at_end);
        md += fmt("| %s | %d | %.1f | %.1f | %.1f | — |\n", label.c_str(), th, c.median_us, c.step_us, c.deform_us);
      }
    }
  }

  // ---- material mode against the paper's springs, same clock, same run ------------
  // Tail and neck driven all the time at a step of 1/480 s; material mode with gravity
  // (the coupled chain stepped by its modes, pre-loaded weight, real moments) against the paper's
  // independent springs. Rounds alternate the two; median over rounds.
  {
    const RealRig paper = diplodocus_rig();
    const RealRig material = in_material(paper);
    sim::Scene scene;
    scene.step = kStep;
    scene.duration = frames / scene.fps + 1;
    scene.forces = {tip_force(paper, 0, 0, 1e9, 2.0), tip_force(paper, 1, 0, 1e9, 2.0)};
    sim::Scene heavy = scene;
    heavy.gravity = Vec3(0, -9.81, 0);
    for (sim::SceneForce& f : heavy.forces) {
      f.spec.moment = MomentModel::physical;
      f.spec.vector *= 5e4;  // N: a push that bends a 10 m tail visibly
    }
    // The same material frame on a body that walks and turns (cubic path, never still
    // over the run), in a gusty wind — against the material frame above.
    sim::Scene walking = heavy;
    {
      std::vector<sim::BodyKey> keys;
      for (int k = 0; k <= 12; ++k) {
        keys.push_back(
            {2.0 * k, Vec3(0.05 * k, 0, 0.01 * (k % 3)), Quat(Eigen::AngleAxisd(0.1 * std::sin(k), Vec3::UnitY()))});
      }
      walking.body = sim::BodyPath(keys, sim::BodyInterpolation::cubic);
      sim::WindSettings w;
      w.enabled = true;
      w.velocity = Vec3(0, 0, 4);
      w.gust = 0.5;
      w.turbulence = 0.2;
      walking.wind = sim::Wind(w);
    }
    std::vector<FrameCost> runs[3];
    for (int r = 0; r < rounds; ++r) {
      runs[0].push_back(frame_cost(paper, scene, frames, 5));
      runs[1].push_back(frame_cost(material, heavy, frames, 5));
      runs[2].push_back(frame_cost(material, walking, frames, 5));
    }
    const FrameCost a = median_cost(runs[0]), b = median_cost(runs[1]), c3 = median_cost(runs[2]);
    const int threads = omp_get_max_threads();
    for (int mode = 0; mode < 3; ++mode) {
      const FrameCost& c = mode == 0 ? a : mode == 1 ? b : c3;
      const char* labels[3] = {"diplodocus, the paper's springs, step 1/480 s",
                               "diplodocus, material mode + gravity, step 1/480 s",
                               "diplodocus, material mode + gravity, walking body and gusty wind"};
      const std::string ratio = mode == 0   ? "—"
                                : mode == 1 ? fmt("%.2f × the paper's", b.median_us / a.median_us)
                                            : fmt("%.2f × the still body's", c3.median_us / b.median_us);
      csv += fmt("\"%s\",%d,%.4g,%.4g,%.4g,%.4g,%d\n", labels[mode], threads, c.median_us, c.step_us, c.deform_us,
                 c.median_us / (mode == 2 ? b.median_us : a.median_us), c.awake_at_end);
      md += fmt("| %s | %d | %.1f | %.1f | %.1f | %s |\n", labels[mode], threads, c.median_us, c.step_us, c.deform_us,
                ratio.c_str());
    }
  }

  // ---- colliders: 0, 4 and 16 near the walking diplodocus, a tail on the ground, the body --
  // The walking material frame above with the demo's ground and three leg capsules (none touched:
  // the broad phase's cost), then the fourth leg and 11 spheres around the body (16), then a floor raised into the
  // tail's way so that it lies on it (the contact solver's cost), and the body as 24 spheres (the
  // body proxy: the tail hangs among them, untouched at rest). Same rounds, same run.
  {
    const RealRig material = in_material(diplodocus_rig());
    sim::Scene walking;
    walking.step = kStep;
    walking.duration = frames / walking.fps + 1;
    walking.gravity = Vec3(0, -9.81, 0);
    std::vector<sim::BodyKey> keys;
    for (int k = 0; k <= 12; ++k) {
      keys.push_back(
          {2.0 * k, Vec3(0.05 * k, 0, 0.01 * (k % 3)), Quat(Eigen::AngleAxisd(0.1 * std::sin(k), Vec3::UnitY()))});
    }
    walking.body = sim::BodyPath(keys, sim::BodyInterpolation::cubic);
    using sim::Collider;
    const std::vector<Collider> demo = {
        // rigs/diplodocus-path.scene.json
        Collider::plane(Vec3(0, -0.462, 0), Vec3::UnitY()),
        Collider::capsule(Vec3(-0.1915, -0.1739, -0.0871), Vec3(-0.2894, -0.3609, -0.1242), 0.0441),
        Collider::capsule(Vec3(0.1538, -0.2441, 0.13), Vec3(0.2263, -0.4616, 0.1177), 0.0333),
        Collider::capsule(Vec3(0.1483, -0.211, -0.0537), Vec3(0.176, -0.4187, -0.0961), 0.0376),
        Collider::capsule(Vec3(-0.1134, -0.2334, 0.1045), Vec3(-0.1207, -0.4139, 0.0611), 0.0387)};
    std::vector<sim::Scene> scenes(6, walking);
    scenes[1].colliders.assign(demo.begin(), demo.begin() + 4);
    scenes[2].colliders = demo;
    for (int k = 0; k < 11; ++k) {
      scenes[2].colliders.push_back(Collider::sphere(Vec3(-0.6 + 0.12 * k, 0.5, 0.3 * ((k % 3) - 1)), 0.03));
    }
    scenes[3] = scenes[2];
    scenes[3].colliders[0] = Collider::plane(Vec3(0, -0.30, 0), Vec3::UnitY());  // in the tail's way
    scenes[4] = scenes[3];
    scenes[4].body = {};  // the tail lying on the floor, the body still: settles, then sleeps
    scenes[4].gravity_start = sim::Scene::GravityStart::unloaded;  // it sags onto the floor: driven until it sleeps
    // The body itself, as sweep-sim fits it for "body_collider": {"spheres": 24} (the fit is load
    // time, not frame time, and is not measured here).
    io::SceneAuthoring::BodyCollider body;
    body.spheres = 24;
    scenes[5].colliders =
        assets::body_proxy(material.mesh, material.rig, material.binding, body, walking.contact_stations).colliders;
    const char* labels[6] = {"walking diplodocus (material, gravity), no collider",
                             "… ground and three legs, none touched",
                             "… 16 colliders, none touched",
                             "… 16 colliders, the tail on a raised floor",
                             "… the same, body still (settles, sleeps)",
                             "… the body proxy (24 spheres carried by the body)"};
    std::vector<FrameCost> runs[6];
    for (int r = 0; r < rounds; ++r) {
      for (int c = 0; c < 6; ++c) runs[c].push_back(frame_cost(material, scenes[c], frames, 5));
    }
    const FrameCost base = median_cost(runs[0]);
    for (int c = 0; c < 6; ++c) {
      const FrameCost m = median_cost(runs[c]);
      csv += fmt("\"%s\",%d,%.4g,%.4g,%.4g,%.4g,%d\n", labels[c], omp_get_max_threads(), m.median_us, m.step_us,
                 m.deform_us, m.median_us / base.median_us, m.awake_at_end);
      md += fmt("| %s | %d | %.1f | %.1f | %.1f | %.2f × no collider |\n", labels[c], omp_get_max_threads(),
                m.median_us, m.step_us, m.deform_us, m.median_us / base.median_us);
    }
  }

  // ---- four sweeps: 1..4 driven, and asleep, on 1 and on 2 threads ---------------------------
  // The cases are measured in rounds, each round running every case once, and each figure is the
  // median over the rounds: this VM's slow spells last seconds, and a ratio between two cases
  // measured seconds apart would otherwise compare two machines.
  const RealRig tubes = four_tubes();
  struct Case {
    std::string name;
    sim::Scene scene;
    int frames = 0, skip = 0;
  };
  std::vector<Case> cases;
  for (int driven = 4; driven >= 1; --driven) {
    Case c{fmt("4 sweeps, %d driven", driven), {}, frames, 5};
    c.scene.duration = frames / c.scene.fps + 1;
    for (int i = 0; i < driven; ++i) c.scene.forces.push_back(tip_force(tubes, i, 0, 1e9, 2.0));
    cases.push_back(c);
  }
  {
    // A short push on all four at the start; the motion dies out (ζ = 0.3 at 1.5 Hz: e^-2.8 a
    // second) and every sweep falls asleep. Measured over the last third of the frames.
    const int long_frames = 30 * 20;
    Case c{"4 sweeps, all asleep (after a push)", {}, long_frames, 2 * long_frames / 3};
    c.scene.duration = long_frames / c.scene.fps + 1;
    for (int i = 0; i < 4; ++i) c.scene.forces.push_back(tip_force(tubes, i, 0, 0.1, 2.0));
    cases.push_back(c);
    Case none{"4 sweeps, no force at all", {}, frames, 5};
    none.scene.duration = frames / none.scene.fps + 1;
    cases.push_back(none);
  }
  for (Case& c : cases) c.scene.step = kStep;
  for (int th = 1; th <= std::min(2, max_threads); ++th) {
    omp_set_num_threads(th);
    std::vector<std::vector<FrameCost>> runs(cases.size());
    for (int r = 0; r < rounds; ++r) {
      for (std::size_t i = 0; i < cases.size(); ++i)
        runs[i].push_back(frame_cost(tubes, cases[i].scene, cases[i].frames, cases[i].skip));
    }
    std::vector<FrameCost> result;
    for (const auto& r : runs) result.push_back(median_cost(r));
    const double all = result.front().median_us;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const FrameCost& c = result[i];
      const std::string& name = cases[i].name;
      csv += fmt("\"%s\",%d,%.4g,%.4g,%.4g,%.4g,%d\n", name.c_str(), th, c.median_us, c.step_us, c.deform_us,
                 c.median_us / all, c.awake_at_end);
      md += fmt("| %s | %d | %.2f | %.2f | %.2f | %.3f |\n", name.c_str(), th, c.median_us, c.step_us, c.deform_us,
                c.median_us / all);
    }
  }
  write_text(args.out / "skip.csv", csv);
  write_text(args.out / "skip.md", md);
  std::fputs(md.c_str(), stdout);
  return 0;
}
