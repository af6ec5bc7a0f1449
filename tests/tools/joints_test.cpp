// sweep-sim --joints N (issue 14 part 2): a skinned .glb instead of morph targets, its error against
// the bake in the summary and the report; a bad N is a usage error (exit 1) that writes nothing.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "pipeline.h"

namespace sweep::test {
namespace {

TEST(Joints, ASkinnedBakeReportsItsErrorAndIsFarSmallerThanTheMorphBake) {
  const Workspace ws("joints-ok");
  const std::string base = quoted(ws / "rig.json") + " -s " + quoted(ws / "scene.json");
  ToolRun r = run_tool(SWEEP_SIM_EXE,
                       base + " -o " + quoted(ws / "skin.glb") + " -o " + quoted(ws / "skin.pc2") +
                           " --joints 8 --report " + quoted(ws / "r.json"),
                       ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("skinned .glb: 9 joints (8 a sweep and the body); against the bake: max "),
            std::string::npos)
      << r.out;
  const nlohmann::json report = nlohmann::json::parse(slurp(ws / "r.json"));
  ASSERT_TRUE(report.contains("skin_error_max_relative")) << report.dump(2);
  const double max = report["skin_error_max_relative"].get<double>();
  const double rms = report["skin_error_rms_relative"].get<double>();
  EXPECT_GT(max, 0);
  EXPECT_LT(max, 0.05);
  EXPECT_LE(rms, max);
  EXPECT_EQ(report["skin_joints"], 9);
  EXPECT_EQ(report["joints_per_sweep"], 8);
  r = run_tool(SWEEP_SIM_EXE, base + " -q -o " + quoted(ws / "morph.glb"), ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_LT(fs::file_size(ws / "skin.glb"), fs::file_size(ws / "morph.glb"));
  // Without --joints the report has no skin figures.
  r = run_tool(SWEEP_SIM_EXE, base + " -q -o " + quoted(ws / "m2.glb") + " --report " + quoted(ws / "r2.json"), ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(nlohmann::json::parse(slurp(ws / "r2.json")).contains("skin_error_max_relative"));
}

TEST(Joints, BadJointCountsExitOneAndWriteNothing) {
  const Workspace ws("joints-bad");
  const std::set<std::string> before = listing(ws.work);
  const std::string base = quoted(ws / "rig.json") + " -s " + quoted(ws / "scene.json") + " -o " +
                           quoted(ws / "out.glb") + " --report " + quoted(ws / "r.json");
  // The tube's rig has K = 6 sections: 41 stations at the default 8 a span, 6 at --stations 1.
  for (const std::string& bad :
       {std::string("--joints 1"), std::string("--joints 0"), std::string("--joints -4"),
        std::string("--joints 256"), std::string("--joints 1000"), std::string("--joints 42"),
        std::string("--joints 7 --stations 1"), std::string("--joints abc"), std::string("--joints")}) {
    const ToolRun r = run_tool(SWEEP_SIM_EXE, base + " " + bad, ws.io);
    EXPECT_EQ(r.code, 1) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("--joints"), std::string::npos) << bad << ": " << r.err;
    EXPECT_EQ(r.out, "") << bad;
    EXPECT_EQ(listing(ws.work), before) << bad;
  }
  const ToolRun r = run_tool(SWEEP_SIM_EXE,
                             quoted(ws / "rig.json") + " -s " + quoted(ws / "scene.json") + " -o " +
                                 quoted(ws / "out.pc2") + " --joints 8",
                             ws.io);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("--joints: skins a .glb output"), std::string::npos) << r.err;
  EXPECT_EQ(listing(ws.work), before);
  // The largest the tube allows is taken.
  const ToolRun ok = run_tool(SWEEP_SIM_EXE, base + " -q --joints 41", ws.io);
  EXPECT_EQ(ok.code, 0) << ok.err;
}

TEST(Joints, TheSkinnedFileIsTheSameBytesWhateverTheThreadCount) {
  const Workspace ws("joints-determinism");
  const std::string base = quoted(ws / "rig.json") + " -s " + quoted(ws / "scene.json") + " -q --joints 12";
  ToolRun r = run_tool(SWEEP_SIM_EXE, base + " -o " + quoted(ws / "a.glb") + " --threads 1", ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_tool(SWEEP_SIM_EXE, base + " -o " + quoted(ws / "b.glb") + " --threads 2", ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_tool(SWEEP_SIM_EXE, base + " -o " + quoted(ws / "c.glb") + " --threads 2", ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string a = slurp(ws / "a.glb");
  EXPECT_GT(a.size(), 1000u);
  EXPECT_EQ(a, slurp(ws / "b.glb"));
  EXPECT_EQ(a, slurp(ws / "c.glb"));
  // No temporaries left beside them.
  for (const auto& name : listing(ws.work)) EXPECT_EQ(name.find(".tmp-"), std::string::npos) << name;
}

}  // namespace
}  // namespace sweep::test
