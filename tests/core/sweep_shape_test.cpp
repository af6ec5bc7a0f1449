// Rest: with no force, every evaluation reproduces the key sections exactly.
#include <gtest/gtest.h>

#include <numbers>

#include "core/elastic_sweep.h"
#include "core/locate.h"
#include "core/sweep_shape.h"
#include "sample_sweeps.h"

namespace sweep {
namespace {

using test::irregular_shape;
using test::straight_shape;

TEST(SweepShape, KeySectionsAreReproducedExactly) {
  const SweepShape s = irregular_shape(7, 8);
  ASSERT_EQ(check_shape(s), "");
  for (int i = 0; i < s.section_count(); ++i) {
    const Frame f = frame_at(s, s.t[i]);
    EXPECT_EQ(f.center, s.frames[i].center) << "section " << i;
    EXPECT_EQ(f.rotation.coeffs(), s.frames[i].rotation.coeffs()) << "section " << i;
    for (int j = 0; j < s.radial_count; ++j) {
      EXPECT_DOUBLE_EQ(radius_at(s, s.sample_angle(j), s.t[i]), s.radius_sample(i, j))
          << "section " << i << " sample " << j;
      // S(θ_j, t_i) lies on the sample: c_i + R_i (r cos θ_j, r sin θ_j, 0).
      const double th = s.sample_angle(j), r = s.radius_sample(i, j);
      const Vec3 expected = s.frames[i].to_world(Vec3(r * std::cos(th), r * std::sin(th), 0));
      EXPECT_LT((surface_point(s, th, s.t[i]) - expected).norm(), 1e-15) << i << "," << j;
    }
  }
}

TEST(SweepShape, DeformedStateAtRestEqualsTheRestShape) {
  ElasticSweep sweep(test::sweep_def(irregular_shape(6, 5)));
  for (int i = 0; i < 6; ++i) {
    EXPECT_LT((sweep.deformed().frames[i].center - sweep.rest().frames[i].center).norm(), 1e-14);
    EXPECT_LT(sweep.deformed().frames[i].rotation.angularDistance(sweep.rest().frames[i].rotation), 1e-14);
  }
  EXPECT_EQ(sweep.deformed().radii, sweep.rest().radii);
}

TEST(SweepShape, StraightTubeIsACylinder) {
  const SweepShape s = straight_shape(5, 6, 0.5);
  for (double t : {0.0, 0.3, 1.5, 2.99, 4.0}) {
    for (double th : {0.0, 0.4, 2.0, 5.9}) {
      const Vec3 p = surface_point(s, th, t);
      EXPECT_NEAR(p.z(), t, 1e-15);
      EXPECT_NEAR(std::hypot(p.x(), p.y()), 0.5, 1e-15);
    }
  }
}

TEST(SweepShape, CentreCurveHasTheSectionAxisAsTangent) {
  const SweepShape s = irregular_shape(6, 4);
  const double h = 1e-6;
  for (int i = 1; i + 1 < s.section_count(); ++i) {
    const Vec3 d = (center_at(s, s.t[i] + h) - center_at(s, s.t[i] - h)) / (2 * h);
    // The Hermite tangent at a key section is its axis (times the unit-speed factor 1).
    EXPECT_LT((d - s.frames[i].axis()).norm(), 1e-5) << "section " << i;
  }
}

TEST(SweepShape, RadiusNeverGoesBelowTheFloor) {
  SweepShape s = straight_shape(4, 6, 1.0);
  // One tiny sample between large ones makes the cubic overshoot below zero without the floor.
  s.radii[1 * 6 + 2] = 1e-3;
  double lowest = 1e9;
  for (double t = 0; t <= 3; t += 0.01) {
    for (double th = 0; th < 2 * std::numbers::pi; th += 0.01) lowest = std::min(lowest, radius_at(s, th, t));
  }
  EXPECT_GE(lowest, kMinRadiusFraction * 1e-3);
}

TEST(SweepShape, FramesStayOrthonormalBetweenSections) {
  const SweepShape s = irregular_shape(6, 4);
  for (double t = 0; t <= s.length(); t += s.length() / 97) {
    const Mat3 r = rotation_at(s, t).toRotationMatrix();
    EXPECT_LT((r.transpose() * r - Mat3::Identity()).norm(), 1e-14);
  }
}

TEST(SweepShape, CheckShapeNamesWhatIsWrong) {
  SweepShape s = straight_shape(3, 4);
  s.t[2] = 1.0;
  EXPECT_NE(check_shape(s).find("section 2"), std::string::npos);
  s = straight_shape(3, 4);
  s.radii[5] = -1;
  EXPECT_NE(check_shape(s).find("section 1, radius 1"), std::string::npos);
  s = straight_shape(3, 2);
  EXPECT_NE(check_shape(s).find("at least 3"), std::string::npos);
}

TEST(Locate, RestPointsRoundTrip) {
  const SweepShape s = irregular_shape(8, 7);
  const SweepLocator locator(s);
  int checked = 0;
  for (double t = 0.05; t < s.length(); t += 0.37) {
    for (double th = 0.1; th < 6.2; th += 0.9) {
      for (double scale : {0.3, 1.0}) {
        const Frame f = frame_at(s, t);
        const double r = scale * radius_at(s, th, t);
        const Vec3 v = f.to_world(Vec3(r * std::cos(th), r * std::sin(th), 0));
        const SweepCoords c = locator.locate(v);
        EXPECT_LT((deform_point(s, c) - v).norm(), 1e-10 * s.length()) << "t " << t << " θ " << th;
        EXPECT_NEAR(c.s, scale, 1e-9);
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(Locate, CapPointsGetAnAxialOffset) {
  const SweepShape s = straight_shape(3, 4, 0.5);
  const SweepLocator locator(s);
  const SweepCoords beyond = locator.locate(Vec3(0.1, 0.0, 2.3));
  EXPECT_DOUBLE_EQ(beyond.t, 2.0);
  EXPECT_NEAR(beyond.z, 0.3, 1e-15);
  const SweepCoords behind = locator.locate(Vec3(0.0, 0.2, -0.4));
  EXPECT_DOUBLE_EQ(behind.t, 0.0);
  EXPECT_NEAR(behind.z, -0.4, 1e-15);
  EXPECT_LT((deform_point(s, beyond) - Vec3(0.1, 0.0, 2.3)).norm(), 1e-15);
}

}  // namespace
}  // namespace sweep
