// Size before surprise: a bake's files are estimated before it starts; --max-output-size
// refuses early (exit 4, nothing written) and a .glb with more morph targets than engines are sure
// to take is warned about, with what to use instead.
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include "pipeline.h"

namespace sweep::test {
namespace {

// `frames` frames at 32 fps (a duration a binary fraction holds exactly).
std::string scene_of(int frames) {
  return R"({"format": "sweep-scene", "version": 1, "fps": 32, "duration": )" + std::to_string((frames - 1) / 32.0) +
         R"(, "forces": [{"sweep": "tube", "t": 1, "theta": 0, "vector": [0, 1, 0], "start": 0, "end": 0.2}]})";
}

TEST(OutputSize, MaxOutputSizeRefusesBeforeSimulating) {
  const Workspace ws("output-size-limit");
  spit(ws / "s.json", scene_of(61));
  const std::set<std::string> before = listing(ws.work);
  const std::string args = quoted(ws / "rig.json") + " -s " + quoted(ws / "s.json") + " -o " + quoted(ws / "out.glb") +
                           " -o " + quoted(ws / "out.pc2");
  // The tube has 794 vertices: the .pc2 alone is 32 + 61 x 794 x 12 bytes, about 0.58 MB.
  ToolRun r = run_tool(SWEEP_SIM_EXE, args + " --max-output-size 500K", ws.io);
  EXPECT_EQ(r.code, 4) << r.err;
  EXPECT_NE(r.err.find("the bake would write about"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("out.pc2 0.581 MB"), std::string::npos) << r.err;
  // 500K is 500,000 bytes (powers of 1000, as the help says; CLI11's own size reader took 512,000).
  EXPECT_NE(r.err.find("more than the limit of 0.5 MB; nothing was written"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "") << "refused before the bake: no summary";
  EXPECT_EQ(listing(ws.work), before);
  r = run_tool(SWEEP_SIM_EXE, args + " --max-output-size 10M -q", ws.io);
  EXPECT_EQ(r.code, 0) << r.err;
  const std::uintmax_t written = fs::file_size(ws / "out.glb") + fs::file_size(ws / "out.pc2");
  EXPECT_LT(written, 10'000'000u);
  EXPECT_EQ(fs::file_size(ws / "out.pc2"), 32u + 61u * 794u * 12u);
}

TEST(OutputSize, ManyMorphTargetsAreWarnedAboutWithWhatToUseInstead) {
  const Workspace ws("output-size-targets");
  const std::string base = quoted(ws / "rig.json") + " -s " + quoted(ws / "s.json") + " -q -o ";
  spit(ws / "s.json", scene_of(256));
  ToolRun r = run_tool(SWEEP_SIM_EXE, base + quoted(ws / "a.glb"), ws.io);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("morph targets"), std::string::npos) << "256 are fine: " << r.err;
  spit(ws / "s.json", scene_of(257));
  r = run_tool(SWEEP_SIM_EXE, base + quoted(ws / "b.glb"), ws.io);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("257 morph targets"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bake to .pc2"), std::string::npos) << r.err;
  r = run_tool(SWEEP_SIM_EXE, base + quoted(ws / "b.pc2"), ws.io);
  EXPECT_EQ(r.err.find("morph targets"), std::string::npos) << ".pc2 has none: " << r.err;
}

// A full disk: a 600 kB tmpfs (where this machine lets the test mount one) takes the rig's folder
// but not a 1 MB bake. Exit 4 naming the file and the cause, nothing left in the folder.
TEST(OutputSize, AFullDiskLeavesNothingBehind) {
  const Workspace ws("output-size-full-disk");
  const fs::path small = ws.work.parent_path() / "small";
  fs::create_directories(small);
  const std::string mount = "mount -t tmpfs -o size=600k tmpfs " + quoted(small) + " 2>/dev/null";
  if (std::system(mount.c_str()) != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (needs root and a kernel that allows it)";
  spit(ws / "s.json", scene_of(120));  // the .pc2: 32 + 120 x 794 x 12 bytes, about 1.1 MB
  const ToolRun r = run_tool(SWEEP_SIM_EXE,
                             quoted(ws / "rig.json") + " -s " + quoted(ws / "s.json") + " -q -o " +
                                 quoted(small / "out.pc2") + " -o " + quoted(small / "out.glb"),
                             ws.io);
  const std::set<std::string> left = listing(small);
  std::system(("umount " + quoted(small)).c_str());
  EXPECT_EQ(r.code, 4) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_TRUE(left.empty()) << *left.begin();
}

extern "C" char** environ;

// Peak resident memory of one sweep-sim run, kB (its stdout and stderr dropped).
long peak_kb(const std::vector<std::string>& arguments) {
  std::vector<std::string> args{SWEEP_SIM_EXE};
  args.insert(args.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  EXPECT_EQ(posix_spawn(&pid, SWEEP_SIM_EXE, &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  return usage.ru_maxrss;
}

// Memory does not grow with the bake's length: frames stream to the files (a .glb's JSON is the
// one part that grows: two accessors a morph target, POSITION and NORMAL, about 4 kB each as
// tinygltf objects: 8.2 kB a frame measured, where one accessor a frame stayed under the former
// bar of 8).
TEST(OutputSize, PeakMemoryIsFlatInTheBakesLength) {
#if defined(SWEEP_SANITIZED)
  GTEST_SKIP() << "AddressSanitizer keeps freed memory in quarantine: peaks say nothing there";
#endif
  const Workspace ws("output-size-memory");
  spit(ws / "short.json", scene_of(100));
  spit(ws / "long.json", scene_of(4000));
  const auto peak = [&](const char* scene, const char* out) {
    return peak_kb({(ws / "rig.json").string(), "-s", (ws / scene).string(), "-q", "-o", (ws / out).string()});
  };
  const long pc2_short = peak("short.json", "a.pc2"), pc2_long = peak("long.json", "b.pc2");
  EXPECT_LT(pc2_long - pc2_short, 4 * 1024)
      << ".pc2: " << pc2_short << " kB for 100 frames, " << pc2_long << " kB for 4,000";
  const long glb_short = peak("short.json", "a.glb"), glb_long = peak("long.json", "b.glb");
  EXPECT_LT(static_cast<double>(glb_long - glb_short) / 3900, 12.0)
      << ".glb: " << glb_short << " kB for 100 frames, " << glb_long << " kB for 4,000";
}

}  // namespace
}  // namespace sweep::test
