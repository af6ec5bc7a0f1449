// The parts sweep-fit --list offers and --all fits (find_fitting_parts): legs ending in feet that
// reach both ways from the ankle (make_legs_with_feet) are each offered once, from the toes, rooted
// at the hips, and every part offered fits with no problem; a part the refuse hook turns down is
// passed over with its reason, and the names count only the parts offered.
#include "sweep/fit/offered_parts.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "fit/creatures.h"
#include "sweep/core/topology.h"
#include "sweep/fit/discover.h"
#include "sweep/fit/fit.h"

namespace sweep::test {
namespace {

TEST(OfferedParts, LegsWithFeetAreEachOfferedOnceFromTheToesAndEveryPartOfferedFits) {
  const LegsWithFeet l = make_legs_with_feet(0.12, 0.45);
  const fit::SweepFitter fitter(l.mesh);
  const fit::OfferedParts offered = fit::find_fitting_parts(l.mesh, fitter, {}, {});
  ASSERT_EQ(offered.parts.size(), 2u) << "one part per leg";
  ASSERT_EQ(offered.fits.size(), 2u);
  std::vector<bool> seen(2, false);
  for (std::size_t i = 0; i < 2; ++i) {
    const fit::FoundPart& p = offered.parts[i];
    const std::size_t leg = p.tip.z() < 0 ? 0 : 1;
    EXPECT_FALSE(seen[leg]) << p.name << ": the same leg twice";
    seen[leg] = true;
    EXPECT_LT((p.tip - l.toes[leg]).norm(), 2 * LegsWithFeet::kFootR) << p.name << ": the tip is at the toes";
    EXPECT_GT(p.root.y(), 0.75 * LegsWithFeet::kHipY) << p.name << ": the root is up at the hips, body -> foot";
    EXPECT_TRUE(offered.fits[i].problems.empty()) << p.name << ": " << offered.fits[i].problems.front();
    EXPECT_EQ(offered.fits[i].sweep.name, p.name);
    EXPECT_EQ(offered.fits[i].tip_vertex, p.tip_vertex);
  }
}

TEST(OfferedParts, APartTheRefuseHookTurnsDownIsPassedOverWithItsReasonAndNotNamed) {
  const Walker w = make_walker(2, false);
  fit::DiscoverOptions o;
  o.refuse = [](const fit::FoundPart& p) { return p.tip.z() > 0 ? std::string("on the left") : std::string(); };
  std::vector<std::string> passed;
  const std::vector<fit::FoundPart> parts = fit::find_parts(w.mesh, build_topology(w.mesh), o, &passed);
  ASSERT_EQ(parts.size(), 2u) << "the two legs on the right only";
  std::vector<std::string> names;
  for (const fit::FoundPart& p : parts) {
    EXPECT_LT(p.tip.z(), 0) << p.name;
    names.push_back(p.name);
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"leg1", "leg2"})) << "numbered over the parts offered";
  EXPECT_EQ(
      std::count_if(passed.begin(), passed.end(), [](const std::string& x) { return x.ends_with(": on the left"); }),
      2);
}

}  // namespace
}  // namespace sweep::test
