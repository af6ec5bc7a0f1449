// Sweeps of one rest shape and material share one chain model (a crowd of one creature reads one
// set of modes), and sharing changes nothing: the model is the one built for that part alone.
#include <gtest/gtest.h>

#include "beam_tubes.h"
#include "sweep/core/chain_model.h"
#include "sweep/core/elastic_sweep.h"

namespace sweep {
namespace {

TEST(SharedChain, SweepsOfOnePartShareTheModelItsOwnBuildWouldGive) {
  const SweepDef def = test::beam::tube(0.05, 0.05, 0.1);
  const ElasticSweep a(def), b(def);
  ASSERT_NE(a.chain(), nullptr);
  EXPECT_EQ(a.chain(), b.chain());
  // The shared model is, to the bit, what building it for this part gives.
  const ChainModel own = build_chain_model(def.rest, def.section_materials);
  EXPECT_EQ(a.chain()->modes, own.modes);
  EXPECT_EQ(a.chain()->omega2, own.omega2);
  EXPECT_EQ(a.chain()->mass, own.mass);
  EXPECT_EQ(a.chain()->damping_ratio, own.damping_ratio);

  // Another material, or another shape, is another model.
  SweepDef stiffer = def;
  test::beam::set_youngs_modulus(stiffer, 2 * def.material->youngs_modulus);
  const ElasticSweep c(stiffer);
  EXPECT_NE(c.chain(), a.chain());
  EXPECT_EQ(c.chain()->omega2, build_chain_model(stiffer.rest, stiffer.section_materials).omega2);
  SweepDef moved = def;
  moved.rest.frames.back().center.x() += 1e-9;
  const ElasticSweep d(moved);
  EXPECT_NE(d.chain(), a.chain());
}

TEST(SharedChain, SweepsOfOnePartStepToTheSameBitsAsOneAlone) {
  const SweepDef def = test::beam::tube(0.05, 0.05, 0.1);
  ElasticSweep alone(def);
  alone.set_gravity(Vec3(0, -9.81, 0), false);
  std::vector<double> tips;
  for (int k = 0; k < 30; ++k) {
    alone.step(1.0 / 60);
    tips.push_back(alone.deformed().frames.back().center.y());
  }
  // The same part again, sharing one model with the first and with a third sweep stepped in between.
  ElasticSweep shared(def), other(def);
  ASSERT_EQ(shared.chain(), other.chain());
  shared.set_gravity(Vec3(0, -9.81, 0), false);
  other.set_gravity(Vec3(0, 9.81, 0), false);
  for (int k = 0; k < 30; ++k) {
    other.step(1.0 / 60);
    shared.step(1.0 / 60);
    EXPECT_EQ(shared.deformed().frames.back().center.y(), tips[k]) << "step " << k;
  }
  EXPECT_LT(tips.back(), def.rest.frames.back().center.y());  // it sagged: the steps did something
}

}  // namespace
}  // namespace sweep
