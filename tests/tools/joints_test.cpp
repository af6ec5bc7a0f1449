// sweep-sim --joints N: a skinned .glb instead of morph targets, its error against
// the bake in the summary and the report; a bad N is a usage error (exit 1) that writes nothing.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "pipeline.h"
#include "sweep/assets/bake_skin.h"

namespace sweep::test {
namespace {

TEST(Joints, ASkinnedBakeReportsItsErrorAndIsFarSmallerThanTheMorphBake) {
  const Workspace ws("joints-ok");
  const std::string base = quoted(ws / "rig.json") + " -s " + quoted(ws / "scene.json");
  ToolRun r = run_tool(SWEEP_SIM_EXE,
                       base + " -o " + quoted(ws / "skin.glb") + " -o " + quoted(ws / "skin.pc2") +
                           " --joints 8 --ring-joints 1 --report " + quoted(ws / "r.json"),
                       ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("skinned .glb: 9 joints (8 a sweep, and the body); against the bake: max "), std::string::npos)
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
  EXPECT_EQ(report["ring_joints"], 1);
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
  for (const std::string& bad : {std::string("--joints 1"), std::string("--joints 0"), std::string("--joints -4"),
                                 std::string("--joints 256"), std::string("--joints 1000"), std::string("--joints 42"),
                                 std::string("--joints 7 --stations 1"), std::string("--joints abc"),
                                 std::string("--joints 4 --ring-joints 0"), std::string("--joints --ring-joints 65"),
                                 std::string("--ring-joints 4"), std::string("--joints 4 --ring-joints")}) {
    const ToolRun r = run_tool(SWEEP_SIM_EXE, base + " " + bad, ws.io);
    EXPECT_EQ(r.code, 1) << bad << ": " << r.err;
    EXPECT_NE(r.err.find(bad.find("--ring-joints") == std::string::npos ? "--joints" : "--ring-joints"),
              std::string::npos)
        << bad << ": " << r.err;
    EXPECT_EQ(r.out, "") << bad;
    EXPECT_EQ(listing(ws.work), before) << bad;
  }
  const ToolRun r = run_tool(
      SWEEP_SIM_EXE,
      quoted(ws / "rig.json") + " -s " + quoted(ws / "scene.json") + " -o " + quoted(ws / "out.pc2") + " --joints 8",
      ws.io);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("--joints: skins a .glb output"), std::string::npos) << r.err;
  EXPECT_EQ(listing(ws.work), before);
  // The largest the tube allows is taken.
  const ToolRun ok = run_tool(SWEEP_SIM_EXE, base + " -q --joints 41", ws.io);
  EXPECT_EQ(ok.code, 0) << ok.err;
}

// --joints alone: the default stations and ring (bake_skin.h: kDefaultSkinJoints, kDefaultRingJoints),
// last or before another option (followed by the rig, it would take the rig's path for its number);
// the ring's joints carry the tube's squeeze better than
// one joint a station does.
TEST(Joints, JointsAloneTakesTheDefaultsWhichBeatSectionJoints) {
  const Workspace ws("joints-default");
  const std::string scene = " -s " + quoted(ws / "scene.json");
  for (const std::string& order :
       {quoted(ws / "rig.json") + scene + " --joints -o " + quoted(ws / "d.glb"),
        std::string("--joints -q ") + quoted(ws / "rig.json") + scene + " -o " + quoted(ws / "d.glb"),
        quoted(ws / "rig.json") + scene + " -o " + quoted(ws / "d.glb") + " --joints"}) {
    const ToolRun r = run_tool(SWEEP_SIM_EXE, order + " -q --report " + quoted(ws / "d.json"), ws.io);
    ASSERT_EQ(r.code, 0) << order << ": " << r.err;
    const nlohmann::json report = nlohmann::json::parse(slurp(ws / "d.json"));
    EXPECT_EQ(report["joints_per_sweep"], assets::kDefaultSkinJoints) << order;
    EXPECT_EQ(report["ring_joints"], assets::kDefaultRingJoints) << order;
    EXPECT_EQ(report["skin_joints"],
              1 + assets::kDefaultSkinJoints + (assets::kDefaultSkinJoints - 1) * assets::kDefaultRingJoints);
  }
  const ToolRun r =
      run_tool(SWEEP_SIM_EXE,
               quoted(ws / "rig.json") + scene + " -q -o " + quoted(ws / "s.glb") + " --joints " +
                   std::to_string(assets::kDefaultSkinJoints) + " --ring-joints 1 --report " + quoted(ws / "s.json"),
               ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  const double ring = nlohmann::json::parse(slurp(ws / "d.json"))["skin_error_max_relative"].get<double>();
  const double section = nlohmann::json::parse(slurp(ws / "s.json"))["skin_error_max_relative"].get<double>();
  EXPECT_LT(ring, section);
  const ToolRun help = run_tool(SWEEP_SIM_EXE, "--help", ws.io);
  EXPECT_NE(help.out.find("--ring-joints"), std::string::npos) << help.out;
}

// --joints alone on a sweep of fewer stations than the default (the tube's K = 6 at one station a
// span: 6) takes a joint a station, said in a note, where the same number given is refused
// (BadJointCounts).
TEST(Joints, JointsAloneOnAShortSweepTakesAJointAStation) {
  const Workspace ws("joints-short");
  const ToolRun r =
      run_tool(SWEEP_SIM_EXE,
               quoted(ws / "rig.json") + " -s " + quoted(ws / "scene.json") + " --stations 1 --joints -o " +
                   quoted(ws / "d.glb") + " --report " + quoted(ws / "d.json"),
               ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("note: --joints: 6 joints a sweep, not 24: sweep \"tube\" has 6 stations"), std::string::npos)
      << r.err;
  const nlohmann::json report = nlohmann::json::parse(slurp(ws / "d.json"));
  EXPECT_EQ(report["joints_per_sweep"], 6);
  EXPECT_EQ(report["skin_joints"], 1 + 6 + 5 * assets::kDefaultRingJoints);
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
