// FoldMeter (core/fold_check.h): a span's bend, a fold past 90°, discs that cross.
#include "sweep/core/fold_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sample_sweeps.h"
#include "test_constants.h"

namespace sweep {
namespace {

using ::sweep::test::kPi;

// A straight tube of 12 sections one unit apart, radius 0.5, bent at section `at` by `angle` about
// x: every section from there on turned rigidly about that section's centre.
SweepShape bent(double angle, int at = 5) {
  SweepShape s = test::straight_shape(12, 8, 0.5);
  for (int i = 0; i < 12; ++i) {
    s.t[i] = i;
    s.frames[i].center = Vec3(0, 0, i);
  }
  const Quat turn(Eigen::AngleAxisd(angle, Vec3::UnitX()));
  const Vec3 pivot = s.frames[at].center;
  for (int i = at; i < 12; ++i) {
    s.frames[i].center = pivot + turn * (s.frames[i].center - pivot);
    s.frames[i].rotation = turn * s.frames[i].rotation;
  }
  return s;
}

TEST(FoldMeter, ABendIsMeasuredOnItsSpanAndAFoldPast90DegreesIsFound) {
  const SweepShape rest = bent(0);
  FoldMeter quiet(rest);
  quiet.measure(bent(0.3), 4);
  EXPECT_NEAR(quiet.largest_bend, 0.3, 1e-12);
  EXPECT_EQ(quiet.bend_span, 5);
  EXPECT_EQ(quiet.bend_frame, 4);
  EXPECT_EQ(quiet.fold_frame, -1);
  EXPECT_EQ(quiet.cross_frame, -1);  // 0.3 rad over unit spans of radius 0.5: no pinch

  FoldMeter folded(rest);
  folded.measure(bent(0.3), 0);
  folded.measure(bent(1.9), 7);
  folded.measure(bent(1.7), 8);
  EXPECT_NEAR(folded.largest_bend, 1.9, 1e-12);
  EXPECT_EQ(folded.bend_frame, 7);
  EXPECT_EQ(folded.fold_frame, 7);
  EXPECT_EQ(folded.fold_span, 5);
  // Turned 1.9 rad about section 5's centre, section 6's disc (1 unit out, radius 0.5) passes
  // below section 4's edge: folded, not yet through itself. At 2.8 rad it cuts section 4's disc
  // (in the bend's plane its edge runs from (0.14, −1.11) to (−0.81, −0.78) about the pivot,
  // crossing section 4's plane z = −1 at y = −0.17, inside its radius).
  EXPECT_EQ(folded.cross_frame, -1);
  folded.measure(bent(2.8), 9);
  EXPECT_EQ(folded.cross_frame, 9);
  // (Sections 3 and 7 meet too, and come first in the search; only pairs folded about section 5
  // can meet.)
  EXPECT_EQ(folded.cross_a + folded.cross_b, 10);
  EXPECT_LT(folded.cross_a, 5);
  EXPECT_EQ(folded.fold_frame, 7);  // the first fold stays the one named
}

TEST(FoldMeter, ARestThatIsAlreadyBentIsNotAFold) {
  // The bend is measured from the rest: a rest bent 100° that does not move bends 0.
  const SweepShape rest = bent(1.75);
  FoldMeter m(rest);
  m.measure(rest, 0);
  EXPECT_NEAR(m.largest_bend, 0, 1e-12);
  EXPECT_EQ(m.fold_frame, -1);
  EXPECT_EQ(m.cross_frame, -1);  // discs that crossed at rest are not news
}

TEST(FoldMeter, DiscsCrossWhereTheirChordsOnTheCommonLineOverlap) {
  const Vec3 z = Vec3::UnitZ(), x = Vec3::UnitX();
  // Perpendicular discs through each other's centres.
  EXPECT_TRUE(discs_cross(Vec3::Zero(), z, 1, Vec3::Zero(), x, 1));
  // Perpendicular, the second beside the first: its plane cuts the first, its chord misses.
  EXPECT_FALSE(discs_cross(Vec3::Zero(), z, 1, Vec3(0, 2.5, 0), x, 1));
  EXPECT_TRUE(discs_cross(Vec3::Zero(), z, 1, Vec3(0, 1.5, 0), x, 1));
  // Parallel, apart: never; one plane, overlapping: yes.
  EXPECT_FALSE(discs_cross(Vec3::Zero(), z, 1, Vec3(0, 0, 0.1), z, 1));
  EXPECT_TRUE(discs_cross(Vec3::Zero(), z, 1, Vec3(1.5, 0, 0), z, 1));
  // The second disc's plane cuts the first's, but the second disc lies wholly above it.
  EXPECT_FALSE(discs_cross(Vec3::Zero(), z, 1, Vec3(0, 0, 1.2), x, 1));
}

}  // namespace
}  // namespace sweep
