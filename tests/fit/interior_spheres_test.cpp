// Spheres filling a closed mesh (fit/interior_spheres.h), on a box whose distances are known:
// each sphere inside and no larger than its centre's distance to the faces, the room callback kept,
// and the box covered.
#include "sweep/fit/interior_spheres.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "sweep/fit/surface_distance.h"

namespace sweep::fit {
namespace {

// The box [0, 2] × [0, 1] × [0, 1] as 12 outward triangles.
struct Box {
  std::vector<Vec3> points;
  std::vector<std::uint32_t> triangles;
};
Box box() {
  Box b;
  for (int k = 0; k < 8; ++k) b.points.emplace_back(2.0 * (k & 1), (k >> 1) & 1, (k >> 2) & 1);
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) b.triangles.insert(b.triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  return b;
}

double distance_to_box(const Vec3& p) {
  return std::min({p.x(), 2 - p.x(), p.y(), 1 - p.y(), p.z(), 1 - p.z()});
}

const auto kNoRoomLimit = [](const Vec3&) { return std::numeric_limits<double>::infinity(); };

TEST(InteriorSpheres, LieInsideTheBoxLargestFirstAndCoverIt) {
  const Box b = box();
  InteriorSpheresOptions o;
  o.max_spheres = 16;
  o.cells = 20;
  const InteriorSpheres s = fit_interior_spheres(b.points, b.triangles, o, kNoRoomLimit);
  ASSERT_FALSE(s.spheres.empty());
  EXPECT_LE(s.spheres.size(), 16u);
  EXPECT_NEAR(s.spheres[0].radius, 0.45, 1e-9);  // the grid's cell centres nearest the box's middle
  const TriangleDistance surface(b.points, b.triangles);
  for (std::size_t k = 0; k < s.spheres.size(); ++k) {
    const Sphere& x = s.spheres[k];
    EXPECT_TRUE(surface.inside(x.centre)) << k;
    EXPECT_LE(x.radius, distance_to_box(x.centre) + 1e-12) << k;
    if (k > 0) {
      EXPECT_LE(x.radius, s.spheres[k - 1].radius) << k;
    }
  }
  EXPECT_EQ(s.points, 20u * 10 * 10);  // every cell centre of the box is inside it
  EXPECT_GE(s.covered, 0.9 * s.points);
  EXPECT_FALSE(surface.inside(Vec3(2.5, 0.5, 0.5)));
  EXPECT_FALSE(surface.inside(Vec3(1, 0.5, -0.01)));
}

TEST(InteriorSpheres, KeepTheirRoomAndLeaveOutPointsWithNone) {
  // The room: the distance to the plane x = 1.3 (a part's surface); nothing past it is to be
  // covered.
  const Box b = box();
  const auto room = [](const Vec3& p) { return 1.3 - p.x(); };
  InteriorSpheresOptions o;
  o.cells = 20;
  const InteriorSpheres s = fit_interior_spheres(b.points, b.triangles, o, room);
  ASSERT_FALSE(s.spheres.empty());
  for (const Sphere& x : s.spheres) EXPECT_LE(x.centre.x() + x.radius, 1.3 + 1e-12);
  EXPECT_EQ(s.points, 13u * 10 * 10);  // cell centres 0.05, 0.15, …, 1.25
  // Deterministic: the same spheres, bit for bit.
  const InteriorSpheres again = fit_interior_spheres(b.points, b.triangles, o, room);
  ASSERT_EQ(again.spheres.size(), s.spheres.size());
  for (std::size_t k = 0; k < s.spheres.size(); ++k) {
    EXPECT_EQ(again.spheres[k].centre, s.spheres[k].centre);
    EXPECT_EQ(again.spheres[k].radius, s.spheres[k].radius);
  }
}

}  // namespace
}  // namespace sweep::fit
