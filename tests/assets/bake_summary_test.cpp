// What sweep-sim tells of a part whose as-modelled rest does not hold under gravity
// (core/held_rest.h): a line in the summary and the check in the report's sweep entry.
#include "sweep/assets/bake_summary.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

namespace sweep::assets {
namespace {

TEST(BakeSummary, APartThatCannotHoldItsModelledPoseIsNamedInTheSummaryAndTheReport) {
  BakeReport report;
  report.frames = 31;
  report.fps = 30;
  report.step_seconds = 1.0 / 480;
  for (const char* name : {"soft", "stiff", "unchecked"}) report.sweeps.emplace_back().name = name;
  report.sweeps[0].held_rest = HeldRest{.load_factor = 6.2, .lowest = -4520, .growth_rate = 62.2, .beta = 68.4};
  report.sweeps[1].held_rest = HeldRest{.load_factor = 0.12, .lowest = 30, .growth_rate = 0, .beta = 1.4};
  report.sweeps[1].as_modelled = true;
  std::ostringstream summary;
  print_bake_summary(summary, report, {});
  const std::string text = summary.str();
  EXPECT_NE(text.find("cannot hold its modelled pose under gravity (beta 68.4, stiffness 6.2x too low): started "
                      "unloaded"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("cannot hold", text.find("stiff ")), std::string::npos) << text;  // the one that holds
  const nlohmann::json doc = nlohmann::json::parse(bake_report_json(report, {}));
  const nlohmann::json& soft = doc["sweeps"][0]["as_modelled_rest"];
  EXPECT_EQ(soft["holds"], false);
  EXPECT_EQ(soft["load_factor"], 6.2);
  EXPECT_EQ(soft["beta"], 68.4);
  EXPECT_EQ(soft["growth_rate"], 62.2);
  EXPECT_EQ(soft["started_from_it"], false);
  EXPECT_EQ(doc["sweeps"][1]["as_modelled_rest"]["holds"], true);
  EXPECT_EQ(doc["sweeps"][1]["as_modelled_rest"]["started_from_it"], true);
  EXPECT_TRUE(doc["sweeps"][2]["as_modelled_rest"].is_null());
}

}  // namespace
}  // namespace sweep::assets
