// A game's frame through libsweep (sweep/sweep.h): the diplodocus tail and neck in material mode
// with gravity, paced at 60 fps (frames 1/60 s apart on the wall clock, the threads asleep and the
// caches cooling between them), a new body pose every frame (a slow walk with a sway), against the
// scene player's frame (sweep-sim's: Simulator::advance_frame and the fast path) in the same run:
//  - "scene player, 30 fps": the scene at its default 30 fps and step (16 internal steps a frame),
//    the body on a path keyed every 1/60 s — what sweep-sim does per output frame;
//  - "scene player, 60 fps": the same at 60 fps (8 steps a frame);
//  - "live (C++)": Simulator::advance_to(t + 1/60) after set_body_pose, then the fast path, timed
//    apart (step, deform); and at the live step on one thread, with the world-space copy an engine
//    uploads made two ways, timed apart (step, deform, copy): the parts deformed into a mesh-order
//    copy and that transformed (deform_sweeps + transform_positions, libsweep's read before), and
//    sim::LivePositions (libsweep's read now: the same bits);
//  - "libsweep": sweep_set_body + sweep_advance (the step) and the read through the C interface:
//    sweep_positions (the moved parts deformed, the world-space copy an engine uploads) or
//    sweep_joints (the skinned export's joints, for an engine that skins on the GPU), timed apart;
//    with a fine internal step (settings "step": 1/480 s) and with the live default (settings
//    that give none: one step a 60 fps frame), also back to back (warm caches, no pacing), and at the
//    live step without the mid-step predictor (sweep_set_predictor 0);
//    and at the live step with every mode moving (sweep_set_all_modes 1: libsweep's step before
//    it took the modes the step resolves alone, the faster ones quasi-static); and at the live
//    step with the reads of an engine that draws the mesh under the body's transform itself:
//    every vertex in the mesh's space (sweep_positions_local) or the bound ones alone
//    (sweep_bound_positions);
//  - a crowd: 1 and 100 instances, their frames shared among 1 or 2 threads, the live default and
//    all modes;
//  - the accuracy a coarser step costs: the same run at steps from 1/480 to 1/30 s against 1/3840 s
//    (every mode moving), at 1/60 s without the predictor and at 1/60 s with all modes.
// Time: median over the frames after the first 10, per frame, µs; rounds alternate the cases and
// thread counts, median over rounds. libsweep runs an instance on the calling thread: its rows at
// "2 threads" differ from those at 1 only by OMP_NUM_THREADS, which it no longer uses.
#include <unistd.h>

#include <barrier>
#include <thread>

#include "bench_common.h"
#include "sweep/bind/fast_deform.h"
#include "sweep/io/binding_file.h"
#include "sweep/io/rig_json.h"
#include "sweep/sim/live_positions.h"
#include "sweep/sim/simulator.h"
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

void pace() {
  std::this_thread::sleep_for(std::chrono::duration<double>(kFrame));
}
double us(Clock::time_point a, Clock::time_point b) {
  return 1e6 * std::chrono::duration<double>(b - a).count();
}

// The scene player: `scene` at its fps, frames 1/60 s apart.
Cost scene_player(const RealRig& dino, const sim::Scene& scene, int frames) {
  std::vector<bind::Vec3f> positions(dino.mesh.vertex_count());
  for (std::size_t v = 0; v < positions.size(); ++v) positions[v] = dino.mesh.positions[v].cast<float>();
  sim::Simulator sim(dino.rig, scene);
  std::vector<std::unique_ptr<bind::FastDeformer>> fast;
  for (int i = 0; i < sim.sweep_count(); ++i)
    fast.push_back(std::make_unique<bind::FastDeformer>(dino.rig.sweeps[i].rest, dino.binding.sweeps[i], positions));
  std::vector<double> total, step, deform;
  std::vector<bind::DeformJob> jobs;
  for (int k = 0; k < frames; ++k) {
    pace();
    const auto t0 = Clock::now();
    sim.advance_frame();
    const auto t1 = Clock::now();
    jobs.clear();
    for (int i = 0; i < sim.sweep_count(); ++i)
      if (sim.moved_last_frame(i)) jobs.push_back({fast[i].get(), &sim.sweep(i).deformed()});
    bind::deform_sweeps(jobs, positions);
    const auto t2 = Clock::now();
    if (k < kSkip) continue;
    total.push_back(us(t0, t2));
    step.push_back(us(t0, t1));
    deform.push_back(us(t1, t2));
  }
  return {median(total), median(step), median(deform), 0};
}

// How a live frame reads its vertices back in world space: the parts deformed into a mesh-order
// copy and the whole copy transformed (deform_sweeps + transform_positions: libsweep's read until
// it took LivePositions), or LivePositions (each part into its own grouped array, one streamed
// pass over the mesh).
enum class WorldRead { none, mesh_order, live_positions };

// The live simulator in C++: a pose, advance_to, the fast path; with `world`, the world-space copy
// too, on the calling thread (Simulator::set_parallel(false)) as libsweep does.
Cost live_cpp(const RealRig& dino, const sim::Scene& settings, int frames, WorldRead world = WorldRead::none) {
  std::vector<bind::Vec3f> positions(dino.mesh.vertex_count());
  for (std::size_t v = 0; v < positions.size(); ++v) positions[v] = dino.mesh.positions[v].cast<float>();
  sim::Simulator sim(dino.rig, settings);
  if (world != WorldRead::none) sim.set_parallel(false);
  std::vector<std::unique_ptr<bind::FastDeformer>> fast;
  for (int i = 0; i < sim.sweep_count(); ++i)
    fast.push_back(std::make_unique<bind::FastDeformer>(dino.rig.sweeps[i].rest, dino.binding.sweeps[i], positions));
  std::vector<const bind::FastDeformer*> parts;
  for (const auto& f : fast) parts.push_back(f.get());
  sim::LivePositions live(positions, parts);
  std::vector<float> out(3 * positions.size());
  std::vector<double> total, step, deform, copy;
  std::vector<bind::DeformJob> jobs;
  for (int k = 0; k < frames; ++k) {
    pace();
    const double t = (k + 1) * kFrame;
    const auto t0 = Clock::now();
    const sim::BodyState b = walk(t);
    sim.set_body_pose(b.rotation, b.translation);
    sim.advance_to(t);
    const auto t1 = Clock::now();
    if (world == WorldRead::live_positions) {
      for (int i = 0; i < sim.sweep_count(); ++i)
        if (sim.moved_last_frame(i)) live.deform(i, *fast[i], sim.sweep(i).deformed());
    } else {
      jobs.clear();
      for (int i = 0; i < sim.sweep_count(); ++i)
        if (sim.moved_last_frame(i)) jobs.push_back({fast[i].get(), &sim.sweep(i).deformed()});
      if (world == WorldRead::none) {
        bind::deform_sweeps(jobs, positions);
      } else {
        for (const bind::DeformJob& j : jobs) j.fast->deform(*j.shape, positions, false);
      }
    }
    const auto t2 = Clock::now();
    const sim::BodyState now = sim.body();
    const Eigen::Matrix3f r = now.rotation.toRotationMatrix().cast<float>();
    const bind::Vec3f tr = now.translation.cast<float>();
    if (world == WorldRead::live_positions) live.world(r, tr, out.data());
    if (world == WorldRead::mesh_order) bind::transform_positions(positions, r, tr, out.data());
    const auto t3 = Clock::now();
    if (k < kSkip) continue;
    total.push_back(us(t0, t3));
    step.push_back(us(t0, t1));
    deform.push_back(us(t1, t2));
    copy.push_back(us(t2, t3));
  }
  return {median(total), median(step), median(deform), median(copy)};
}

void check(int code) {
  if (code != SWEEP_OK) throw std::runtime_error("libsweep: " + std::string(sweep_last_error()));
}

// The body's pose at t as sweep_set_body takes it.
void body_matrix(double t, double m[16]) {
  const sim::BodyState b = walk(t);
  const Mat3 r = b.rotation.toRotationMatrix();
  for (int c = 0; c < 3; ++c) {
    for (int row = 0; row < 3; ++row) m[4 * c + row] = r(row, c);
    m[3 + 4 * c] = 0;
    m[12 + c] = b.translation[c];
  }
  m[15] = 1;
}

// What a frame reads back: the deformed positions (an engine that skins on the CPU or uploads
// vertices: world space, or the mesh's own — every vertex or the bound ones alone) or the joints
// (one that skins on the GPU).
enum class Read { positions, joints, local, bound };

// The read's floats: vertices × 3, bound vertices × 3 or joints × 16.
std::size_t read_size(sweep_instance* in, Read read, std::size_t rest_floats) {
  if (read == Read::joints) return 16 * static_cast<std::size_t>(sweep_joint_count(in));
  if (read == Read::bound) return 3 * static_cast<std::size_t>(sweep_bound_count(in));
  return rest_floats;
}

int read_out(sweep_instance* in, Read read, float* out) {
  switch (read) {
    case Read::positions:
      return sweep_positions(in, out);
    case Read::joints:
      return sweep_joints(in, out);
    case Read::local:
      return sweep_positions_local(in, out);
    case Read::bound:
      return sweep_bound_positions(in, out);
  }
  return SWEEP_ERROR_USAGE;
}

sweep_instance* open_dino(const fs::path& dir, const char* settings, const std::vector<float>& rest) {
  sweep_instance* in = sweep_open((dir / "dino.rig.json").c_str(), (dir / "dino.bind").c_str(),
                                  (dir / settings).c_str(), rest.data(), static_cast<int>(rest.size() / 3));
  if (in == nullptr) check(SWEEP_ERROR_INTERNAL);
  return in;
}

// Through the C interface, as an engine calls it: step (sweep_set_body + sweep_advance) and read
// (sweep_positions: the parts that moved deformed, the world-space copy; or sweep_joints) timed
// apart. `ring`: the skeleton's ring joints (0: the default).
Cost live_c(const fs::path& dir, const char* settings, const std::vector<float>& rest, int frames, bool paced,
            Read read, int ring = 0, bool predictor = true, bool all_modes = false) {
  sweep_instance* in = open_dino(dir, settings, rest);
  if (ring > 0) check(sweep_set_skin(in, 24, ring));
  check(sweep_set_predictor(in, predictor ? 1 : 0));
  check(sweep_set_all_modes(in, all_modes ? 1 : 0));
  std::vector<float> out(read_size(in, read, rest.size()));
  std::vector<double> total, step, copy;
  for (int k = 0; k < frames; ++k) {
    if (paced) pace();
    const auto t0 = Clock::now();
    double m[16];
    body_matrix((k + 1) * kFrame, m);
    check(sweep_set_body(in, m));
    check(sweep_advance(in, kFrame));
    const auto t1 = Clock::now();
    check(read_out(in, read, out.data()));
    const auto t2 = Clock::now();
    if (k < kSkip) continue;
    total.push_back(us(t0, t2));
    step.push_back(us(t0, t1));
    copy.push_back(us(t1, t2));
  }
  sweep_close(in);
  return {median(total), median(step), 0, median(copy)};
}

// A crowd: `count` instances, each its own creature on the same walk (a phase apart), every frame
// stepped and read on `threads` threads (the game's workers: each takes every threads-th creature,
// libsweep's own OpenMP kept to one thread inside them), frames 1/60 s apart. The frame: from the
// workers' start to the last one's end. Opened from the same files, the creatures share what never
// changes (each part's chain model, the rest positions), as a game's crowd of one creature would.
double crowd(const fs::path& dir, const std::vector<float>& rest, int count, int threads, int frames, Read read,
             bool all_modes = false) {
  std::vector<sweep_instance*> herd;
  for (int c = 0; c < count; ++c) {
    herd.push_back(open_dino(dir, "settings.scene.json", rest));
    check(sweep_set_all_modes(herd.back(), all_modes ? 1 : 0));
  }
  const std::size_t size =
      read == Read::positions ? rest.size() : 16 * static_cast<std::size_t>(sweep_joint_count(herd[0]));
  std::vector<std::vector<float>> out(static_cast<std::size_t>(count), std::vector<float>(size));
  int frame = 0;
  const auto work = [&](int worker) {
    for (int c = worker; c < count; c += threads) {
      double m[16];
      body_matrix((frame + 1) * kFrame + 0.37 * c, m);
      check(sweep_set_body(herd[c], m));
      check(sweep_advance(herd[c], kFrame));
      check(read == Read::positions ? sweep_positions(herd[c], out[c].data()) : sweep_joints(herd[c], out[c].data()));
    }
  };
  std::vector<double> total;
  std::barrier start(threads), done(threads);
  bool stop = false;
  std::vector<std::thread> pool;
  for (int w = 1; w < threads; ++w) {
    pool.emplace_back([&, w] {
      omp_set_num_threads(1);
      for (;;) {
        start.arrive_and_wait();
        if (stop) return;
        work(w);
        done.arrive_and_wait();
      }
    });
  }
  const int inner = omp_get_max_threads();
  omp_set_num_threads(1);
  for (frame = 0; frame < frames; ++frame) {
    pace();
    const auto t0 = Clock::now();
    start.arrive_and_wait();
    work(0);
    done.arrive_and_wait();
    if (frame >= kSkip) total.push_back(us(t0, Clock::now()));
  }
  stop = true;
  start.arrive_and_wait();
  for (std::thread& t : pool) t.join();
  omp_set_num_threads(inner);
  for (sweep_instance* in : herd) sweep_close(in);
  return median(total);
}

// The cost of a coarser internal step: the same live run (the walk, gravity, and a 20 kN hit on the
// tail's tip at 0.5 s, held 0.1 s) with settings whose "step" is `step`, against the same run at
// `reference`: the largest distance of any bound vertex over `frames` frames at 60 fps, over the
// length of the part it is bound to. Also the frame's cost, back to back.
struct StepError {
  double relative = 0, frame_us = 0;
};
std::vector<std::vector<float>> step_run(const fs::path& dir, double step, const std::vector<float>& rest, int frames,
                                         double& frame_us, bool predictor = true, bool all_modes = false) {
  const fs::path settings = dir / fmt("step-%.9g.scene.json", step);
  write_text(
      settings,
      fmt(R"({"format": "sweep-scene", "version": 1, "duration": 10, "fps": 60, "step": %.17g, "gravity": [0, -9.81, 0], "forces": []})",
          step));
  sweep_instance* in = sweep_open((dir / "dino.rig.json").c_str(), (dir / "dino.bind").c_str(), settings.c_str(),
                                  rest.data(), static_cast<int>(rest.size() / 3));
  if (in == nullptr) check(SWEEP_ERROR_INTERNAL);
  check(sweep_set_predictor(in, predictor ? 1 : 0));
  check(sweep_set_all_modes(in, all_modes ? 1 : 0));
  std::vector<std::vector<float>> out;
  std::vector<double> times;
  for (int k = 0; k < frames; ++k) {
    const double t = (k + 1) * kFrame;
    const sim::BodyState b = walk(t);
    double m[16] = {0};
    const Mat3 r = b.rotation.toRotationMatrix();
    for (int c = 0; c < 3; ++c) {
      for (int row = 0; row < 3; ++row) m[4 * c + row] = r(row, c);
      m[12 + c] = b.translation[c];
    }
    m[15] = 1;
    if (k == 30) {
      const double point[3] = {-0.5, -0.345, -0.012}, force[3] = {0, 0, 20000};
      check(sweep_add_force(in, "tail", point, force, 0.1));
    }
    const auto t0 = Clock::now();
    check(sweep_set_body(in, m));
    check(sweep_advance(in, kFrame));
    times.push_back(us(t0, Clock::now()));
    out.emplace_back(rest.size());
    check(sweep_positions(in, out.back().data()));
  }
  sweep_close(in);
  frame_us = median(times);
  return out;
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
  io::write_binding(dir / "dino.bind", dino.binding);
  write_text(
      dir / "settings.scene.json",
      R"({"format": "sweep-scene", "version": 1, "duration": 10, "fps": 60, "gravity": [0, -9.81, 0], "forces": []})");
  // The same with a fine internal step, 1/480 s: 8 steps a 60 fps frame instead of 1.
  write_text(
      dir / "fine.scene.json",
      R"({"format": "sweep-scene", "version": 1, "duration": 10, "fps": 60, "step": 0.0020833333333333333, "gravity": [0, -9.81, 0], "forces": []})");
  std::vector<float> rest;
  for (const Vec3& p : dino.mesh.positions) rest.insert(rest.end(), {float(p.x()), float(p.y()), float(p.z())});

  sim::Scene settings;
  settings.gravity = Vec3(0, -9.81, 0);
  sim::Scene live_settings = settings;  // libsweep's default step
  live_settings.step = kFrame;
  sim::Scene fine_settings = settings;  // the live simulator at 1/480 s
  fine_settings.step = 1.0 / 480;
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
  const char* names[] = {
      "scene player, 30 fps (sweep-sim's frame)",
      "scene player, 60 fps",
      "live (C++): set_body_pose + advance_to, step 1/480 s",
      "live (C++), live step 1/60 s, one thread: mesh-order deform + transform_positions (libsweep's read before)",
      "live (C++), live step 1/60 s, one thread: LivePositions (libsweep's read now)",
      "libsweep, step 1/480 s (8 a frame): positions",
      "libsweep, live step 1/60 s: positions",
      "libsweep, live step, frames back to back: positions",
      "libsweep, live step: joints out (24 + 23×24 ring a part)",
      "libsweep, live step: joints out (24 a part, no ring)",
      "libsweep, live step without the mid-step predictor (sweep_set_predictor 0): positions",
      "libsweep, live step without the mid-step predictor: joints out (24 + 23×24 ring a part)",
      "libsweep, live step, all modes (sweep_set_all_modes 1, the step before): positions",
      "libsweep, live step, all modes (sweep_set_all_modes 1, the step before): joints out (24 + 23×24 ring a part)",
      "libsweep, live step, all modes, frames back to back: positions",
      "libsweep, live step: positions in the mesh's space (sweep_positions_local)",
      "libsweep, live step: the bound vertices alone, mesh space (sweep_bound_positions)"};
  constexpr int kCases = 17;
  std::vector<std::vector<std::vector<Cost>>> runs(kCases, std::vector<std::vector<Cost>>(max_threads));
  // A crowd of 1 and 100, on 1 and 2 threads, positions and joints out, the default and all modes.
  const int herd_sizes[] = {1, 100};
  std::vector<double> herd_runs[2][2][2][2];  // [size][threads − 1][read][all modes]
  for (int r = 0; r < rounds; ++r) {
    for (int th = 1; th <= max_threads; ++th) {
      omp_set_num_threads(th);
      runs[0][th - 1].push_back(scene_player(dino, player30, frames / 2 + kSkip));
      runs[1][th - 1].push_back(scene_player(dino, player60, frames));
      runs[2][th - 1].push_back(live_cpp(dino, fine_settings, frames));
      runs[3][th - 1].push_back(live_cpp(dino, live_settings, frames, WorldRead::mesh_order));
      runs[4][th - 1].push_back(live_cpp(dino, live_settings, frames, WorldRead::live_positions));
      runs[5][th - 1].push_back(live_c(dir, "fine.scene.json", rest, frames, true, Read::positions));
      runs[6][th - 1].push_back(live_c(dir, "settings.scene.json", rest, frames, true, Read::positions));
      runs[7][th - 1].push_back(live_c(dir, "settings.scene.json", rest, frames, false, Read::positions));
      runs[8][th - 1].push_back(live_c(dir, "settings.scene.json", rest, frames, true, Read::joints));
      runs[9][th - 1].push_back(live_c(dir, "settings.scene.json", rest, frames, true, Read::joints, 1));
      runs[10][th - 1].push_back(live_c(dir, "settings.scene.json", rest, frames, true, Read::positions, 0, false));
      runs[11][th - 1].push_back(live_c(dir, "settings.scene.json", rest, frames, true, Read::joints, 0, false));
      runs[12][th - 1].push_back(
          live_c(dir, "settings.scene.json", rest, frames, true, Read::positions, 0, true, true));
      runs[13][th - 1].push_back(live_c(dir, "settings.scene.json", rest, frames, true, Read::joints, 0, true, true));
      runs[14][th - 1].push_back(
          live_c(dir, "settings.scene.json", rest, frames, false, Read::positions, 0, true, true));
      runs[15][th - 1].push_back(live_c(dir, "settings.scene.json", rest, frames, true, Read::local));
      runs[16][th - 1].push_back(live_c(dir, "settings.scene.json", rest, frames, true, Read::bound));
      for (int h = 0; h < 2; ++h) {
        for (int read = 0; read < 2; ++read) {
          for (int all = 0; all < 2; ++all) {
            herd_runs[h][th - 1][read][all].push_back(crowd(dir, rest, herd_sizes[h], th,
                                                            h == 0 ? frames : frames / 2 + kSkip,
                                                            read == 0 ? Read::positions : Read::joints, all == 1));
          }
        }
      }
    }
  }
  std::string csv = "case,threads,frame_us,step_us,deform_us,read_us\n";
  std::string md =
      fmt("Diplodocus tail + neck (%zu bound vertices of %zu), material mode, gravity, a new body pose every "
          "frame, frames 1/60 s apart (a %s build):\n\n",
          bound, dino.mesh.vertex_count(), SWEEP_BUILD_TYPE);
  md +=
      "| case | threads | frame µs (median) | step µs | deform µs | read µs (world copy; libsweep: sweep_positions or "
      "sweep_joints) |\n"
      "|---|---|---|---|---|---|\n";
  for (int c = 0; c < kCases; ++c) {
    for (int th = 1; th <= max_threads; ++th) {
      const Cost m = median_of(runs[c][th - 1]);
      csv += fmt("\"%s\",%d,%.4g,%.4g,%.4g,%.4g\n", names[c], th, m.frame_us, m.step_us, m.deform_us, m.copy_us);
      const std::string deform = c >= 5 ? "—" : fmt("%.1f", m.deform_us);
      const std::string read = c >= 3 ? fmt("%.1f", m.copy_us) : "—";
      md += fmt("| %s | %d | %.1f | %.1f | %s | %s |\n", names[c], th, m.frame_us, m.step_us, deform.c_str(),
                read.c_str());
    }
  }
  md +=
      "\nA crowd: N instances through libsweep, the live step, each frame every creature's pose, advance and read, "
      "the creatures shared among the threads (libsweep's own threads kept to one inside each), frames 1/60 s "
      "apart:\n\n"
      "| creatures | threads | frame µs, positions (median) | frame µs, joints out (median) | all modes "
      "(sweep_set_all_modes 1): positions | all modes: joints out |\n|---|---|---|---|---|---|\n";
  csv += "\ncreatures,threads,frame_us_positions,frame_us_joints,all_modes_positions,all_modes_joints\n";
  for (int h = 0; h < 2; ++h) {
    for (int th = 1; th <= max_threads; ++th) {
      const double pos = median(herd_runs[h][th - 1][0][0]), joints = median(herd_runs[h][th - 1][1][0]);
      const double all_pos = median(herd_runs[h][th - 1][0][1]), all_joints = median(herd_runs[h][th - 1][1][1]);
      md += fmt("| %d | %d | %.1f | %.1f | %.1f | %.1f |\n", herd_sizes[h], th, pos, joints, all_pos, all_joints);
      csv += fmt("%d,%d,%.4g,%.4g,%.4g,%.4g\n", herd_sizes[h], th, pos, joints, all_pos, all_joints);
    }
  }
  // What a coarser step costs in accuracy, against a step 8× finer than 1/480 s.
  const int accuracy_frames = args.quick ? 120 : 300;
  const int reference_per_second = 3840;
  double reference_us = 0;
  const auto reference = step_run(dir, 1.0 / reference_per_second, rest, accuracy_frames, reference_us, true, true);
  md += fmt(
      "\nA coarser internal step against a fine one (1/%d s), the same live run (the walk, gravity, a 20 kN push on "
      "the tail's tip from 0.5 to 0.6 s), %d frames at 60 fps: the largest distance of a bound vertex from where the "
      "fine step puts it, over its part's length, and the frame's cost back to back (1 thread):\n\n",
      reference_per_second, accuracy_frames);
  md += "| step | steps a 60 fps frame | largest error / length | frame µs (median) |\n|---|---|---|---|\n";
  csv += "\nstep_s,steps_per_frame,max_error_relative,frame_us\n";
  omp_set_num_threads(1);
  for (const double step : {1.0 / 480, 1.0 / 240, 1.0 / 120, 1.0 / 60, 1.0 / 30, 0.0, -1.0}) {
    double frame_us = 0;
    // step 0: the live step without the mid-step predictor (sweep_set_predictor(in, 0)); −1: the
    // live step with every mode moving (sweep_set_all_modes(in, 1)).
    const auto run = step_run(dir, step > 0 ? step : kFrame, rest, accuracy_frames, frame_us, step != 0, step < 0);
    double worst = 0;
    for (std::size_t i = 0; i < dino.binding.sweeps.size(); ++i) {
      const double length = dino.rig.sweeps[i].rest.length();
      for (int k = 0; k < accuracy_frames; ++k) {
        for (const std::uint32_t v : dino.binding.sweeps[i].vertices) {
          const Eigen::Map<const Eigen::Vector3f> a(run[k].data() + 3 * v), b(reference[k].data() + 3 * v);
          worst = std::max(worst, static_cast<double>((a - b).norm()) / length);
        }
      }
    }
    const std::string name = step > 0    ? fmt("1/%d s", static_cast<int>(std::lround(1 / step)))
                             : step == 0 ? std::string("1/60 s without the mid-step predictor (sweep_set_predictor 0)")
                                         : std::string("1/60 s, all modes (sweep_set_all_modes 1, the step before)");
    const double per_frame = step > 0 ? kFrame / step : 1.0;
    md += fmt("| %s | %.3g | %.2e | %.1f |\n", name.c_str(), per_frame, worst, frame_us);
    csv += fmt("%.9g,%.3g,%.4g,%.4g\n", step > 0 ? step : kFrame, per_frame, worst, frame_us);
  }
  write_text(args.out / "live.csv", csv);
  write_text(args.out / "live.md", md);
  std::printf("%s", md.c_str());
  fs::remove_all(dir);
  return 0;
}
