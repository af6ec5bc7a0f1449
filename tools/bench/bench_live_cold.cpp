// Why a paced live frame costs ~3x one run back to back: libsweep's diplodocus frame (as
// sweep-bench-live's "libsweep, live step 1/60 s" row: material mode, gravity, the walk, one thread)
// after each way of spending the 1/60 s between frames:
//  - none: frames back to back (warm caches and branch predictors);
//  - sleep: asleep (a game's frame: the core runs whatever else is waiting);
//  - spin: spinning on the clock for 1/60 s (the thread never leaves the core... unless preempted);
//  - evict: 8 MB of this thread's own data touched (its caches' data evicted, nothing else run);
//  - sleep, then another instance's frame: the code warm again, this instance's data still cold.
// Prints a Markdown table; step and read timed apart, medians over the frames after the first 10,
// µs. Not part of run-benchmarks.sh (its rows only explain sweep-bench-live's).
//
//   build/dev/tools/bench/sweep-bench-live-cold [--quick]
//
// With --count positions|joints it runs 10 frames and then 200 back to back, nothing else and no
// timing: the run to count instructions in, load-independent, e.g.
//   valgrind --tool=callgrind --toggle-collect='*counted_frames*' build/dev/tools/bench/sweep-bench-live-cold
//     --count positions
// (then callgrind_annotate --inclusive=yes: sweep_advance is the step, sweep_positions or
// sweep_joints the read, each over the 200 frames).
#include <unistd.h>

#include <thread>

#include "bench_common.h"
#include "sweep/io/binding_file.h"
#include "sweep/io/rig_json.h"
#include "sweep/sweep.h"

namespace sweep::bench {
namespace {

constexpr double kFrame = 1.0 / 60;
constexpr int kSkip = 10;

double us(Clock::time_point a, Clock::time_point b) {
  return 1e6 * std::chrono::duration<double>(b - a).count();
}

// The walk of sweep-bench-live as sweep_set_body takes it.
void body_matrix(double t, double m[16]) {
  const Mat3 r = Quat(Eigen::AngleAxisd(0.1 * std::sin(2 * t), Vec3::UnitY())).toRotationMatrix();
  for (int c = 0; c < 3; ++c) {
    for (int row = 0; row < 3; ++row) m[4 * c + row] = r(row, c);
    m[3 + 4 * c] = 0;
  }
  m[12] = 0.05 * t, m[13] = m[14] = 0;
  m[15] = 1;
}

struct Files {
  fs::path dir;
  std::vector<float> rest;
  sweep_instance* open() const {
    sweep_instance* in =
        sweep_open((dir / "dino.rig.json").c_str(), (dir / "dino.bind").c_str(), (dir / "settings.scene.json").c_str(),
                   rest.data(), static_cast<int>(rest.size() / 3));
    if (in == nullptr) throw std::runtime_error(sweep_last_error());
    return in;
  }
};

enum class Gap { none, sleep, spin, evict, warm_code };
enum class Read { positions, joints };

// One frame of `in`: pose, advance, read; the step's and the read's µs.
void frame(sweep_instance* in, double t, Read read, std::vector<float>& out, double& step, double& got) {
  const auto t0 = Clock::now();
  double m[16];
  body_matrix(t, m);
  sweep_set_body(in, m);
  sweep_advance(in, kFrame);
  const auto t1 = Clock::now();
  if (read == Read::positions) {
    sweep_positions(in, out.data());
  } else {
    sweep_joints(in, out.data());
  }
  step = us(t0, t1);
  got = us(t1, Clock::now());
}

// The 200 frames that --count counts (the first 10 warm up outside them).
[[gnu::noinline]] void counted_frames(sweep_instance* in, Read read, std::vector<float>& out) {
  double step = 0, got = 0;
  for (int k = 10; k < 210; ++k) frame(in, (k + 1) * kFrame, read, out, step, got);
}

void count(const Files& files, Read read) {
  sweep_instance* in = files.open();
  const std::size_t size = read == Read::positions ? files.rest.size() : 16 * std::size_t(sweep_joint_count(in));
  std::vector<float> out(size);
  double step = 0, got = 0;
  for (int k = 0; k < 10; ++k) frame(in, (k + 1) * kFrame, read, out, step, got);
  counted_frames(in, read, out);
  sweep_close(in);
}

std::string row(const Files& files, Gap gap, Read read, int frames) {
  sweep_instance* in = files.open();
  sweep_instance* other = files.open();
  const std::size_t size = read == Read::positions ? files.rest.size() : 16 * std::size_t(sweep_joint_count(in));
  std::vector<float> out(size), scratch(size);
  std::vector<char> junk(std::size_t{8} << 20, 1);
  std::vector<double> steps, reads;
  for (int k = 0; k < frames; ++k) {
    const auto until = Clock::now() + std::chrono::duration<double>(kFrame);
    double step = 0, got = 0;
    if (gap == Gap::sleep || gap == Gap::warm_code) std::this_thread::sleep_until(until);
    if (gap == Gap::spin) {
      while (Clock::now() < until) {
      }
    }
    if (gap == Gap::evict) {
      for (std::size_t i = 0; i < junk.size(); i += 64) ++junk[i];
    }
    if (gap == Gap::warm_code) frame(other, (k + 1) * kFrame + 0.37, read, scratch, step, got);
    frame(in, (k + 1) * kFrame, read, out, step, got);
    if (k < kSkip) continue;
    steps.push_back(step);
    reads.push_back(got);
  }
  sweep_close(in);
  sweep_close(other);
  const char* names[] = {"back to back", "asleep 1/60 s", "spinning 1/60 s", "8 MB of own data touched",
                         "asleep, then another instance's frame"};
  return fmt("| %s | %s | %.1f | %.1f | %.1f |\n", names[static_cast<int>(gap)],
             read == Read::positions ? "positions" : "joints", median(steps) + median(reads), median(steps),
             median(reads));
}

}  // namespace
}  // namespace sweep::bench

int main(int argc, char** argv) {
  using namespace sweep;
  using namespace sweep::bench;
  const bool quick = argc > 1 && std::string(argv[1]) == "--quick";
  const std::string counting = argc > 2 && std::string(argv[1]) == "--count" ? argv[2] : "";
  const int frames = quick ? 60 : 200;
  Files files;
  files.dir = fs::temp_directory_path() / fmt("sweep-bench-live-cold-%d", static_cast<int>(::getpid()));
  fs::create_directories(files.dir);
  RealRig dino = in_material(diplodocus_rig());
  dino.rig.mesh = diplodocus_path().string();
  io::write_rig(files.dir / "dino.rig.json", dino.rig);
  io::write_binding(files.dir / "dino.bind", dino.binding);
  write_text(
      files.dir / "settings.scene.json",
      R"({"format": "sweep-scene", "version": 1, "duration": 10, "fps": 60, "gravity": [0, -9.81, 0], "forces": []})");
  for (const Vec3& p : dino.mesh.positions)
    files.rest.insert(files.rest.end(), {float(p.x()), float(p.y()), float(p.z())});

  if (!counting.empty()) {
    count(files, counting == "joints" ? Read::joints : Read::positions);
    fs::remove_all(files.dir);
    return 0;
  }
  std::string md = "| between frames | read | frame µs | step µs | read µs |\n|---|---|---|---|---|\n";
  for (const Read read : {Read::positions, Read::joints}) {
    for (const Gap gap : {Gap::none, Gap::sleep, Gap::spin, Gap::evict, Gap::warm_code})
      md += row(files, gap, read, frames);
  }
  std::printf("%s", md.c_str());
  fs::remove_all(files.dir);
  return 0;
}
