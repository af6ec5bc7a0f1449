// find_parts on shapes whose parts are known: a body with one tube (one part, ending where the
// tube does, starting where it leaves the body), a lone tube (the whole mesh), and flat pieces
// (no part: rings that enclose nothing are no tube).
#include <gtest/gtest.h>

#include "core/topology.h"
#include "curve_tubes.h"
#include "fit/discover.h"

namespace sweep::test {
namespace {

constexpr double kR = 0.1;

TEST(Discover, ABodyWithOneTubeHasOnePartEndingWhereTheTubeEnds) {
  // A body 4r wide over 10r, then a straight tube of 12r along +Z.
  const double body_length = 10 * kR, tube_length = 12 * kR;
  CurveTube t;
  t.curve = [=](double u) { return Vec3(0, 0, u * (body_length + tube_length)); };
  t.radius = with_body(4 * kR, body_length, [](double) { return kR; });
  const Mesh mesh = t.mesh();
  const std::vector<fit::FoundPart> parts = fit::find_parts(mesh, build_topology(mesh));
  ASSERT_EQ(parts.size(), 1u);
  const fit::FoundPart& p = parts[0];
  EXPECT_NEAR(p.tip.z(), body_length + tube_length + kR, 0.2 * kR) << "the tip is the cap's end";
  EXPECT_NEAR(p.root.z(), body_length, 2 * kR) << "the root is where the tube leaves the body";
  EXPECT_NEAR(p.mean_radius, kR, 0.05 * kR);
}

TEST(Discover, ALoneTubeIsOnePart) {
  CurveTube t;
  t.curve = [](double u) { return Vec3(0, 0, 2 * u); };
  t.radius = [](double) { return kR; };
  const Mesh mesh = t.mesh();
  const std::vector<fit::FoundPart> parts = fit::find_parts(mesh, build_topology(mesh));
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_NEAR(parts[0].mean_radius, kR, 0.05 * kR);
  EXPECT_GT(parts[0].length, 1.5);
}

TEST(Discover, FlatPiecesHaveNoParts) {
  Mesh triangle;
  triangle.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  triangle.add_face({0, 1, 2});
  EXPECT_TRUE(fit::find_parts(triangle, build_topology(triangle)).empty());
  // A long strip of quads: long and thin, but flat.
  Mesh strip;
  for (int i = 0; i <= 40; ++i) {
    strip.positions.push_back(Vec3(0.1 * i, 0, 0));
    strip.positions.push_back(Vec3(0.1 * i, 0.1, 0));
  }
  for (std::uint32_t i = 0; i < 40; ++i) strip.add_face({2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1});
  EXPECT_TRUE(fit::find_parts(strip, build_topology(strip)).empty());
}

}  // namespace
}  // namespace sweep::test
