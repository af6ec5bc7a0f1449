// sweep-fit adds a sweep to a rig by reading it, fitting and writing it back. Two runs updating one
// rig at once used to both read the rig before either wrote it, and the second to write dropped
// the first's sweep, both exiting 0. They take turns now (a lock beside the rig): every sweep is
// kept, whatever the interleaving, and the lock file goes with the run.
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "pipeline.h"

namespace sweep::test {
namespace {

std::vector<std::string> sweep_names(const fs::path& rig) {
  std::vector<std::string> names;
  const nlohmann::json doc = nlohmann::json::parse(slurp(rig));
  for (const auto& s : doc["sweeps"]) names.push_back(s["name"]);
  std::sort(names.begin(), names.end());
  return names;
}

TEST(RigUpdate, TwoFitsIntoOneRigAtOnceKeepBothSweeps) {
  const Workspace ws("rig-update-concurrent");
  const std::set<std::string> before = listing(ws.work);
  auto fit = [&](const std::string& name) {
    return "'" + std::string(SWEEP_FIT_EXE) + "' " + quoted(ws / "tube.obj") + " -o " + quoted(ws / "rig.json") +
           " --name " + name + " --root 0,0,0.02 --tip 0,0,1 -k 6 -n 8 -q >" + quoted(ws.io / (name + ".out")) + " 2>" +
           quoted(ws.io / (name + ".err"));
  };
  for (int trial = 0; trial < 3; ++trial) {
    const std::string a = "a" + std::to_string(trial), b = "b" + std::to_string(trial);
    // Both started together by one shell: their reads of the rig overlap unless they take turns.
    const std::string both = "(" + fit(a) + "; echo $? >" + quoted(ws.io / "a.code") + ") & (" + fit(b) +
                             "; echo $? >" + quoted(ws.io / "b.code") + ") & wait";
    ASSERT_EQ(std::system(both.c_str()), 0);
    EXPECT_EQ(slurp(ws.io / "a.code"), "0\n") << slurp(ws.io / (a + ".err"));
    EXPECT_EQ(slurp(ws.io / "b.code"), "0\n") << slurp(ws.io / (b + ".err"));
  }
  EXPECT_EQ(sweep_names(ws / "rig.json"), (std::vector<std::string>{"a0", "a1", "a2", "b0", "b1", "b2", "tube"}));
  EXPECT_EQ(listing(ws.work), before) << "no lock file or temporary left";
}

}  // namespace
}  // namespace sweep::test
