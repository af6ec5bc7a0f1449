// Rest: with no force, every evaluation reproduces the key sections exactly.
#include "sweep/core/sweep_shape.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "sample_sweeps.h"
#include "sweep/core/deform_point.h"
#include "sweep/core/elastic_sweep.h"
#include "sweep/core/locate.h"

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

// The interpolants the exact path and the fast path's station table share (core/sweep_shape.h).
Quat random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Quat q;
  q.coeffs() = Eigen::Vector4d(normal(rng), normal(rng), normal(rng), normal(rng)).normalized();
  return q;
}

// Pairs of rotations far apart, on both sides of the hypersphere (a negative dot product: the
// shorter arc flips one), equal, opposite and nearly equal (Eigen's linear case).
std::vector<std::pair<Quat, Quat>> rotation_pairs(std::mt19937& rng) {
  std::vector<std::pair<Quat, Quat>> pairs;
  for (int i = 0; i < 100; ++i) {
    const Quat a = random_rotation(rng), b = random_rotation(rng);
    Quat nudged, opposite;
    nudged.coeffs() = (a.coeffs() + 1e-10 * b.coeffs()).normalized();
    opposite.coeffs() = -a.coeffs();
    for (const Quat& c : {b, a, opposite, nudged}) pairs.emplace_back(a, c);
  }
  return pairs;
}

TEST(Interpolants, SlerpIsEigensSlerpBitForBit) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const auto& [a, b] : rotation_pairs(rng)) {
    const Slerp arc(a, b);
    for (double u : {0.0, 0.125, 0.25, 1.0 / 3.0, 0.5, 0.875, 1.0, unit(rng), unit(rng)}) {
      EXPECT_EQ(arc.at(u).coeffs(), a.slerp(u, b).coeffs()) << "u " << u;
    }
  }
}

TEST(Interpolants, SlerpStepsFollowTheArc) {
  std::mt19937 rng(20);
  for (const auto& [a, b] : rotation_pairs(rng)) {
    const Slerp arc(a, b);
    const bool linear = std::abs(a.dot(b)) >= 1.0 - Eigen::NumTraits<double>::epsilon();
    for (int steps : {1, 2, 7, 8, 16}) {
      std::vector<Quat> out(steps + 1);
      arc.at_steps(out);
      for (int q = 0; q <= steps; ++q) {
        const Quat exact = arc.at(static_cast<double>(q) / steps);
        // The recurrence's sines differ from sin() in the last bits; the linear case is the same.
        if (linear) {
          EXPECT_EQ(out[q].coeffs(), exact.coeffs()) << "step " << q << " of " << steps;
        } else {
          EXPECT_LT((out[q].coeffs() - exact.coeffs()).norm(), 1e-14) << "step " << q << " of " << steps;
        }
      }
    }
  }
}

TEST(Interpolants, CatmullRomFormsAreOneCubicThroughTheSamples) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> radius(0.5, 2.0), unit(0.0, 1.0);
  std::vector<double> samples(7);
  for (double& r : samples) r = radius(rng);
  const int n = static_cast<int>(samples.size());
  for (int j = 0; j < n; ++j) {
    const CatmullRomCell cell(samples, j);
    EXPECT_EQ(cell.at(0.0), samples[j]);  // through the samples
    EXPECT_NEAR(cell.at(1.0), samples[(j + 1) % n], 1e-15);
    const auto [c0, c1, c2, c3] = cell.cubic();
    for (double w : {0.0, 0.25, 0.5, 0.75, 1.0, unit(rng), unit(rng)}) {
      EXPECT_NEAR(c0 + w * (c1 + w * (c2 + w * c3)), cell.at(w), 1e-14) << "cell " << j << " w " << w;
    }
  }
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
