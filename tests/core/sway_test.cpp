// A part's sway figures (core/sway.h) against beam theory, and the presets (core/presets.h): each
// gives the frequency its table says, a droop that follows from it, and the same motion at any scale.
#include "sweep/core/sway.h"

#include <gtest/gtest.h>

#include <cmath>

#include "beam_tubes.h"
#include "sweep/core/presets.h"

namespace sweep {
namespace {

using namespace test::beam;

constexpr double kGravity = 9.81;
// β₁ L of a clamped–free beam's first mode, to more digits than the beam table needs.
constexpr double kBeta1 = 1.8751040687119611;

TEST(Sway, StiffTubeSwaysAtTheCantileversFirstFrequency) {
  // 1.875² / (2π L²) · √(EI / ρA). The chain's is a discretisation of it, O(h²) in the span: at
  // K = 32 within 0.5 % (+0.18 %), and twice the sections take a quarter of the error off.
  const SweepDef def = tube(kRadius, kRadius, 0.05);
  const SectionProperties p = props_of(def);
  const double l = length_m(def);
  const double closed = kBeta1 * kBeta1 / (2 * kPi * l * l) * std::sqrt(kYoung * p.i_xx / (kDensity * p.area));
  const SwayFigures f = sway_figures(def, Vec3(0, -kGravity, 0));
  ASSERT_EQ(f.frequencies_hz.size(), 2u);  // a round tube: one in each plane, the same
  EXPECT_NEAR(f.frequencies_hz[0], closed, 5e-3 * closed);
  EXPECT_NEAR(f.frequencies_hz[1], f.frequencies_hz[0], 1e-9 * closed);
  const SwayFigures finer = sway_figures(tube(kRadius, kRadius, 0.05, 2 * kSections - 1), Vec3(0, -kGravity, 0));
  EXPECT_LT(std::abs(finer.frequencies_hz[0] - closed), 0.3 * std::abs(f.frequencies_hz[0] - closed));
  EXPECT_TRUE(f.feels_gravity);
}

TEST(Sway, DroopIsTheCantileversUnderItsOwnWeight) {
  // δ = q L⁴ / (8 EI), q = ρ A g: within 1 % at K = 32, and the same as the settled simulation.
  const SweepDef def = tube(kRadius, kRadius, 1.0);
  const SectionProperties p = props_of(def);
  const double l = length_m(def);
  const double closed = kDensity * p.area * kGravity * std::pow(l, 4) / (8 * kYoung * p.i_xx) / l;
  const SwayFigures f = sway_figures(def, Vec3(0, -kGravity, 0));
  EXPECT_NEAR(f.droop, closed, 1e-2 * closed);
  // Gravity along the tube bends nothing.
  EXPECT_NEAR(sway_figures(def, Vec3(0, 0, -kGravity)).droop, 0, 1e-12);
}

TEST(Sway, PaperSpringsSwayAtTheirBendFrequencyAndDoNotDroop) {
  SweepDef def = tube(kRadius, kRadius, 0.05);
  def.material.reset();
  def.section_materials.clear();
  def.springs[5].bend.frequency_hz = 0.7;
  const SwayFigures f = sway_figures(def, Vec3(0, -kGravity, 0));
  ASSERT_EQ(f.frequencies_hz.size(), 1u);
  EXPECT_EQ(f.frequencies_hz[0], 0.7);
  EXPECT_EQ(f.droop, 0);
  EXPECT_FALSE(f.feels_gravity);
}

TEST(Preset, EachSwaysAtItsFrequencyAndDroopsAsTheCantileverSaysAtAnyScale) {
  // The droop of a cantilever swaying at ω₁: δ/L = β₁⁴ g / (8 ω₁² L) (both from EI/ρA).
  for (const Preset& preset : presets()) {
    for (const double scale : {0.01, 0.1, 1.0}) {
      const SweepDef shape = tube(kRadius, kRadius, 0.05, 16);
      SweepDef def = shape;
      def.material = preset_material(shape.rest, preset, scale);
      def.section_materials.assign(16, *def.material);
      EXPECT_EQ(def.material->density, preset.density);
      EXPECT_EQ(def.material->damping_ratio, preset.damping_ratio);
      const SwayFigures f = sway_figures(def, Vec3(0, -kGravity, 0));
      ASSERT_FALSE(f.frequencies_hz.empty());
      EXPECT_NEAR(f.frequencies_hz[0], preset.frequency_hz, 1e-9 * preset.frequency_hz) << preset.name;
      const double w = 2 * kPi * preset.frequency_hz, l = scale * shape.rest.length();
      const double closed = std::pow(kBeta1, 4) * kGravity / (8 * w * w * l);
      EXPECT_NEAR(f.droop, closed, 1e-2 * closed) << preset.name << " at " << scale << " m/unit";
    }
  }
  EXPECT_EQ(find_preset("tail")->frequency_hz, 2.0);
  EXPECT_EQ(find_preset("wing"), nullptr);
}

TEST(Preset, SameMotionInAngleAndTimeAt1x10x100x) {
  // One bent tube at 1×, 10× and 100× its size, a preset's material, the body shaken and turned
  // by a motion scaled with it (no gravity: a fixed g is a physical size). Every section's
  // rotation from its rest, against time, is the same within 1e-6 rad.
  for (const bool exact : {false, true}) {  // the rest-pose modes, and the geometrically exact chain
    std::vector<std::vector<double>> angles;
    for (const double size : {1.0, 10.0, 100.0}) {
      SweepDef def = tube(size * kRadius, size * kRadius, 0.05, 12);
      // Round exactly at every size (section_properties takes J = I_p only for equal radii, and the
      // ellipse's formula rounds a circle's radii differently at different sizes).
      for (double& r : def.rest.radii) r = size * kRadius;
      for (int i = 0; i < 12; ++i) {
        // A gentle curve in x, scaled with the rest.
        const double t = def.rest.t[i] * size;
        def.rest.t[i] = t;
        def.rest.frames[i].center = Vec3(0.02 * t * t / size, 0, t);
      }
      def.material = preset_material(def.rest, *find_preset("tail"), 0.1);
      def.section_materials.assign(12, *def.material);
      ElasticSweep sweep(def);
      sweep.set_exact_chain(exact);
      std::vector<double> a;
      for (int step = 0; step < 60; ++step) {
        const double time = step / 60.0;
        ElasticSweep::BodyMotion motion;
        motion.acceleration = size * Vec3(40 * std::sin(9 * time), 0, 5);
        motion.angular_velocity = Vec3(0, 2 * std::sin(5 * time), 0);
        motion.angular_acceleration = Vec3(0, 10 * std::cos(5 * time), 0);
        sweep.set_body_motion(motion);
        sweep.step(1.0 / 60);
        for (int i = 1; i < 12; ++i) {
          a.push_back(sweep.deformed().frames[i].rotation.angularDistance(def.rest.frames[i].rotation));
        }
      }
      angles.push_back(a);
    }
    double largest = 0;
    for (double x : angles[0]) largest = std::max(largest, x);
    EXPECT_GT(largest, 0.05);  // it moved
    for (std::size_t m = 0; m < angles[0].size(); ++m) {
      EXPECT_NEAR(angles[1][m], angles[0][m], 1e-6);
      EXPECT_NEAR(angles[2][m], angles[0][m], 1e-6);
    }
  }
}

}  // namespace
}  // namespace sweep
