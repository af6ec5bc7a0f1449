// Integration: integrator × time step against the closed-form damped oscillator, cost per step, and
// the frame-rate spread — the same scene baked at 24, 30, 60 and 144 fps, poses compared at the
// times all four share.
//
// Oscillator error measure: |x(T) − x*(T)| / |x0 − f/k| at T = 1 s, where x* is the textbook closed
// form (evaluated here in long double, independently of lib/core) for m = 1 kg, f0 = 1.5 Hz,
// ζ = 0.1, x0 = 1, v0 = 0, under a constant force of 2 N. "diverged" = the value left 1e6 of it.
// Frame-rate spread measure: the largest distance of any bound vertex (exact path) from the same
// vertex of the 144 fps bake with the same clock and integrator, over every time all frame rates
// share (every 1/6 s), relative to the part's length. With a step of its own the simulator's
// internal steps do not depend on the frame rate (frames are reached by an exact partial step), so
// the spread is rounding; with the old clock (substeps per frame) the step follows the frame rate.
// Then the follower-load step table: see its section below.
#include <random>

#include "bench_common.h"
#include "sweep/bind/deform.h"
#include "sweep/core/oscillator.h"
#include "sweep/io/scene_json.h"
#include "sweep/sim/scene.h"
#include "sweep/sim/simulator.h"

namespace sweep::bench {
namespace {

// Closed form of m x'' + c x' + k x = f, x(0) = x0, v(0) = 0, under-damped, long double.
long double closed_form(long double m, long double c, long double k, long double f, long double x0, long double t) {
  const long double alpha = c / (2 * m), w2 = k / m;
  const long double beta = std::sqrt(w2 - alpha * alpha);
  const long double eq = f / k, a = x0 - eq;
  return eq + std::exp(-alpha * t) * (a * std::cos(beta * t) + (alpha * a / beta) * std::sin(beta * t));
}

struct SpreadRow {
  std::string integrator;
  std::string clock;
  int fps = 0;
  double max_dev = 0, max_dev_rel = 0;
};

}  // namespace
}  // namespace sweep::bench

int main(int argc, char** argv) {
  using namespace sweep;
  using namespace sweep::bench;
  const Args args = parse_args(argc, argv);
  const Integrator integrators[] = {Integrator::exact, Integrator::rk4, Integrator::semi_implicit_euler};

  // ---- integrator × dt ------------------------------------------------------------------------
  const SpringSettings spring{1.0, 1.5, 0.1};
  const OscillatorParams p{spring.mass, spring.damping(), spring.stiffness()};
  const double force = 2.0, x0 = 1.0, T = 1.0;
  const long double ref = closed_form(p.mass, p.damping, p.stiffness, force, x0, T);
  const double scale = std::abs(x0 - force / p.stiffness);
  std::string csv = "integrator,dt,steps,error_over_amplitude,ns_per_oscillator_step,map_us\n";
  std::string md =
      "| integrator | dt (s) | ω·dt | error at T = 1 s / amplitude | ns per oscillator step | map "
      "setup µs |\n"
      "|---|---|---|---|---|---|\n";
  const int divisions[] = {4, 10, 24, 30, 60, 120, 144, 240, 480, 1000, 10000};
  // Cost: one step of 4,096 oscillators (a flat loop, as ElasticSweep does it), per oscillator.
  constexpr int kBank = 4096;
  std::vector<double> xs(kBank, 0.5), vs(kBank, 0.0), fs(kBank, 1.0);
  for (Integrator integ : integrators) {
    for (int nsteps : divisions) {
      const double dt = T / nsteps;
      const StepMap map = make_step_map(p, dt, integ);
      double x = x0, v = 0;
      bool diverged = false;
      for (int s = 0; s < nsteps && !diverged; ++s) {
        map.apply(x, v, force);
        diverged = !(std::abs(x) < 1e6);
      }
      const double err = diverged ? -1 : static_cast<double>(std::abs(static_cast<long double>(x) - ref)) / scale;
      std::vector<StepMap> maps(kBank, map);
      const double step_s = median_seconds(args.quick ? 51 : 201, [&] {
        for (int m = 0; m < kBank; ++m) maps[m].apply(xs[m], vs[m], fs[m]);
        for (int m = 0; m < kBank; ++m) xs[m] = std::min(std::max(xs[m], -1e3), 1e3);  // keep it bounded
      });
      const double map_s = median_seconds(args.quick ? 101 : 1001, [&] {
        volatile double sink = make_step_map(p, dt, integ).xx;
        (void)sink;
      });
      const std::string name(integrator_name(integ));
      csv += fmt("%s,%.6g,%d,%.6g,%.4g,%.4g\n", name.c_str(), dt, nsteps, err, 1e9 * step_s / kBank, 1e6 * map_s);
      md += fmt("| %s | 1/%d | %.3g | %s | %.2g | %.2g |\n", name.c_str(), nsteps, std::sqrt(p.stiffness / p.mass) * dt,
                diverged ? "diverged" : fmt("%.2e", err).c_str(), 1e9 * step_s / kBank, 1e6 * map_s);
    }
  }
  write_text(args.out / "integrate.csv", csv);
  write_text(args.out / "integrate.md", md);
  std::fputs(md.c_str(), stdout);

  // ---- frame-rate spread ----------------------------------------------------------------------
  const RealRig dino = diplodocus_rig();
  // step > 0: the simulator's own clock; else the old one, `substeps` steps per frame.
  auto make_scene = [&](int fps, double step, int substeps, Integrator integ) {
    sim::Scene s;
    s.duration = 2.0;
    s.fps = fps;
    s.step = step;
    s.substeps = step > 0 ? 0 : substeps;
    s.integrator = integ;
    // The tail pushed sideways at its tip for half a second (chain: it bends as a whole) and the
    // neck pushed down for a third of a second; both then swing free.
    for (int i = 0; i < 2; ++i) {
      sim::SceneForce f;
      f.sweep = dino.rig.sweeps[i].name;
      f.sweep_index = i;
      f.spec.t = 0.9 * dino.rig.sweeps[i].rest.length();
      f.spec.theta = 0.0;
      f.spec.vector = i == 0 ? Vec3(0, 0, 5.0) : Vec3(0, -5.0, 0);
      f.spec.target = RotationTarget::chain;
      f.spec.moment = MomentModel::physical;
      f.start = 0;
      f.end = i == 0 ? 0.5 : 1.0 / 3;
      s.forces.push_back(f);
    }
    return s;
  };
  // Poses at t = 0, 1/6, ..., 2 s: the exact-path vertices of both parts.
  auto bake = [&](const sim::Scene& scene) {
    sim::Simulator sim(dino.rig, scene, sim::SleepSettings{0, 0, 0, false});
    const int every = static_cast<int>(std::lround(scene.fps / 6));
    std::vector<std::vector<Vec3>> poses;
    std::vector<Vec3> out(dino.mesh.vertex_count());
    for (int k = 0; k < scene.frame_count(); ++k) {
      if (k > 0) sim.advance_frame();
      if (k % every) continue;
      std::vector<const SweepShape*> shapes{&sim.sweep(0).deformed(), &sim.sweep(1).deformed()};
      bind::deform_exact(dino.binding, shapes, dino.mesh.positions, out);
      poses.push_back(out);
    }
    return poses;
  };
  double length = 0;
  for (const auto& d : dino.rig.sweeps) length = std::max(length, d.rest.length());
  auto deviation = [&](const std::vector<std::vector<Vec3>>& a, const std::vector<std::vector<Vec3>>& b) {
    double dev = 0;
    for (std::size_t q = 0; q < std::min(a.size(), b.size()); ++q) {
      for (const auto& sw : dino.binding.sweeps) {
        for (std::uint32_t v : sw.vertices) dev = std::max(dev, (a[q][v] - b[q][v]).norm());
      }
    }
    return dev;
  };
  struct Clock {
    std::string name;
    double step;
    int substeps;
  };
  const Clock clocks[] = {{fmt("step %.4g s (the default)", sim::Scene::kDefaultStep), sim::Scene::kDefaultStep, 0},
                          {"step 1/100 s", 0.01, 0},
                          {"1 substep per frame (old clock)", 0, 1},
                          {"4 substeps per frame (old clock)", 0, 4}};
  std::vector<SpreadRow> rows;
  for (const Clock& clock : clocks) {
    for (Integrator integ : integrators) {
      const auto reference = bake(make_scene(144, clock.step, clock.substeps, integ));
      for (int fps : {24, 30, 60}) {
        const double dev = deviation(bake(make_scene(fps, clock.step, clock.substeps, integ)), reference);
        rows.push_back({std::string(integrator_name(integ)), clock.name, fps, dev, dev / length});
      }
    }
  }
  csv = "integrator,clock,fps,max_vertex_deviation_from_144fps,over_length\n";
  md = "| clock | integrator | 24 fps | 30 fps | 60 fps |\n|---|---|---|---|---|\n";
  for (std::size_t r = 0; r < rows.size(); r += 3) {
    md += fmt("| %s | %s |", rows[r].clock.c_str(), rows[r].integrator.c_str());
    for (std::size_t c = 0; c < 3; ++c) md += fmt(" %.2e |", rows[r + c].max_dev_rel);
    md += "\n";
  }
  for (const SpreadRow& r : rows) {
    csv += fmt("%s,%s,%d,%.6g,%.6g\n", r.integrator.c_str(), r.clock.c_str(), r.fps, r.max_dev, r.max_dev_rel);
  }
  write_text(args.out / "framerate.csv", csv);
  write_text(args.out / "framerate.md", md);
  std::fputs(md.c_str(), stdout);

  // ---- follower loads: step against error and cost -------------------------------------------
  // The diplodocus Fig. 4 scene (rigs/diplodocus-fig4.scene.json), exact integrator: loads that
  // follow the moving surface are re-split at the predicted mid-step pose (second order). Error:
  // the largest section pose difference (centres, radii, rotation angle × length) over every frame
  // against a step 64 times finer than 1/480 s, over the part's length.
  sim::Scene fig4 = io::read_scene(source_dir() / "rigs/diplodocus-fig4.scene.json", dino.rig);
  fig4.substeps = 0;
  auto section_poses = [&](double step) {
    sim::Scene s = fig4;
    s.step = step;
    sim::Simulator sim(dino.rig, s, sim::SleepSettings{0, 0, 0, false});
    std::vector<double> out;
    for (int k = 1; k < s.frame_count(); ++k) {
      sim.advance_frame();
      for (int i = 0; i < sim.sweep_count(); ++i) {
        const ElasticSweep& e = sim.sweep(i);
        const double len = e.rest().length();
        for (int j = 0; j < e.rest().section_count(); ++j) {
          const Frame& f = e.deformed().frames[j];
          for (int c = 0; c < 3; ++c) out.push_back(f.center[c] / len);
          out.push_back(f.rotation.angularDistance(e.rest().frames[j].rotation));
        }
        for (const double r : e.deformed().radii) out.push_back(r / len);
      }
    }
    return out;
  };
  const std::vector<double> fine = section_poses(1.0 / (64 * 480));
  csv = "step_s,error_over_length,ms_per_simulated_second\n";
  md = "| step (s) | error / length | error ratio to the step twice as long | ms per simulated second |\n"
       "|---|---|---|---|\n";
  double previous = 0;
  for (const int per_second : {60, 120, 240, 480, 960, 1920}) {
    const double step = 1.0 / per_second;
    const std::vector<double> poses = section_poses(step);
    double err = 0;
    for (std::size_t m = 0; m < poses.size(); ++m) err = std::max(err, std::abs(poses[m] - fine[m]));
    sim::Scene s = fig4;
    s.step = step;
    const double seconds = median_seconds(args.quick ? 3 : 7,
                                          [&] {
                                            sim::Simulator sim(dino.rig, s, sim::SleepSettings{0, 0, 0, false});
                                            for (int k = 1; k < s.frame_count(); ++k) sim.advance_frame();
                                          }) /
                           s.duration;
    md += fmt("| 1/%d%s | %.2e | %s | %.3g |\n", per_second,
              std::abs(step - sim::Scene::kDefaultStep) < 1e-15 ? " (default)" : "", err,
              previous > 0 ? fmt("%.2f", previous / err).c_str() : "", 1e3 * seconds);
    csv += fmt("%.6g,%.6g,%.6g\n", step, err, 1e3 * seconds);
    previous = err;
  }
  write_text(args.out / "follower.csv", csv);
  write_text(args.out / "follower.md", md);
  std::fputs(md.c_str(), stdout);
  return 0;
}
