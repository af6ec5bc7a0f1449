// find_parts on parts that are separate shells around a body (make_walker: legs as closed tubes
// with ball feet, an abdomen as a second body shell): each leg is found once, from its foot, with
// its root at the hip; the abdomen is no part; names follow the up axis given.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "fit/creatures.h"
#include "sweep/core/topology.h"
#include "sweep/fit/discover.h"

namespace sweep::test {
namespace {

// The leg whose foot (tip) lies nearest to p, and how far.
std::size_t nearest_leg(const std::vector<Vec3>& ends, const Vec3& p, double& distance) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < ends.size(); ++i)
    if ((ends[i] - p).norm() < (ends[best] - p).norm()) best = i;
  distance = (ends[best] - p).norm();
  return best;
}

void expect_each_leg_once_from_its_foot(const Walker& w, const std::vector<fit::FoundPart>& parts) {
  ASSERT_EQ(parts.size(), w.feet.size()) << "one part per leg, nothing for the body shells";
  std::set<std::size_t> legs;
  for (const fit::FoundPart& p : parts) {
    double tip_off = 0, root_off = 0;
    const std::size_t leg = nearest_leg(w.feet, p.tip, tip_off);
    const std::size_t hip = nearest_leg(w.hips, p.root, root_off);
    EXPECT_LT(tip_off, 2 * Walker::kFootRadius) << p.name << ": the tip is at a foot";
    EXPECT_EQ(hip, leg) << p.name << ": the root is at the same leg's hip";
    EXPECT_LT(root_off, 3 * Walker::kLegRadius) << p.name << ": the root is at the hip end";
    legs.insert(leg);
  }
  EXPECT_EQ(legs.size(), w.feet.size()) << "every leg exactly once";
}

TEST(DiscoverShells, SeparateLegShellsAreEachOnePartOrientedFromTheBodyToTheFoot) {
  const Walker w = make_walker(3, true);
  std::vector<std::string> passed;
  const std::vector<fit::FoundPart> parts = fit::find_parts(w.mesh, build_topology(w.mesh), {}, &passed);
  // The body and the abdomen, each traced from both ends, are passed over as the body's core.
  EXPECT_EQ(std::count_if(passed.begin(), passed.end(),
                          [](const std::string& x) { return x.find("the body's core") != std::string::npos; }),
            4);
  expect_each_leg_once_from_its_foot(w, parts);
  for (const fit::FoundPart& p : parts) EXPECT_EQ(p.name.substr(0, 3), "leg") << p.name;
}

TEST(DiscoverShells, AZUpWalkerIsNamedByTheUpAxisGiven) {
  // The Y-up walker turned so that its up is +Z (x, y, z) → (x, −z, y).
  Eigen::Matrix3d to_z_up;
  to_z_up << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  const Walker w = make_walker(2, false, to_z_up);
  fit::DiscoverOptions o;
  o.up = Vec3::UnitZ();
  const std::vector<fit::FoundPart> parts = fit::find_parts(w.mesh, build_topology(w.mesh), o);
  expect_each_leg_once_from_its_foot(w, parts);
  std::set<std::string> names;
  for (const fit::FoundPart& p : parts) names.insert(p.name);
  EXPECT_EQ(names, (std::set<std::string>{"leg1", "leg2", "leg3", "leg4"}));
  // With +Y (the default) the same legs point sideways and up: not four legs.
  names.clear();
  for (const fit::FoundPart& p : fit::find_parts(w.mesh, build_topology(w.mesh))) names.insert(p.name);
  EXPECT_NE(names, (std::set<std::string>{"leg1", "leg2", "leg3", "leg4"}));
}

// A T-posed figure's arms are arms, whatever hangs past their ends: its gloves made the body that
// names are judged by wider than tall (a lying body, its side parts along it "tails"), but what
// lies past a part's end is the part's, not the body's.
TEST(DiscoverShells, AFigureInATPoseHasArmsWhateverHangsPastTheirEnds) {
  const TPosedFigure f = make_t_posed_figure();
  std::set<std::string> arms;
  for (const fit::FoundPart& p : fit::find_parts(f.mesh, build_topology(f.mesh))) {
    // (The fists, balls, are offered too, traced across: not what this test is about.)
    if (std::abs(std::abs(p.tip.x()) - (TPosedFigure::kWrist + TPosedFigure::kArmRadius)) > 0.05) continue;
    EXPECT_NEAR(std::abs(p.root.x()), 0.15, 0.1) << p.name << ": from the shoulder";
    arms.insert(p.name);
  }
  EXPECT_EQ(arms, (std::set<std::string>{"arm1", "arm2"}));
}

// A stocky figure, wider than tall, is not upright by its proportions, and its arms, hanging out to
// the sides along its widest direction, read as tails, its horns as necks; each pair is the other's
// mirror image, and a body has one tail: the pairs are named arms and horns.
TEST(DiscoverShells, MirroredPairsOnAStockyFigureAreArmsAndHorns) {
  const StockyFigure f = make_stocky_figure();
  std::map<std::string, std::string> named;  // the end nearest each part's tip → its name
  for (const fit::FoundPart& p : fit::find_parts(f.mesh, build_topology(f.mesh))) {
    for (const auto& [ends, what] : {std::pair(&f.hands, "hand"), std::pair(&f.horn_tips, "horn tip")}) {
      for (std::size_t k = 0; k < ends->size(); ++k)
        if ((p.tip - (*ends)[k]).norm() < 0.06) named[what + std::to_string(k)] = p.name;
    }
  }
  // (Which of a pair is 1 and which 2 follows the search's order.)
  const std::set<std::string> arms{named["hand0"], named["hand1"]}, horns{named["horn tip0"], named["horn tip1"]};
  EXPECT_EQ(arms, (std::set<std::string>{"arm1", "arm2"}));
  EXPECT_EQ(horns, (std::set<std::string>{"horn1", "horn2"}));
}

}  // namespace
}  // namespace sweep::test
