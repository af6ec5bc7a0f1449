// An .obj sequence is one output of many files, and the bake owns it: a shorter re-bake leaves no
// frame of the longer one beside its own; the earlier files a run killed while publishing had set
// aside are put back (or removed, when the new file took the name) by the next run; a signal
// removes every temporary however many frames the bake has; and --max-output-size holds for what
// is written, not for a typical line length.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <sstream>
#include <thread>

#include "pipeline.h"

extern char** environ;

namespace sweep::test {
namespace {

using Clock = std::chrono::steady_clock;

std::string scene(double duration, double fps, const std::string& extra = "") {
  return R"({"format": "sweep-scene", "version": 1, "duration": )" + std::to_string(duration) + R"(, "fps": )" +
         std::to_string(fps) + extra +
         R"(, "forces": [{"sweep": "tube", "t": 1, "theta": 0, "vector": [0, 1, 0], "start": 0, "end": 0.2}]})";
}

std::vector<std::string> frames(const fs::path& dir, const std::string& stem) {
  std::vector<std::string> out;
  for (const std::string& name : listing(dir)) {
    if (name.rfind(stem + "_", 0) == 0) out.push_back(name);
  }
  return out;
}

std::vector<std::string> hidden(const fs::path& dir) {
  std::vector<std::string> out;
  for (const std::string& name : listing(dir)) {
    if (!name.empty() && name[0] == '.') out.push_back(name);
  }
  return out;
}

std::string bake(const Workspace& ws, const std::string& scene_file, const std::string& out) {
  return quoted(ws / "rig.json") + " -s " + quoted(ws / scene_file) + " -q -o " + quoted(ws / out);
}

TEST(ObjSequence, AShorterRebakeRemovesTheLongerOnesFrames) {
  const Workspace ws("obj-sequence-rebake");
  spit(ws / "long.json", scene(2.0, 20));   // 41 frames
  spit(ws / "short.json", scene(0.5, 10));  // 6 frames
  ASSERT_EQ(run_tool(SWEEP_SIM_EXE, bake(ws, "long.json", "o.obj"), ws.io).code, 0);
  ASSERT_EQ(frames(ws.work, "o").size(), 41u);
  // Beside the sequence, files of its name pattern that no bake wrote: kept.
  spit(ws / "o_0100.obj", "v 0 0 0\n");
  spit(ws / "o_notes.obj", "# sweep bake 1: frame 0 of a file named by hand\n");
  const ToolRun r = run_tool(SWEEP_SIM_EXE, bake(ws, "short.json", "o.obj"), ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(frames(ws.work, "o"), (std::vector<std::string>{"o_0000.obj", "o_0001.obj", "o_0002.obj", "o_0003.obj",
                                                            "o_0004.obj", "o_0005.obj", "o_0100.obj", "o_notes.obj"}));
  EXPECT_EQ(slurp(ws / "o_0005.obj").rfind("# sweep bake 1: frame 5 of 6,", 0), 0u);
  EXPECT_TRUE(hidden(ws.work).empty());
}

// A run killed between setting the earlier frames aside and renaming its own into place leaves
// them hidden (".o_0000.obj.old-XXXXXX", as earlier versions named them, or with the tool and
// process as now). The next run writing into the folder puts back the one whose name is free and
// removes the one whose name the new file took, each with a note.
TEST(ObjSequence, FilesAKilledRunSetAsideArePutBackOrRemoved) {
  const Workspace ws("obj-sequence-set-aside");
  spit(ws / "short.json", scene(0.5, 10));
  ASSERT_EQ(run_tool(SWEEP_SIM_EXE, bake(ws, "short.json", "o.obj"), ws.io).code, 0);
  const std::string frame0 = slurp(ws / "o_0000.obj");
  // A process that is gone: one that ran and was waited for.
  pid_t gone = 0;
  char arg0[] = "true";
  char* argv[] = {arg0, nullptr};
  ASSERT_EQ(posix_spawnp(&gone, "true", nullptr, nullptr, argv, environ), 0);
  waitpid(gone, nullptr, 0);
  fs::rename(ws / "o_0000.obj", ws / ".o_0000.obj.old-Ab12Cd");  // the name left free: put back
  spit(ws / (".o_0001.obj.sweep-sim-" + std::to_string(gone) + ".old-Xy34Zw"), "the earlier frame 1\n");
  const std::string frame1 = slurp(ws / "o_0001.obj");  // the new frame took the name: removed
  const ToolRun r = run_tool(SWEEP_SIM_EXE, bake(ws, "short.json", "other.pc2"), ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "") << "-q: no notes";
  EXPECT_EQ(slurp(ws / "o_0000.obj"), frame0);
  EXPECT_EQ(slurp(ws / "o_0001.obj"), frame1);
  EXPECT_TRUE(hidden(ws.work).empty());

  // The same, said: without -q the notes name both.
  fs::rename(ws / "o_0000.obj", ws / ".o_0000.obj.old-Ef56Gh");
  spit(ws / ".o_0001.obj.old-Ij78Kl", "the earlier frame 1\n");
  const std::string rig =
      quoted(ws / "rig.json") + " -s " + quoted(ws / "short.json") + " -o " + quoted(ws / "fourth.pc2");
  const ToolRun said = run_tool(SWEEP_SIM_EXE, rig, ws.io);
  ASSERT_EQ(said.code, 0) << said.err;
  EXPECT_NE(said.err.find("note: put back " + (ws / "o_0000.obj").string()), std::string::npos) << said.err;
  EXPECT_NE(said.err.find("note: removed " + (ws / ".o_0001.obj.old-Ij78Kl").string()), std::string::npos) << said.err;
  EXPECT_EQ(slurp(ws / "o_0000.obj"), frame0);
  EXPECT_TRUE(hidden(ws.work).empty());
}

// --max-output-size is an upper bound on what the bake writes: under a limit one byte short of
// what the sequence takes it is refused before anything is written; under any limit it is taken
// at, it writes no more than the limit. The tube is made a third the size and moved off the origin,
// and the body moves, so every coordinate of every frame takes eight or nine digits and a sign
// (the estimate used to assume a typical 36-byte line and let this bake overrun the limit).
TEST(ObjSequence, TheSizeLimitHoldsForWhatIsWritten) {
  const Workspace ws("obj-sequence-size");
  std::istringstream in(slurp(ws / "tube.obj"));
  std::string obj;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) == 0) {
      std::istringstream v(line.substr(2));
      double x = 0, y = 0, z = 0;
      v >> x >> y >> z;
      char text[128];
      std::snprintf(text, sizeof text, "v %.9g %.9g %.9g", x / 3 - 0.0123457, y / 3 - 0.0234568, z / 3 - 0.3456789);
      line = text;
    }
    obj += line + "\n";
  }
  spit(ws / "off.obj", obj);
  ASSERT_EQ(run_tool(SWEEP_FIT_EXE,
                     quoted(ws / "off.obj") + " -o " + quoted(ws / "off.rig.json") +
                         " --name tube --root -0.0123457,-0.0234568,-0.3390122"
                         " --tip -0.0123457,-0.0234568,-0.0123456 -k 6 -n 8 -q",
                     ws.io)
                .code,
            0);
  ASSERT_EQ(run_tool(SWEEP_BIND_EXE, quoted(ws / "off.rig.json") + " -q", ws.io).code, 0);
  spit(ws / "moving.json", scene(1.0, 30, R"(, "body": {"keys": [{"time": 0, "translation": [0, 0, 0]},
                                                                  {"time": 1, "translation": [0.1, 0.2, 0.3]}]})"));
  auto run = [&](const std::string& out, const std::string& extra) {
    return run_tool(
        SWEEP_SIM_EXE,
        quoted(ws / "off.rig.json") + " -s " + quoted(ws / "moving.json") + " -q -o " + quoted(ws / out) + extra,
        ws.io);
  };
  ASSERT_EQ(run("o.obj", "").code, 0);
  std::uint64_t written = 0;
  for (const std::string& f : frames(ws.work, "o")) written += fs::file_size(ws / f);
  ASSERT_GT(written, 1000000u);
  const std::set<std::string> before = listing(ws.work);
  int taken = 0;
  for (const double share : {1.0, 1.2, 1.4, 1.6, 2.0}) {
    const std::uint64_t limit = static_cast<std::uint64_t>(share * static_cast<double>(written)) - (share == 1.0);
    const ToolRun r = run("n.obj", " --max-output-size " + std::to_string(limit));
    SCOPED_TRACE("limit " + std::to_string(limit) + " for " + std::to_string(written) + " bytes\n" + r.err);
    if (share == 1.0) {
      EXPECT_EQ(r.code, 4) << "one byte short of what it writes";
    }
    if (r.code == 4) {
      EXPECT_NE(r.err.find("more than the limit"), std::string::npos);
      EXPECT_EQ(listing(ws.work), before);
      continue;
    }
    ASSERT_EQ(r.code, 0);
    ++taken;
    std::uint64_t now = 0;
    for (const std::string& f : frames(ws.work, "n")) now += fs::file_size(ws / f);
    EXPECT_EQ(now, written) << "the same frames";
    EXPECT_LE(now, limit);
    for (const std::string& f : frames(ws.work, "n")) fs::remove(ws / f);
  }
  EXPECT_GE(taken, 1) << "twice what it writes is a limit the estimate must meet";
}

// SIGTERM while a sequence of 601 frames has hundreds of temporaries: every one removed (the
// handler used to track 256 and leave the rest).
TEST(ObjSequence, ASignalRemovesEveryTemporaryOfALongSequence) {
  const Workspace ws("obj-sequence-signal");
  spit(ws / "long.json", scene(60, 10, R"(, "step": 2e-5)"));
  const std::set<std::string> before = listing(ws.work);
  const std::string out = (ws.io / "stdout.txt").string(), err = (ws.io / "stderr.txt").string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<std::string> args{SWEEP_SIM_EXE, (ws / "rig.json").string(), "-s", (ws / "long.json").string(), "-q",
                                "-o",          (ws / "o.obj").string()};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  ASSERT_EQ(posix_spawn(&pid, SWEEP_SIM_EXE, &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  std::size_t seen = 0;
  const auto deadline = Clock::now() + std::chrono::seconds(120);
  int status = 0;
  bool ended = false;
  while (seen < 300 && Clock::now() < deadline) {
    if (waitpid(pid, &status, WNOHANG) == pid) {
      ended = true;
      break;
    }
    seen = hidden(ws.work).size();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (!ended) {
    kill(pid, SIGTERM);
    waitpid(pid, &status, 0);
  }
  ASSERT_FALSE(ended) << "the bake ended before 300 frames were held (" << seen << "): make it longer";
  ASSERT_GE(seen, 300u);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 143) << slurp(ws.io / "stderr.txt");
  EXPECT_NE(slurp(ws.io / "stderr.txt").find("error: interrupted by SIGTERM"), std::string::npos);
  const std::set<std::string> after = listing(ws.work);
  EXPECT_EQ(after.size(), before.size()) << hidden(ws.work).size() << " temporaries left";
  EXPECT_EQ(after, before);
}

}  // namespace
}  // namespace sweep::test
