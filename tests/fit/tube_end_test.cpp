// find_tube_end (fit/tube_end.h) on measured distances made up span by span: where the run of
// spans off the tube begins, and when the end is not cut at all.
#include "sweep/fit/tube_end.h"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "core/sample_sweeps.h"

namespace sweep::fit {
namespace {

// A straight sweep of 11 sections one unit apart, radius 1 (sections a radius apart), and one
// measured vertex a tenth of the way into each span at each of ten places: `off(span)` the
// distance of that span's vertices.
template <class Off>
std::vector<std::pair<double, double>> measured(Off off, int spans = 10) {
  std::vector<std::pair<double, double>> along;
  for (int span = 0; span < spans; ++span) {
    for (int i = 0; i < 10; ++i) along.emplace_back(span + 0.05 + 0.1 * i, off(span));
  }
  return along;
}

constexpr double kLimit = 0.1;  // the error limit: a span is off the tube past half of it

TEST(TubeEnd, TheRunOfSpansOffTheTubeAtTheTipEndEndsTheSweep) {
  const SweepShape shape = test::straight_shape(11, 8, 1.0);
  const auto along = measured([](int span) { return span >= 8 ? 0.2 : 0.01; });
  const std::optional<TubeEnd> end = find_tube_end(shape, along, kLimit, 1.0);
  ASSERT_TRUE(end.has_value());
  EXPECT_EQ(end->first_section, 8);
  EXPECT_DOUBLE_EQ(end->t, 8.0);
  EXPECT_DOUBLE_EQ(end->share, 0.2);
  EXPECT_EQ(end->end_count, 20u);
  EXPECT_DOUBLE_EQ(end->end_rms, 0.2);
  EXPECT_DOUBLE_EQ(end->before_rms, 0.01);
}

TEST(TubeEnd, OneSpanWithinTheRunDoesNotStopIt) {
  // A toe's gap: span 8 fits, 7 and 9 do not.
  const SweepShape shape = test::straight_shape(11, 8, 1.0);
  const auto along = measured([](int span) { return span == 7 || span == 9 ? 0.2 : 0.01; });
  const std::optional<TubeEnd> end = find_tube_end(shape, along, kLimit, 1.0);
  ASSERT_TRUE(end.has_value());
  EXPECT_EQ(end->first_section, 7);
}

TEST(TubeEnd, TheRunGoesOnOverSpansWithNoVertexButNotOverMoreThanTwoRadiiOfTube) {
  const SweepShape shape = test::straight_shape(11, 8, 1.0);
  // Spans 7 and 9 off, span 8 with no vertex measured (dense sections on a coarse mesh): one run.
  std::vector<std::pair<double, double>> along;
  for (const auto& [t, d] : measured([](int span) { return span == 7 || span == 9 ? 0.2 : 0.01; })) {
    if (t < 8 || t >= 9) along.emplace_back(t, d);
  }
  const std::optional<TubeEnd> end = find_tube_end(shape, along, kLimit, 1.0);
  ASSERT_TRUE(end.has_value());
  EXPECT_EQ(end->first_section, 7);
  // On 15 spans, 11 and 14 off, 12 and 13 fit (two radii of tube): still one run.
  const std::optional<TubeEnd> gap2 =
      find_tube_end(test::straight_shape(16, 8, 1.0),
                    measured([](int span) { return span == 11 || span == 14 ? 0.2 : 0.01; }, 15), kLimit, 1.0);
  ASSERT_TRUE(gap2.has_value());
  EXPECT_EQ(gap2->first_section, 11);
  // Spans 5 (a little: within the limit) and 9 off, 6 to 8 fit (three radii of tube): the run is
  // span 9 alone.
  const std::optional<TubeEnd> tip_only =
      find_tube_end(shape, measured([](int span) { return span == 9   ? 0.2
                                                          : span == 5 ? 0.08
                                                                      : 0.01; }), kLimit, 1.0);
  ASSERT_TRUE(tip_only.has_value());
  EXPECT_EQ(tip_only->first_section, 9);
  // The last three spans fit: no run begins at the tip end, whatever is off before them.
  EXPECT_FALSE(find_tube_end(shape, measured([](int span) { return span == 6 ? 0.2 : 0.01; }), kLimit, 1.0));
}

TEST(TubeEnd, NoCutForATubeALongRunOrSectionsFarApart) {
  const SweepShape shape = test::straight_shape(11, 8, 1.0);
  // Every span on the tube: nothing to cut.
  EXPECT_FALSE(find_tube_end(shape, measured([](int) { return 0.01; }), kLimit, 1.0).has_value());
  // Off over the last half: more than a third of the length is not an end, it is a bad fit.
  EXPECT_FALSE(find_tube_end(shape, measured([](int span) { return span >= 5 ? 0.2 : 0.01; }), kLimit, 1.0));
  // The same end, the sections 2.5 radii apart: a span's error may be the spacing's.
  EXPECT_FALSE(find_tube_end(shape, measured([](int span) { return span >= 8 ? 0.2 : 0.01; }), kLimit, 0.4));
  // The vertices before the end off by more than the limit at the 90th percentile.
  EXPECT_FALSE(find_tube_end(shape, measured([](int span) { return span >= 8 ? 0.3 : 0.12; }), kLimit, 1.0));
}

}  // namespace
}  // namespace sweep::fit
