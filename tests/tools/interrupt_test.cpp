// A bake stopped halfway leaves nothing behind. sweep-sim bakes to .glb and .pc2 with a
// report; SIGINT, SIGTERM and SIGHUP at random moments (seeded, a bounded number) must end it with
// 130, 143 or 129, "error: interrupted by ...", and the folder exactly as it was: no output under
// its final name, no temporary. After SIGKILL nothing can run, so the temporary stays; the next run
// writing there removes it and says so.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <random>
#include <thread>

#include "pipeline.h"

extern char** environ;

namespace sweep::test {
namespace {

using Clock = std::chrono::steady_clock;

// A bake of a second or two: 1.2 s of motion at 30 fps, stepped every microsecond — every ten
// under the sanitizers, where each step costs many times more (with the same step, this one test
// took 633 s of CI's 29 minutes).
#if defined(SWEEP_SANITIZED)
#define SWEEP_LONG_SCENE_STEP "1e-5"
constexpr int kMomentsPerSignal = 1;
#else
#define SWEEP_LONG_SCENE_STEP "1e-6"
constexpr int kMomentsPerSignal = 2;
#endif
constexpr const char* kLongScene =
    R"({"format": "sweep-scene", "version": 1, "duration": 1.2, "fps": 30, "step": )" SWEEP_LONG_SCENE_STEP R"(,
  "forces": [{"sweep": "tube", "t": 1, "theta": 0, "vector": [0, 1, 0], "start": 0, "end": 1.2}]}
)";

struct Bake {
  pid_t pid = -1;
};

// Starts sweep-sim on the workspace's rig with the long scene, stdout and stderr to `io`.
Bake start_bake(const Workspace& ws) {
  const std::string out = (ws.io / "stdout.txt").string(), err = (ws.io / "stderr.txt").string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const std::string rig = (ws / "rig.json").string(), scene = (ws / "long.json").string();
  const std::string glb = (ws / "out.glb").string(), pc2 = (ws / "out.pc2").string();
  const std::string report = (ws / "report.json").string();
  std::vector<std::string> args{SWEEP_SIM_EXE, rig, "-s", scene, "-o", glb, "-o", pc2, "--report", report};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  Bake b;
  EXPECT_EQ(posix_spawn(&b.pid, SWEEP_SIM_EXE, &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  return b;
}

// The exit code, or 128 + the signal for a process a signal ended; -1 after 300 s (killed).
int wait_for(const Bake& b) {
  const auto deadline = Clock::now() + std::chrono::seconds(300);
  int status = 0;
  while (waitpid(b.pid, &status, WNOHANG) == 0) {
    if (Clock::now() > deadline) {
      kill(b.pid, SIGKILL);
      waitpid(b.pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> found;
  for (const std::string& name : listing(dir)) {
    if (name.find(".tmp-") != std::string::npos || name.find(".old-") != std::string::npos) {
      found.push_back(name);
    }
  }
  return found;
}

TEST(Interrupt, SignalsAtRandomMomentsLeaveTheFolderAsItWas) {
  Workspace ws("interrupt-signals");
  spit(ws / "long.json", kLongScene);
  const std::set<std::string> before = listing(ws.work);
  // The whole bake once, to know how long it takes (and that it writes all three files).
  const auto t0 = Clock::now();
  ASSERT_EQ(wait_for(start_bake(ws)), 0) << slurp(ws.io / "stderr.txt");
  const double full = std::chrono::duration<double>(Clock::now() - t0).count();
  for (const char* name : {"out.glb", "out.pc2", "report.json"}) {
    EXPECT_TRUE(fs::exists(ws / name)) << name;
    fs::remove(ws / name);
  }
  ASSERT_EQ(listing(ws.work), before);

  std::mt19937 random(15);  // seeded: the same moments every run
  std::uniform_real_distribution<double> moment(0.05, 0.7);
  int interrupted = 0;
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    for (int k = 0; k < kMomentsPerSignal; ++k) {
      const double at = moment(random) * full;
      const Bake b = start_bake(ws);
      std::this_thread::sleep_for(std::chrono::duration<double>(at));
      kill(b.pid, signal);
      const int code = wait_for(b);
      const std::string err = slurp(ws.io / "stderr.txt");
      SCOPED_TRACE(std::string(strsignal(signal)) + " after " + std::to_string(at) + " s of " + std::to_string(full) +
                   " s\n" + err);
      if (code == 0) {  // finished first (a slow start): then everything is there; start again
        for (const char* name : {"out.glb", "out.pc2", "report.json"}) fs::remove(ws / name);
        continue;
      }
      ++interrupted;
      EXPECT_EQ(code, 128 + signal);
      const char* signal_name = signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "SIGHUP";
      EXPECT_NE(err.find(std::string("error: interrupted by ") + signal_name), std::string::npos);
      EXPECT_NE(err.find("not written: " + (ws / "out.glb").string() + ", " + (ws / "out.pc2").string() + ", " +
                         (ws / "report.json").string()),
                std::string::npos)
          << "names every output";
      EXPECT_EQ(listing(ws.work), before) << "no output under its final name, no temporary";
    }
  }
  EXPECT_GE(interrupted, 2 * kMomentsPerSignal) << "most runs must have been caught halfway";
}

TEST(Interrupt, AKilledRunsTemporaryIsRemovedByTheNextRun) {
  Workspace ws("interrupt-kill");
  spit(ws / "long.json", kLongScene);
  const std::set<std::string> before = listing(ws.work);
  const Bake killed = start_bake(ws);
  // The .pc2 is written frame by frame into its temporary: wait until there is one.
  const auto deadline = Clock::now() + std::chrono::seconds(60);
  while (temporaries(ws.work).empty() && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(killed.pid, SIGKILL);
  EXPECT_EQ(wait_for(killed), 128 + SIGKILL);
  const std::vector<std::string> left = temporaries(ws.work);
  ASSERT_FALSE(left.empty()) << "SIGKILL cannot be caught: the temporary stays";
  EXPECT_NE(left[0].find(".sweep-sim-" + std::to_string(killed.pid) + ".tmp-"), std::string::npos)
      << left[0] << ": a temporary names its tool and process";

  const Bake next = start_bake(ws);
  ASSERT_EQ(wait_for(next), 0) << slurp(ws.io / "stderr.txt");
  const std::string err = slurp(ws.io / "stderr.txt");
  EXPECT_NE(err.find("note: removed"), std::string::npos) << err;
  EXPECT_NE(err.find(left[0]), std::string::npos) << err;
  EXPECT_TRUE(temporaries(ws.work).empty());
  EXPECT_EQ(listing(ws.work).size(), before.size() + 3) << "out.glb, out.pc2, report.json";
}

}  // namespace
}  // namespace sweep::test
