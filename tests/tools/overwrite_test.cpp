// The promises that need more than one run or more than the matrix's one-run shape:
// no tool writes onto what it reads, an earlier bake survives a later one that fails, two bakes
// of one .obj sequence never mix, a closed stdout is no error, out of memory is exit 6.
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>

#include "pipeline.h"

namespace sweep::test {
namespace {

using nlohmann::json;

std::map<std::string, std::string> files_of(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const std::string& name : listing(dir)) files[name] = slurp(dir / name);
  return files;
}

// Every input of every tool given as an output, one run each: refused with exit 1 and a message
// naming both roles, before any work (stderr holds that one line and nothing else — no warning
// or progress of a later stage), and the folder byte for byte as it was.
TEST(Overwrite, OutputOntoAnyInputIsRefusedBeforeAnyWork) {
  const Workspace ws("overwrite-inputs");
  const std::string rig = quoted(ws / "rig.json"), scene = " -s " + quoted(ws / "scene.json");
  struct Run {
    const char* tool;
    std::string args, expect;
  };
  std::vector<Run> runs;
  for (const char* input : {"rig.json", "scene.json", "rig.bind", "tube.obj"}) {
    runs.push_back(
        {SWEEP_SIM_EXE, rig + scene + " -o " + quoted(ws / "o.pc2") + " --report " + quoted(ws / input), "--report "});
  }
  runs.push_back({SWEEP_SIM_EXE, rig + scene + " -o " + quoted(ws / "rig.bind"), "-o "});
  for (const char* input : {"rig.json", "tube.obj"}) {
    runs.push_back({SWEEP_BIND_EXE, rig + " -o " + quoted(ws / input), "the binding "});
    runs.push_back(
        {SWEEP_BIND_EXE, rig + " -o " + quoted(ws / "b.bind") + " --report " + quoted(ws / input), "--report "});
  }
  runs.push_back({SWEEP_FIT_EXE,
                  quoted(ws / "tube.obj") + " -o " + quoted(ws / "tube.obj") + " --name t --root 0,0,0.02 --tip 0,0,1",
                  "-o "});
  runs.push_back({SWEEP_FIT_EXE,
                  quoted(ws / "tube.obj") + " -o " + rig + " --report " + quoted(ws / "tube.obj") +
                      " --name t --root 0,0,0.02 --tip 0,0,1",
                  "--report "});
  const auto before = files_of(ws.work);
  for (const Run& run : runs) {
    const ToolRun r = run_tool(run.tool, run.args, ws.io);
    SCOPED_TRACE(std::string(run.tool) + " " + run.args + "\nstderr: " + r.err);
    EXPECT_EQ(r.code, 1);
    ASSERT_EQ(r.err_lines().size(), 1u);
    EXPECT_EQ(r.err.rfind("error: " + run.expect, 0), 0u);
    EXPECT_NE(r.err.find("is the same file as"), std::string::npos);
    EXPECT_EQ(r.out, "");
    EXPECT_TRUE(files_of(ws.work) == before) << "a file was changed, added or removed";
  }
}

// Hard links and symlinks are the same file too: identity, not spelling.
TEST(Overwrite, OutputThroughAHardLinkOrASymlinkedFolderIsRefused) {
  const Workspace ws("overwrite-links");
  fs::create_hard_link(ws / "scene.json", ws / "linked.json");
  fs::create_directory_symlink(ws.work, ws / "alias");
  const auto before = files_of(ws.work);
  for (const std::string& report : {std::string("linked.json"), std::string("alias/rig.bind")}) {
    const ToolRun r = run_tool(SWEEP_SIM_EXE,
                               quoted(ws / "rig.json") + " -s " + quoted(ws / "scene.json") + " -q -o " +
                                   quoted(ws / "o.pc2") + " --report " + quoted(ws / report),
                               ws.io);
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find("is the same file as"), std::string::npos) << r.err;
  }
  EXPECT_TRUE(files_of(ws.work) == before);
}

// sweep-fit adding a sweep to a rig that carries its scene keeps the scene, value for value.
TEST(Overwrite, FitKeepsTheRigsScene) {
  const Workspace ws("overwrite-fit-scene");
  json rig = json::parse(slurp(ws / "rig.json"));
  rig["scene"] = json::parse(kScene);
  spit(ws / "rig.json", rig.dump(2));
  const ToolRun r = run_tool(SWEEP_FIT_EXE,
                             quoted(ws / "tube.obj") + " -o " + quoted(ws / "rig.json") +
                                 " --name second --root 0,0,0.5 --tip 0,0,1 -k 4 -n 8",
                             ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  const json after = json::parse(slurp(ws / "rig.json"));
  ASSERT_TRUE(after.contains("scene"));
  EXPECT_EQ(after["scene"], json::parse(kScene));
  EXPECT_EQ(after["sweeps"].size(), 2u);
}

std::string sim(const Workspace& ws, const std::string& scene, const std::string& out) {
  return quoted(ws / "rig.json") + " -s " + quoted(ws / scene) + " -q -o " + quoted(ws / out);
}

// An .obj bake over an earlier one that then fails (here: diverges) leaves the earlier frames.
TEST(Overwrite, ObjRebakeThatFailsKeepsTheEarlierFrames) {
  const Workspace ws("overwrite-obj-rebake");
  ASSERT_EQ(run_tool(SWEEP_SIM_EXE, sim(ws, "scene.json", "out.obj"), ws.io).code, 0);
  const auto before = files_of(ws.work);
  ASSERT_TRUE(before.count("out_0005.obj"));
  json rig = json::parse(slurp(ws / "rig.json"));
  rig["sweeps"][0]["springs"]["bend"]["frequency_hz"] = 1000;
  json scene = json::parse(kScene);
  scene["integrator"] = "semi-implicit-euler";
  scene["substeps"] = 1;
  scene["forces"][0]["vector"] = {0, 100, 0};
  rig["scene"] = scene;
  spit(ws / "diverging.rig.json", rig.dump(2));
  fs::copy_file(ws / "rig.bind", ws / "diverging.rig.bind");
  const auto inputs = files_of(ws.work);
  const ToolRun r =
      run_tool(SWEEP_SIM_EXE, quoted(ws / "diverging.rig.json") + " -q -o " + quoted(ws / "out.obj"), ws.io);
  EXPECT_EQ(r.code, 5) << r.err;
  EXPECT_TRUE(files_of(ws.work) == inputs) << "the earlier frames were touched";
}

// Two runs baking one .obj sequence at once: every frame in the folder comes from one of them.
TEST(Overwrite, TwoObjBakesAtOnceDoNotMix) {
  const Workspace ws("overwrite-obj-race");
  json strong = json::parse(kScene);
  strong["forces"][0]["vector"] = {0, 3, 0};
  spit(ws / "strong.json", strong.dump());
  fs::create_directories(ws.work / "a");
  fs::create_directories(ws.work / "b");
  ASSERT_EQ(run_tool(SWEEP_SIM_EXE, sim(ws, "scene.json", "a/out.obj"), ws.io).code, 0);
  ASSERT_EQ(run_tool(SWEEP_SIM_EXE, sim(ws, "strong.json", "b/out.obj"), ws.io).code, 0);
  const auto a = files_of(ws.work / "a"), b = files_of(ws.work / "b");
  ASSERT_NE(a, b);
  for (int round = 0; round < 3; ++round) {
    fs::remove_all(ws.work / "c");
    fs::create_directories(ws.work / "c");
    const std::string both = "'" + std::string(SWEEP_SIM_EXE) + "' " + sim(ws, "scene.json", "c/out.obj") + " & '" +
                             SWEEP_SIM_EXE + "' " + sim(ws, "strong.json", "c/out.obj") + " & wait";
    ASSERT_EQ(std::system(both.c_str()), 0);
    const auto c = files_of(ws.work / "c");
    EXPECT_TRUE(c == a || c == b) << "round " << round << ": frames of both runs mixed";
  }
}

// `sweep-sim ... | true`: the reader is gone before the summary is printed. The run still
// succeeds (SIGPIPE ignored, the lines dropped) and its output is there.
TEST(Overwrite, ClosedStdoutIsNoError) {
  const Workspace ws("overwrite-closed-stdout");
  const std::string cmd = "bash -c \"'" + std::string(SWEEP_SIM_EXE) + "' " + quoted(ws / "rig.json") + " -s " +
                          quoted(ws / "scene.json") + " -o " + quoted(ws / "o.pc2") + " 2>" +
                          quoted(ws.io / "err.txt") + " | true; exit \\${PIPESTATUS[0]}\"";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << slurp(ws.io / "err.txt");
  EXPECT_TRUE(fs::exists(ws / "o.pc2"));
}

// Out of memory (a 30 MB scene, within the size limit, under a 300 MB address-space limit) is
// exit 6 with a message, not an abort, and leaves nothing behind. Not under ASan, whose shadow
// memory does not fit such a limit.
#if !defined(SWEEP_SANITIZED)
TEST(Overwrite, OutOfMemoryIsExit6WithAMessage) {
  const Workspace ws("overwrite-oom");
  json scene = json::parse(kScene);
  const json force = scene["forces"][0];
  scene["forces"] = json::array();
  for (int i = 0; i < 300000; ++i) scene["forces"].push_back(force);
  spit(ws / "big.json", scene.dump());
  const auto before = files_of(ws.work);
  const ToolRun r = run_tool(SWEEP_SIM_EXE, sim(ws, "big.json", "o.pc2"), ws.io, "ulimit -v 300000;");
  EXPECT_EQ(r.code, 6) << r.err;
  EXPECT_EQ(r.err, "error: out of memory\n");
  EXPECT_TRUE(files_of(ws.work) == before);
}
#endif

}  // namespace
}  // namespace sweep::test
