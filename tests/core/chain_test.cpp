// Chain: turning X_j turns every later section rigidly about c'_j and leaves earlier ones alone.
#include <gtest/gtest.h>

#include "sample_sweeps.h"
#include "sweep/core/elastic_sweep.h"

namespace sweep {
namespace {

TEST(Chain, TurningOneSectionTurnsEveryLaterSectionRigidlyAboutItsCentre) {
  const int k = 7, j = 3;
  ElasticSweep sweep(test::sweep_def(test::irregular_shape(k, 5)));
  const Vec3 phi(0.3, -0.2, 0.5);  // in section j's own axes
  sweep.set_section_pose(j, Vec3::Zero(), phi);
  const SweepShape& rest = sweep.rest();
  const SweepShape& def = sweep.deformed();

  // The rigid motion: rotate about c_j by the world rotation G = R_j exp(φ) R_jᵀ.
  const Quat g = rest.frames[j].rotation * rotation_from_vector(phi) * rest.frames[j].rotation.conjugate();
  const Vec3 cj = rest.frames[j].center;
  for (int i = 0; i < k; ++i) {
    Vec3 c = rest.frames[i].center;
    Quat q = rest.frames[i].rotation;
    if (i >= j) {
      c = g * (c - cj) + cj;
      q = g * q;
    }
    EXPECT_LT((def.frames[i].center - c).norm(), 1e-14) << "section " << i;
    EXPECT_LT(def.frames[i].rotation.angularDistance(q), 1e-14) << "section " << i;
  }
  // Radii are untouched by rotation.
  EXPECT_EQ(def.radii, rest.radii);
}

TEST(Chain, ShiftingOneSectionCarriesEveryLaterSection) {
  const int k = 5, j = 2;
  ElasticSweep sweep(test::sweep_def(test::irregular_shape(k, 4)));
  const Vec3 x(0.1, 0.2, -0.05);  // section j's own axes
  sweep.set_section_pose(j, x, Vec3::Zero());
  const Vec3 shift = sweep.rest().frames[j].rotation * x;
  for (int i = 0; i < k; ++i) {
    const Vec3 expected = sweep.rest().frames[i].center + (i >= j ? shift : Vec3::Zero());
    EXPECT_LT((sweep.deformed().frames[i].center - expected).norm(), 1e-14) << "section " << i;
  }
}

TEST(Chain, RadialOffsetChangesOnlyItsHandle) {
  ElasticSweep sweep(test::sweep_def(test::straight_shape(4, 6, 0.5)));
  sweep.set_radial_offset(2, 3, 0.2);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 6; ++j) {
      const double expected = (i == 2 && j == 3) ? 0.7 : 0.5;
      EXPECT_DOUBLE_EQ(sweep.deformed().radius_sample(i, j), expected);
    }
  }
  // A handle can never invert its section: the radius is floored.
  sweep.set_radial_offset(2, 3, -5.0);
  EXPECT_DOUBLE_EQ(sweep.deformed().radius_sample(2, 3), kMinRadiusFraction * 0.5);
}

}  // namespace
}  // namespace sweep
