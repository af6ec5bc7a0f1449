// find_parts on shapes whose parts are known: a body with one tube (one part, ending where the
// tube does, starting where it leaves the body), a lone tube (the whole mesh), and flat pieces
// (no part: rings that enclose nothing are no tube).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

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

// The mesh without the triangles `drop` selects (by their centroid): holes punched in it.
Mesh without(const Mesh& mesh, const std::function<bool(const Vec3&)>& drop) {
  Mesh out;
  out.positions = mesh.positions;
  const std::vector<std::uint32_t> tris = mesh.triangles();
  for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
    const Vec3 c = (mesh.positions[tris[t]] + mesh.positions[tris[t + 1]] +
                    mesh.positions[tris[t + 2]]) / 3;
    if (!drop(c)) out.add_face({tris[t], tris[t + 1], tris[t + 2]});
  }
  return out;
}

TEST(Discover, AHoleInTheBodyLeavesTheTubeAsItWas) {
  const double body_length = 10 * kR, tube_length = 12 * kR;
  CurveTube t;
  t.curve = [=](double u) { return Vec3(0, 0, u * (body_length + tube_length)); };
  t.radius = with_body(4 * kR, body_length, [](double) { return kR; });
  const Mesh whole = t.mesh();
  // A hole 2r across in the body's side, away from the tube.
  const Mesh holed = without(whole, [&](const Vec3& c) {
    return c.x() > 0 && std::abs(c.y()) < kR && std::abs(c.z() - 0.4 * body_length) < kR;
  });
  ASSERT_LT(holed.face_count(), whole.face_count());
  ASSERT_GT(hole_edge_count(build_topology(holed)), 0u);
  EXPECT_EQ(hole_edge_count(build_topology(whole)), 0u);
  const std::vector<fit::FoundPart> before = fit::find_parts(whole, build_topology(whole));
  const std::vector<fit::FoundPart> after = fit::find_parts(holed, build_topology(holed));
  ASSERT_EQ(before.size(), 1u);
  ASSERT_EQ(after.size(), 1u);
  EXPECT_EQ(after[0].tip_vertex, before[0].tip_vertex);
  EXPECT_NEAR(after[0].mean_radius, kR, 0.05 * kR);
  EXPECT_NEAR(after[0].root.z(), before[0].root.z(), kR);
}

TEST(Discover, AnOpenSheetCutFromATubeHasNoParts) {
  // A tube 20 radii long cut open along its length and its end cut off: a trough, long and thin
  // like a tube, but rings of surface distance from any point of it run into its rims. (Such
  // rings, measured anyway, gave parts a vertex or two long and a hundredth of a radius wide on
  // open meshes: mech-holes-shark, holes, blobby_3cc.)
  CurveTube t;
  t.curve = [](double u) { return Vec3(0, 0, 20 * kR * u); };
  t.radius = [](double) { return kR; };
  const Mesh tube = t.mesh();
  const Mesh trough = without(tube, [](const Vec3& c) { return c.y() > 0.3 * kR || c.z() < 0; });
  ASSERT_GT(hole_edge_count(build_topology(trough)), 0u);
  EXPECT_TRUE(fit::find_parts(trough, build_topology(trough)).empty());
}

}  // namespace
}  // namespace sweep::test
