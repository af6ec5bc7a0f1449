// sweep-fit with no --preset, --material or --springs: a part takes the preset its name chooses
// (a tail the tail's, a leg the fallback), says which and why, and sways at that preset's
// frequency; --springs keeps the paper's springs, byte for byte what a fit with a material
// written without its material is; a material file that gives no Young's modulus is solved for
// the tail preset's frequency, with a warning naming the sweep.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pipeline.h"
#include "sweep/core/chain_model.h"
#include "sweep/core/held_rest.h"
#include "sweep/core/presets.h"
#include "sweep/core/section_properties.h"
#include "sweep/core/sway.h"
#include "sweep/io/rig_json.h"

namespace sweep::test {
namespace {

// A straight tube of 1 m and 5 cm radius by sweep-tube, fine around (its sections near circles),
// fitted as `name` with `options` from just inside its capped root (every section the same); the run's result (the rig
// at ws / (name + ".rig.json")).
ToolRun fit_named_tube(const Workspace& ws, const std::string& name, const std::string& options) {
  const fs::path mesh = ws / "fine-tube.obj";
  if (!fs::exists(mesh)) {
    const ToolRun tube =
        run_tool(SWEEP_TUBE_EXE, "-q --length 1 --radius 0.05 --rings 21 --segments 32 -o " + quoted(mesh), ws.io);
    EXPECT_EQ(tube.code, 0) << tube.err;
  }
  return run_tool(SWEEP_FIT_EXE,
                  quoted(mesh) + " -o " + quoted(ws / (name + ".rig.json")) + " --name " + name +
                      " --root 0,0,0.02 --tip 0,0,1" + options,
                  ws.io);
}

// A small tube, 10 cm long and 5 mm round, by sweep-tube, fitted as `name` with `options` from just
// inside its root to its tip; the run's result (the rig at ws / (name + ".rig.json")).
ToolRun fit_small_tube(const Workspace& ws, const std::string& name, const std::string& options) {
  const fs::path mesh = ws / "small-tube.obj";
  if (!fs::exists(mesh)) {
    const ToolRun tube =
        run_tool(SWEEP_TUBE_EXE, "-q --length 0.1 --radius 0.005 --rings 21 --segments 32 -o " + quoted(mesh), ws.io);
    EXPECT_EQ(tube.code, 0) << tube.err;
  }
  return run_tool(SWEEP_FIT_EXE,
                  quoted(mesh) + " -o " + quoted(ws / (name + ".rig.json")) + " --name " + name +
                      " --root 0,0,0.002 --tip 0,0,0.1" + options,
                  ws.io);
}

// The first frequency of a clamped–free uniform beam, 1.875² / (2π L²) · √(EI / ρA), of the
// sweep's own length and sections (metres: the material's scale).
double cantilever_frequency_hz(const SweepDef& def) {
  constexpr double kBeta1 = 1.8751040687119611;
  const Material& m = *def.material;
  double ei_over_rho_a = 0;
  for (int i = 0; i < def.rest.section_count(); ++i) {
    const SectionProperties p = section_properties(def.rest.section_radii(i));  // mesh units
    const double s2 = m.metres_per_unit * m.metres_per_unit;
    ei_over_rho_a += m.youngs_modulus * p.i_xx * s2 / (m.density * p.area) / def.rest.section_count();
  }
  const double l = m.metres_per_unit * def.rest.length();
  return kBeta1 * kBeta1 / (2 * std::numbers::pi * l * l) * std::sqrt(ei_over_rho_a);
}

TEST(DefaultPreset, APartNamedTailSwaysAtTheTailPresetsFrequency) {
  const Workspace ws("default-preset-tail");
  const ToolRun r = fit_named_tube(ws, "tail", "");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("tail: preset tail (its name says tail;"), std::string::npos) << r.out;
  const Rig rig = io::read_rig(ws / "tail.rig.json");
  const SweepDef& def = rig.sweeps.at(0);
  ASSERT_TRUE(def.material.has_value());
  const Preset& tail = *find_preset("tail");
  EXPECT_EQ(def.material->density, tail.density);
  EXPECT_EQ(def.material->damping_ratio, tail.damping_ratio);
  const SwayFigures f = sway_figures(def, Vec3::Zero());
  ASSERT_FALSE(f.frequencies_hz.empty());
  EXPECT_NEAR(f.frequencies_hz[0], tail.frequency_hz, 1e-9 * tail.frequency_hz);
  // The modulus written is the beam's for 2 Hz: the closed form within the presets' 1 %.
  EXPECT_NEAR(cantilever_frequency_hz(def), tail.frequency_hz, 1e-2 * tail.frequency_hz);
}

TEST(DefaultPreset, ALegTakesTheFallbackAndSaysWhy) {
  const Workspace ws("default-preset-leg");
  const ToolRun r = fit_named_tube(ws, "leg_front2", "");
  ASSERT_EQ(r.code, 0) << r.err;
  const Preset& fallback = *find_preset(kFallbackPreset);
  EXPECT_NE(r.out.find("leg_front2: preset " + std::string(fallback.name) + " (no tail, neck, ear"), std::string::npos)
      << r.out;
  const Rig rig = io::read_rig(ws / "leg_front2.rig.json");
  const SweepDef& def = rig.sweeps.at(0);
  ASSERT_TRUE(def.material.has_value());
  EXPECT_EQ(def.material->density, fallback.density);
  const SwayFigures f = sway_figures(def, Vec3::Zero());
  ASSERT_FALSE(f.frequencies_hz.empty());
  EXPECT_NEAR(f.frequencies_hz[0], fallback.frequency_hz, 1e-9 * fallback.frequency_hz);
  // The words of a name, not its letters: "heart" and "Bear" hold no ear; "HairStrands" and
  // "TAILS" are a strand and a tail.
  EXPECT_EQ(preset_for_name("heart").preset, &fallback);
  EXPECT_EQ(preset_for_name("Bear").preset, &fallback);
  EXPECT_EQ(preset_for_name("HairStrands").preset, find_preset("strand"));
  EXPECT_EQ(preset_for_name("TAILS").preset, find_preset("tail"));
  EXPECT_EQ(preset_for_name("ear_2").preset, find_preset("ear"));
  EXPECT_EQ(preset_for_name("elephantTrunk").preset, find_preset("tentacle"));
}

// --springs writes what the fit wrote before parts took presets: the same sections with the
// paper's default springs and no material. Built apart: the tail fitted with a material, that
// material taken off and the rig formatted again.
TEST(DefaultPreset, SpringsKeepThePapersSpringsByteForByte) {
  const Workspace ws("default-preset-springs");
  const ToolRun springs = fit_named_tube(ws, "tail", " --springs");
  ASSERT_EQ(springs.code, 0) << springs.err;
  EXPECT_EQ(springs.out.find(": preset "), std::string::npos) << springs.out;
  fs::rename(ws / "tail.rig.json", ws / "springs.rig.json");
  ASSERT_EQ(fit_named_tube(ws, "tail", " --preset neck").code, 0);
  Rig rig = io::read_rig(ws / "tail.rig.json");
  SweepDef& def = rig.sweeps.at(0);
  ASSERT_TRUE(def.material.has_value());
  def.material.reset();
  def.section_materials.clear();
  EXPECT_EQ(def.default_springs, SectionSprings{});
  EXPECT_EQ(slurp(ws / "springs.rig.json"), io::format_rig(rig));
  const ToolRun both = fit_named_tube(ws, "both", " --springs --preset tail");
  EXPECT_EQ(both.code, 1);
  EXPECT_FALSE(fs::exists(ws / "both.rig.json"));
}

TEST(DefaultPreset, AMaterialWithoutYoungsModulusSwaysAtTheTailFrequencyAndWarns) {
  const Workspace ws("default-preset-no-e");
  spit(ws / "flesh.json", R"({"density_kg_m3": 1000, "damping_ratio": 0.05})");
  const ToolRun r = fit_named_tube(ws, "hose", " --material " + quoted(ws / "flesh.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("flesh.json gives no youngs_modulus_pa: sweep \"hose\" takes "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("sway at 2 Hz (the tail preset's frequency"), std::string::npos) << r.err;
  const Rig rig = io::read_rig(ws / "hose.rig.json");
  const SweepDef& def = rig.sweeps.at(0);
  ASSERT_TRUE(def.material.has_value());
  EXPECT_EQ(def.material->density, 1000);  // the file's members kept
  EXPECT_EQ(def.material->damping_ratio, 0.05);
  const SwayFigures f = sway_figures(def, Vec3::Zero());
  ASSERT_FALSE(f.frequencies_hz.empty());
  EXPECT_NEAR(f.frequencies_hz[0], default_frequency_hz(), 1e-9 * default_frequency_hz());
  EXPECT_NEAR(cantilever_frequency_hz(def), default_frequency_hz(), 1e-2 * default_frequency_hz());
}

// At a preset's frequency a small part is soft against its weight (its droop goes as g / (ω² L)):
// a tail 10 cm long and 5 mm round, level under the OBJ's +Y up, would take 0.7 of the stiffness
// it needs just to hold its modelled pose. sweep-fit stiffens it until it holds twice over (its
// load factor 0.5) and says so; a strand, which hangs, keeps its frequency's modulus.
TEST(DefaultPreset, ASmallPartIsStiffenedToHoldItsModelledPoseTwiceOverButAStrandIsNot) {
  const Workspace ws("default-preset-hold");
  const Vec3 gravity(0, -kStandardGravity, 0);
  for (const std::string name : {"tail", "strand"}) {
    const ToolRun r = fit_small_tube(ws, name, "");
    ASSERT_EQ(r.code, 0) << r.err;
    SweepDef def = io::read_rig(ws / (name + ".rig.json")).sweeps.at(0);
    ASSERT_TRUE(def.material.has_value());
    const double written = def.material->youngs_modulus;
    // The modulus of the preset's frequency alone, and the load factor it leaves.
    const Preset& preset = *find_preset(name);
    const double solved = with_frequency(def.rest, *def.material, preset.frequency_hz).youngs_modulus;
    for (Material& m : def.section_materials) m.youngs_modulus = solved;
    def.material->youngs_modulus = solved;
    const double given = held_rest(def, build_chain_model(def.rest, def.section_materials), gravity).load_factor;
    if (name == "strand") {
      EXPECT_GT(given, 1);  // it cannot hold its pose, and hangs
      EXPECT_NEAR(written, solved, 1e-9 * solved);
      EXPECT_EQ(r.out.find("stiffened"), std::string::npos) << r.out;
      continue;
    }
    ASSERT_GT(given, kPresetLoadFactor);
    EXPECT_NEAR(written / solved, given / kPresetLoadFactor, 1e-9 * given);
    EXPECT_NE(r.out.find(name + ": stiffened "), std::string::npos) << r.out;
    const Rig rig = io::read_rig(ws / (name + ".rig.json"));
    const SweepDef& fitted = rig.sweeps.at(0);
    EXPECT_NEAR(held_rest(fitted, build_chain_model(fitted.rest, fitted.section_materials), gravity).load_factor,
                kPresetLoadFactor, 1e-6);
  }
}

// sweep-sim warns on stderr of a part that cannot hold its modelled pose under the scene's gravity
// (the 10 cm strand above: its frequency's modulus is too weak), naming it and saying what the bake
// does with it for each "gravity_start"; a part that holds (the stiffened tail) gets no warning, and
// "unloaded", which asks for no such pose, none.
TEST(DefaultPreset, AStrandThatCannotHoldItsPoseIsWarnedOfAsTheBakeStarts) {
  const Workspace ws("default-preset-warn");
  for (const std::string name : {"tail", "strand"}) {
    const fs::path rig = ws / (name + ".rig.json");
    ASSERT_EQ(fit_small_tube(ws, name, " -q").code, 0);
    ASSERT_EQ(run_tool(SWEEP_BIND_EXE, quoted(rig) + " -q", ws.io).code, 0);
    for (const std::string start : {"auto", "as-modelled", "unloaded"}) {
      spit(ws / "scene.json", R"({"format": "sweep-scene", "version": 1, "duration": 0.1, "fps": 10, "forces": [],
        "gravity": [0, -9.81, 0], "gravity_start": ")" +
                                  start + R"("})");
      const ToolRun r = run_tool(
          SWEEP_SIM_EXE, quoted(rig) + " -s " + quoted(ws / "scene.json") + " -o " + quoted(ws / "out.pc2"), ws.io);
      ASSERT_EQ(r.code, 0) << r.err;
      const std::size_t at = r.err.find("part \"" + name + "\" cannot hold its modelled pose under gravity (β = ");
      if (name == "tail" || start == "unloaded") {
        EXPECT_EQ(at, std::string::npos) << name << ", " << start << ": " << r.err;
        continue;
      }
      ASSERT_NE(at, std::string::npos) << name << ", " << start << ": " << r.err;
      EXPECT_NE(r.err.find(start == "auto" ? "it starts unloaded and droops from the modelled pose instead"
                                           : "it starts from that pose, as \"gravity_start\": \"as-modelled\" asks",
                           at),
                std::string::npos)
          << r.err;
    }
  }
}

}  // namespace
}  // namespace sweep::test
