// A game's frame through libsweep (sweep/sweep.h): the diplodocus tail and neck in material mode
// with gravity, paced at 60 fps (frames 1/60 s apart on the wall clock, the threads asleep and the
// caches cooling between them), a new body pose every frame (a slow walk with a sway), against the
// scene player's frame (sweep-sim's: Simulator::advance_frame and the fast path) in the same run:
//  - "scene player, 30 fps": the scene at its default 30 fps (16 internal steps a frame), the body
//    on a path keyed every 1/60 s — what sweep-sim does per output frame;
//  - "scene player, 60 fps": the same at 60 fps (8 steps a frame);
//  - "live (C++)": Simulator::advance_to(t + 1/60) after set_body_pose, then the fast path, timed
//    apart (step, deform);
//  - "libsweep": sweep_set_body + sweep_advance (step and deform) through the C interface, and
//    sweep_positions (the world-space copy an engine uploads) timed apart; also back to back (warm
//    caches, no pacing) and with a coarser internal step (settings "step": 1/120 s).
// Time: median over the frames after the first 10, per frame, µs; rounds alternate the cases and
// thread counts, median over rounds.
#include <unistd.h>

#include <thread>

#include "bench_common.h"
#include "io/binding_file.h"
#include "io/rig_json.h"
#include "sim/fast_deform.h"
#include "sim/simulator.h"
#include "sweep/sweep.h"

namespace sweep::bench {
namespace {

constexpr double kFrame = 1.0 / 60;
constexpr int kSkip = 10;

// The body at time t: walking along x, swaying about y.
sim::BodyState walk(double t) {
  sim::BodyState b;
  b.translation = Vec3(0.05 * t, 0, 0);
  b.rotation = Quat(Eigen::AngleAxisd(0.1 * std::sin(2 * t), Vec3::UnitY()));
  return b;
}

struct Cost {
  double frame_us = 0, step_us = 0, deform_us = 0, copy_us = 0;
};

Cost median_of(const std::vector<Cost>& runs) {
  const auto pick = [&](double Cost::*f) {
    std::vector<double> v;
    for (const Cost& c : runs) v.push_back(c.*f);
    return median(v);
  };
  return {pick(&Cost::frame_us), pick(&Cost::step_us), pick(&Cost::deform_us), pick(&Cost::copy_us)};
}

void pace() { std::this_thread::sleep_for(std::chrono::duration<double>(kFrame)); }
double us(Clock::time_point a, Clock::time_point b) { return 1e6 * std::chrono::duration<double>(b - a).count(); }

// The scene player: `scene` at its fps, frames 1/60 s apart.
Cost scene_player(const RealRig& dino, const sim::Scene& scene, int frames) {
  std::vector<sim::Vec3f> positions(dino.mesh.vertex_count());
  for (std::size_t v = 0; v < positions.size(); ++v) positions[v] = dino.mesh.positions[v].cast<float>();
  sim::Simulator sim(dino.rig, scene);
  std::vector<std::unique_ptr<sim::FastDeformer>> fast;
  for (int i = 0; i < sim.sweep_count(); ++i)
    fast.push_back(std::make_unique<sim::FastDeformer>(dino.rig.sweeps[i].rest, dino.binding.sweeps[i], positions));
  std::vector<double> total, step, deform;
  std::vector<sim::DeformJob> jobs;
  for (int k = 0; k < frames; ++k) {
    pace();
    const auto t0 = Clock::now();
    sim.advance_frame();
    const auto t1 = Clock::now();
    jobs.clear();
    for (int i = 0; i < sim.sweep_count(); ++i)
      if (sim.moved_last_frame(i)) jobs.push_back({fast[i].get(), &sim.sweep(i).deformed()});
    sim::deform_sweeps(jobs, positions);
    const auto t2 = Clock::now();
    if (k < kSkip) continue;
    total.push_back(us(t0, t2));
    step.push_back(us(t0, t1));
    deform.push_back(us(t1, t2));
  }
  return {median(total), median(step), median(deform), 0};
}

// The live simulator in C++: a pose, advance_to, the fast path.
Cost live_cpp(const RealRig& dino, const sim::Scene& settings, int frames) {
  std::vector<sim::Vec3f> positions(dino.mesh.vertex_count());
  for (std::size_t v = 0; v < positions.size(); ++v) positions[v] = dino.mesh.positions[v].cast<float>();
  sim::Simulator sim(dino.rig, settings);
  std::vector<std::unique_ptr<sim::FastDeformer>> fast;
  for (int i = 0; i < sim.sweep_count(); ++i)
    fast.push_back(std::make_unique<sim::FastDeformer>(dino.rig.sweeps[i].rest, dino.binding.sweeps[i], positions));
  std::vector<double> total, step, deform;
  std::vector<sim::DeformJob> jobs;
  for (int k = 0; k < frames; ++k) {
    pace();
    const double t = (k + 1) * kFrame;
    const auto t0 = Clock::now();
    const sim::BodyState b = walk(t);
    sim.set_body_pose(b.rotation, b.translation);
    sim.advance_to(t);
    const auto t1 = Clock::now();
    jobs.clear();
    for (int i = 0; i < sim.sweep_count(); ++i)
      if (sim.moved_last_frame(i)) jobs.push_back({fast[i].get(), &sim.sweep(i).deformed()});
    sim::deform_sweeps(jobs, positions);
    const auto t2 = Clock::now();
    if (k < kSkip) continue;
    total.push_back(us(t0, t2));
    step.push_back(us(t0, t1));
    deform.push_back(us(t1, t2));
  }
  return {median(total), median(step), median(deform), 0};
}

void check(int code) {
  if (code != SWEEP_OK) throw std::runtime_error("libsweep: " + std::string(sweep_last_error()));
}

// Through the C interface, as an engine calls it.
Cost live_c(const fs::path& dir, const char* settings, const std::vector<float>& rest, int frames, bool paced = true) {
  sweep_instance* in = sweep_open((dir / "dino.rig.json").c_str(), (dir / "dino.bind").c_str(),
                                  (dir / settings).c_str(), rest.data(), static_cast<int>(rest.size() / 3));
  if (in == nullptr) check(SWEEP_ERROR_INTERNAL);
  std::vector<float> out(rest.size());
  std::vector<double> total, copy;
  for (int k = 0; k < frames; ++k) {
    if (paced) pace();
    const double t = (k + 1) * kFrame;
    const auto t0 = Clock::now();
    const sim::BodyState b = walk(t);
    double m[16] = {0};
    const Mat3 r = b.rotation.toRotationMatrix();
    for (int c = 0; c < 3; ++c) {
      for (int row = 0; row < 3; ++row) m[4 * c + row] = r(row, c);
      m[12 + c] = b.translation[c];
    }
    m[15] = 1;
    check(sweep_set_body(in, m));
    check(sweep_advance(in, kFrame));
    const auto t1 = Clock::now();
    check(sweep_positions(in, out.data()));
    const auto t2 = Clock::now();
    if (k < kSkip) continue;
    total.push_back(us(t0, t1));
    copy.push_back(us(t1, t2));
  }
  sweep_close(in);
  return {median(total), 0, 0, median(copy)};
}

}  // namespace
}  // namespace sweep::bench

int main(int argc, char** argv) {
  using namespace sweep;
  using namespace sweep::bench;
  const Args args = parse_args(argc, argv);
  const int frames = args.quick ? 60 : 180;
  const int rounds = args.quick ? 3 : 5;
  const int max_threads = std::min(2, omp_get_max_threads());

  RealRig dino = in_material(diplodocus_rig());
  // The files an engine would ship: rig, binding, settings (gravity, pre-loaded: the modelled
  // pose is the pose under it).
  const fs::path dir = fs::temp_directory_path() / fmt("sweep-bench-live-%d", static_cast<int>(::getpid()));
  fs::create_directories(dir);
  dino.rig.mesh = diplodocus_path().string();
  io::write_rig(dir / "dino.rig.json", dino.rig);
  bind::write_binding(dir / "dino.bind", dino.binding);
  write_text(dir / "settings.scene.json", R"({"format": "sweep-scene", "version": 1, "duration": 10, "fps": 60, "gravity": [0, -9.81, 0], "forces": []})");
  // The same with an internal step of 1/120 s: 2 steps a 60 fps frame instead of 8.
  write_text(dir / "coarse.scene.json",
             R"({"format": "sweep-scene", "version": 1, "duration": 10, "fps": 60, "step": 0.008333333333333333, "gravity": [0, -9.81, 0], "forces": []})");
  std::vector<float> rest;
  for (const Vec3& p : dino.mesh.positions) rest.insert(rest.end(), {float(p.x()), float(p.y()), float(p.z())});

  sim::Scene settings;
  settings.gravity = Vec3(0, -9.81, 0);
  sim::Scene player30 = settings, player60 = settings;
  std::vector<sim::BodyKey> keys;
  for (int k = 0; k <= frames + 1; ++k) {
    const sim::BodyState b = walk(k * kFrame);
    keys.push_back({k * kFrame, b.translation, b.rotation});
  }
  player30.body = player60.body = sim::BodyPath(keys, sim::BodyInterpolation::linear);
  player30.duration = player60.duration = frames * kFrame + 1;
  player60.fps = 60;

  std::size_t bound = 0;
  for (const auto& s : dino.binding.sweeps) bound += s.size();
  const char* names[] = {"scene player, 30 fps (sweep-sim's frame)", "scene player, 60 fps", "live (C++): set_body_pose + advance_to",
                         "libsweep: sweep_set_body + sweep_advance", "libsweep, frames back to back",
                         "libsweep, step 1/120 s (2 steps a frame)"};
  constexpr int kCases = 6;
  std::vector<std::vector<std::vector<Cost>>> runs(kCases, std::vector<std::vector<Cost>>(max_threads));
  for (int r = 0; r < rounds; ++r) {
    for (int th = 1; th <= max_threads; ++th) {
      omp_set_num_threads(th);
      runs[0][th - 1].push_back(scene_player(dino, player30, frames / 2 + kSkip));
      runs[1][th - 1].push_back(scene_player(dino, player60, frames));
      runs[2][th - 1].push_back(live_cpp(dino, settings, frames));
      runs[3][th - 1].push_back(live_c(dir, "settings.scene.json", rest, frames));
      runs[4][th - 1].push_back(live_c(dir, "settings.scene.json", rest, frames, false));
      runs[5][th - 1].push_back(live_c(dir, "coarse.scene.json", rest, frames));
    }
  }
  std::string csv = "case,threads,frame_us,step_us,deform_us,positions_us\n";
  std::string md = fmt("Diplodocus tail + neck (%zu bound vertices of %zu), material mode, gravity, a new body pose every "
                       "frame, frames 1/60 s apart:\n\n",
                       bound, dino.mesh.vertex_count());
  md += "| case | threads | frame µs (median) | step µs | deform µs | sweep_positions µs |\n|---|---|---|---|---|---|\n";
  for (int c = 0; c < kCases; ++c) {
    for (int th = 1; th <= max_threads; ++th) {
      const Cost m = median_of(runs[c][th - 1]);
      csv += fmt("\"%s\",%d,%.4g,%.4g,%.4g,%.4g\n", names[c], th, m.frame_us, m.step_us, m.deform_us, m.copy_us);
      md += c >= 3 ? fmt("| %s | %d | %.1f | — | — | %.1f |\n", names[c], th, m.frame_us, m.copy_us)
                   : fmt("| %s | %d | %.1f | %.1f | %.1f | — |\n", names[c], th, m.frame_us, m.step_us, m.deform_us);
    }
  }
  write_text(args.out / "live.csv", csv);
  write_text(args.out / "live.md", md);
  std::printf("%s", md.c_str());
  fs::remove_all(dir);
  return 0;
}
