// The parts sweep-fit --list offers and --all fits (find_fitting_parts): legs ending in feet that
// reach both ways from the ankle (make_legs_with_feet) are each offered once, from the toes, rooted
// at the hips, and every part offered fits with no problem; a part the refuse hook turns down is
// passed over with its reason, and the names count only the parts offered; a part tiny against the
// figure (a walker's short horns) is passed over as small; a person's legs, whose thighs widen into
// the hips without a jump in the rings' size, are each offered once and fit.
#include "sweep/fit/offered_parts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <utility>

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

// make_walker(2, false) with six short horns along its back: closed tubes of radius 0.01, each a
// separate shell standing 0.1 up from inside the body (0.04 to 0.06 of them out of it): about 4 %
// of the walker's bounding-box diagonal of 3.2 (caps included), against legs of about 1.6.
Mesh walker_with_horns(const Walker& w) {
  Mesh m = w.mesh;
  for (const double x : {-0.3, 0.0, 0.3}) {
    for (const double z : {-0.1, 0.1}) {
      CurveTube horn;
      const Vec3 from(x, 1.03, z), to(x, 1.13, z);
      horn.curve = [=](double u) { return Vec3(from + u * (to - from)); };
      horn.radius = [](double) { return 0.01; };
      horn.samples = 100;
      horn.segments = 12;
      horn.ring_spacing = 0.004;
      horn.resample();
      append(m, horn.mesh());
    }
  }
  return m;
}

TEST(OfferedParts, PartsTinyAgainstTheFigureAreNotOfferedButPassedOverWithTheirReason) {
  const Walker w = make_walker(2, false);
  const Mesh m = walker_with_horns(w);
  const fit::SweepFitter fitter(m);
  std::vector<std::string> passed;
  const fit::OfferedParts offered = fit::find_fitting_parts(m, fitter, {}, {}, &passed);
  std::vector<std::string> names;
  for (const fit::FoundPart& p : offered.parts) {
    names.push_back(p.name);
    EXPECT_LT(p.tip.y(), 0.5) << p.name << ": a leg, its tip at a foot";
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"leg1", "leg2", "leg3", "leg4"}));
  // Each horn passed over as small (from its tip, or from both ends), and nothing else.
  std::set<std::pair<double, double>> small_horns;
  for (const std::string& x : passed) {
    if (x.find(": small, ") == std::string::npos) continue;
    Vec3 at;
    ASSERT_EQ(std::sscanf(x.c_str() + x.find(" at "), " at %lf,%lf,%lf", &at.x(), &at.y(), &at.z()), 3) << x;
    EXPECT_GT(at.y(), 0.98) << x << ": on a horn";
    small_horns.emplace(std::round(10 * at.x()), std::round(10 * at.z()));
  }
  EXPECT_EQ(small_horns.size(), 6u) << ::testing::PrintToString(passed);
  // The horns are tubes the search finds and fits: only their size keeps them out.
  fit::DiscoverOptions any_size;
  any_size.min_length_share = 0;
  EXPECT_EQ(fit::find_fitting_parts(m, fitter, any_size, {}).parts.size(), 10u);
}

// A person's thighs widen slowly into the hips (make_standing_hips): the rings from a foot grow by
// under 0.4 of their distance there, never jumping, and then split round the other leg and the
// torso; before, they ran on through the whole figure to its far side (one "leg" rooted at the
// chest, fitted as a bent tube). Where that first jump would leave the part holding the body, the
// widening into the split is where the leg meets it — for the search and for the fit from the toes.
TEST(OfferedParts, ThighsThatWidenGentlyIntoTheHipsAreTwoLegsFromTheToesThatFit) {
  const StandingHips s = make_standing_hips();
  const fit::SweepFitter fitter(s.mesh);
  const fit::OfferedParts offered = fit::find_fitting_parts(s.mesh, fitter, {}, {});
  ASSERT_EQ(offered.fits.size(), offered.parts.size());
  std::set<std::size_t> legs;
  for (std::size_t i = 0; i < offered.parts.size(); ++i) {
    const fit::FoundPart& p = offered.parts[i];
    const std::size_t leg = p.tip.z() < 0 ? 0 : 1;
    legs.insert(leg);
    EXPECT_EQ(p.name.substr(0, 3), "leg") << p.name;
    EXPECT_LT((p.tip - s.toes[leg]).norm(), 0.08) << p.name << ": the tip is at the toes";
    EXPECT_NEAR(p.root.y(), StandingHips::kPartY, 0.1) << p.name << ": rooted where the legs part, below the pelvis";
    EXPECT_NEAR(p.root.z(), s.toes[leg].z(), 0.03) << p.name << ": on its own leg's axis";
    EXPECT_TRUE(offered.fits[i].problems.empty()) << p.name << ": " << offered.fits[i].problems.front();
    EXPECT_TRUE(offered.fits[i].root_found) << p.name;
    EXPECT_LT((offered.fits[i].root - p.root).norm(), 0.03) << p.name << ": the fit's root is where the search's is";
  }
  EXPECT_EQ(offered.parts.size(), 2u) << "one part per leg";
  EXPECT_EQ(legs.size(), 2u) << "each leg once";
}

}  // namespace
}  // namespace sweep::test
