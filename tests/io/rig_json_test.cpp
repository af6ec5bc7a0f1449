// The rig file: round trip, and every kind of bad input answered with the JSON pointer.
#include "sweep/io/rig_json.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "fp_guard.h"
#include "sweep/core/error.h"
#include "sweep/core/presets.h"
#include "sweep/core/sway.h"
#include "sweep/core/text.h"
#include "sweep/io/atomic_file.h"
#include "sweep/io/mesh_names.h"

namespace sweep::io {
namespace {

// A two-section rig with every optional member used.
Rig small_rig() {
  SweepShape s;
  s.radial_count = 3;
  s.t = {0.0, 1.5};
  s.frames = {{Quat::Identity(), Vec3(0, 0, 0)},
              {Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized())), Vec3(0.1, 0.2, 1.5)}};
  s.radii = {0.5, 0.6, 0.7, 0.4, 0.45, 0.5};
  SweepDef def = make_sweep("tail", s);
  def.section_names = {"root", ""};
  def.springs[1].bend.frequency_hz = 4.25;
  def.rotational_scale = 0.75;
  def.part = PartSeeds{Vec3(0, 0, -0.1), Vec3(0, 0, 1.6)};
  Rig rig;
  rig.mesh = "../meshes/tube.obj";
  rig.sweeps.push_back(def);
  return rig;
}

TEST(RigJson, RoundTripKeepsEveryBit) {
  const Rig rig = small_rig();
  const std::string text = format_rig(rig);
  const Rig back = parse_rig(text, "mem.json");
  ASSERT_EQ(back.sweeps.size(), 1u);
  const SweepDef& a = rig.sweeps[0];
  const SweepDef& b = back.sweeps[0];
  EXPECT_EQ(back.mesh, rig.mesh);
  EXPECT_EQ(b.name, a.name);
  EXPECT_EQ(b.rest.t, a.rest.t);
  EXPECT_EQ(b.rest.radii, a.rest.radii);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(b.rest.frames[i].center, a.rest.frames[i].center);
    EXPECT_EQ(b.rest.frames[i].rotation.coeffs(), a.rest.frames[i].rotation.coeffs());
    EXPECT_EQ(b.springs[i], a.springs[i]);
  }
  EXPECT_EQ(b.section_names, a.section_names);
  EXPECT_EQ(b.rotational_scale, 0.75);
  ASSERT_TRUE(b.part.has_value());
  EXPECT_EQ(b.part->tip, a.part->tip);
  EXPECT_EQ(format_rig(back), text);  // byte-identical when written again
}

TEST(RigJson, MaterialsAndTheirPerSectionOverridesRoundTrip) {
  Rig rig = small_rig();
  SweepDef& def = rig.sweeps[0];
  Material m;
  m.youngs_modulus = 3.5e6;
  m.shear_modulus = 1.1e6;
  m.density = 1060;
  m.metres_per_unit = 0.013;
  m.damping_ratio = 0.07;
  def.material = m;
  def.section_materials.assign(2, m);
  def.section_materials[1].youngs_modulus = 2.25e5;  // a softer tip
  // whose shear modulus follows from the (default) Poisson ratio instead of the sweep's G
  def.section_materials[1].shear_modulus = 0;
  const std::string text = format_rig(rig);
  const Rig back = parse_rig(text, "mem.json");
  const SweepDef& b = back.sweeps[0];
  ASSERT_TRUE(b.material.has_value());
  EXPECT_EQ(*b.material, m);
  EXPECT_EQ(b.section_materials, def.section_materials);
  EXPECT_EQ(format_rig(back), text);
  // Only what a section changes is written for it.
  const auto doc = nlohmann::json::parse(text);
  EXPECT_FALSE(doc["sweeps"][0]["sections"][0].contains("material"));
  EXPECT_EQ(doc["sweeps"][0]["sections"][1]["material"].size(), 2u);
}

// Each constant finite and in range, yet G = E / (2 (1 + ν)) = 1e308 / 2e-7 overflows: refused with
// the place (found by the material fuzz target: tests/fuzz/regressions/material/). The same
// material a little less extreme, G = 1e300 / 2e-7 = 5e306, is accepted with that G.
TEST(RigJson, AMaterialWhoseShearModulusOverflowsIsRefused) {
  try {
    parse_material(R"({"youngs_modulus_pa": 1e308, "poisson_ratio": -0.9999999})", "m.json");
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::bad_input);
    EXPECT_NE(std::string(e.what()).find("m.json: (document): its shear modulus E / (2 (1 + poisson_ratio)) is not "
                                         "finite (E 1e+308, poisson_ratio -0.9999999)"),
              std::string::npos)
        << e.what();
  }
  const Material ok = parse_material(R"({"youngs_modulus_pa": 1e300, "poisson_ratio": -0.9999999})", "m.json");
  EXPECT_DOUBLE_EQ(ok.shear(), 1e300 / (2 * (1 - 0.9999999)));
}

// Parses `text`, expects a bad-input error whose message contains `expected`.
void expect_bad(const std::string& text, const std::string& expected,
                ErrorCategory category = ErrorCategory::bad_input) {
  try {
    parse_rig(text, "rig.json");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), category) << e.what();
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << "message: " << e.what();
  }
}

// The small rig's text with one JSON-pointer location replaced.
std::string with(const std::string& pointer, const nlohmann::json& value) {
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(format_rig(small_rig()));
  doc[nlohmann::ordered_json::json_pointer(pointer)] = value;
  return doc.dump();
}

TEST(RigJson, MalformedJsonNamesLineAndColumn) {
  expect_bad("{\n  \"format\": \"sweep-rig\",\n  \"version\": 1,,\n}", "rig.json:3:");
  expect_bad("", "rig.json:1:1: empty file");
}

TEST(RigJson, WrongValuesNameTheirPointer) {
  expect_bad(with("/sweeps/0/sections/1/radii/2", -1),
             "rig.json: /sweeps/0/sections/1/radii/2: must be a positive number, got -1");
  expect_bad(with("/sweeps/0/sections/1/radii/0", "wide"),
             "/sweeps/0/sections/1/radii/0: must be a number, got \"wide\"");
  expect_bad(with("/sweeps/0/radial_samples", 2), "/sweeps/0/radial_samples: must be between 3");
  expect_bad(with("/sweeps/0/sections/1/t", 0.0), "/sweeps/0/sections/1/t: must be greater than the previous");
  expect_bad(with("/sweeps/0/sections/0/t", 0.5), "/sweeps/0/sections/0/t: the first section's t must be 0");
  expect_bad(with("/sweeps/0/sections/1/rotation", nlohmann::json::array({0, 0, 0, 2})),
             "/sweeps/0/sections/1/rotation: must be a unit quaternion");
  expect_bad(with("/sweeps/0/sections/1/center", nlohmann::json::array({0, 0})),
             "/sweeps/0/sections/1/center: must be an array of 3 numbers");
  expect_bad(with("/sweeps/0/springs/bend/mass", -2), "/sweeps/0/springs/bend/mass: must be a positive number, got -2");
  expect_bad(with("/sweeps/0/springs/radial/damping_ratio", -0.1),
             "/sweeps/0/springs/radial/damping_ratio: must not be negative");
  expect_bad(with("/sweeps/0/sections/1/springs/twist/frequency_hz", 0),
             "/sweeps/0/sections/1/springs/twist/frequency_hz: must be a positive number");
  expect_bad(with("/sweeps/0/sections/1/radii", nlohmann::json::array({1, 2})),
             "/sweeps/0/sections/1/radii: expected 3 radii");
  expect_bad(with("/format", "other"), "/format: must be \"sweep-rig\"");
  expect_bad(with("/version", 7), "/version: rig format version 7 is not supported", ErrorCategory::unsupported);
  expect_bad(with("/sweeps", nlohmann::json::object()), "/sweeps: must be an array, got an object");
}

// A sweep's "preset": its members, E solved on the sweep's own sections for the preset's first
// sway frequency, the members given beside it (and a section's own E) over it.
TEST(RigJson, APresetIsSolvedOnThePartAndExplicitMembersOverrideIt) {
  const Preset& tail = *find_preset("tail");
  const SweepShape rest = small_rig().sweeps[0].rest;
  const Rig plain = parse_rig(with("/sweeps/0/material", {{"preset", "tail"}, {"metres_per_unit", 0.02}}), "rig.json");
  const SweepDef& def = plain.sweeps[0];
  ASSERT_TRUE(def.material.has_value());
  EXPECT_EQ(def.material->density, tail.density);
  EXPECT_EQ(def.material->damping_ratio, tail.damping_ratio);
  EXPECT_EQ(def.material->metres_per_unit, 0.02);
  EXPECT_EQ(*def.material, preset_material(rest, tail, 0.02));
  EXPECT_EQ(def.section_materials, std::vector<Material>(2, *def.material));
  EXPECT_NEAR(sway_figures(def, Vec3::Zero()).frequencies_hz.at(0), tail.frequency_hz, 1e-9);

  // A density given: E solved with it (same frequency); E given: nothing solved.
  nlohmann::ordered_json doc =
      nlohmann::ordered_json::parse(with("/sweeps/0/material", {{"preset", "tail"}, {"density_kg_m3", 500}}));
  doc["sweeps"][0]["sections"][1]["material"] = {{"youngs_modulus_pa", 7e5}};
  const Rig dense = parse_rig(doc.dump(), "rig.json");
  EXPECT_EQ(dense.sweeps[0].material->density, 500);
  EXPECT_EQ(dense.sweeps[0].section_materials[0].youngs_modulus, dense.sweeps[0].material->youngs_modulus);
  EXPECT_EQ(dense.sweeps[0].section_materials[1].youngs_modulus, 7e5);  // the section's own
  const Rig given = parse_rig(with("/sweeps/0/material", {{"preset", "ear"}, {"youngs_modulus_pa", 3e6}}), "rig.json");
  EXPECT_EQ(given.sweeps[0].material->youngs_modulus, 3e6);
  EXPECT_EQ(given.sweeps[0].material->density, find_preset("ear")->density);

  expect_bad(with("/sweeps/0/material", {{"preset", "wing"}}),
             "/sweeps/0/material/preset: unknown preset \"wing\": one of tail, neck, ear, tentacle, strand");
  nlohmann::ordered_json section = nlohmann::ordered_json::parse(with("/sweeps/0/material", {{"preset", "tail"}}));
  section["sweeps"][0]["sections"][1]["material"] = {{"preset", "ear"}};
  // A section takes the sweep's preset, never its own: that member is unknown there (a warning).
  std::vector<std::string> warnings;
  parse_rig(section.dump(), "rig.json", [&](const std::string& w) { warnings.push_back(w); });
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("/sweeps/0/sections/1/material/preset: unknown member \"preset\" ignored"),
            std::string::npos)
      << warnings[0];
}

// A sweep's material that gives no Young's modulus: the one that makes the part sway at the tail
// preset's frequency, solved on its sections with the members given, and a warning naming the
// sweep and the modulus taken; a section that gives its own keeps it.
TEST(RigJson, AMaterialWithoutYoungsModulusSwaysAtTheTailFrequencyAndWarns) {
  nlohmann::ordered_json doc =
      nlohmann::ordered_json::parse(with("/sweeps/0/material", {{"density_kg_m3", 800}, {"metres_per_unit", 0.1}}));
  doc["sweeps"][0]["sections"][1]["material"] = {{"youngs_modulus_pa", 3e5}};
  std::vector<std::string> warnings;
  const Rig rig = parse_rig(doc.dump(), "rig.json", [&](const std::string& w) { warnings.push_back(w); });
  const SweepDef& def = rig.sweeps[0];
  ASSERT_TRUE(def.material.has_value());
  EXPECT_EQ(def.material->density, 800);
  EXPECT_EQ(def.material->metres_per_unit, 0.1);
  // Solved as a preset is, every section the sweep's material: that part sways at 2 Hz.
  SweepDef uniform = def;
  uniform.section_materials.assign(2, with_frequency(def.rest, *def.material, find_preset("tail")->frequency_hz));
  EXPECT_EQ(uniform.section_materials[0], *def.material);
  EXPECT_NEAR(sway_figures(uniform, Vec3::Zero()).frequencies_hz.at(0), 2.0, 1e-9);
  EXPECT_EQ(def.section_materials[0].youngs_modulus, def.material->youngs_modulus);
  EXPECT_EQ(def.section_materials[1].youngs_modulus, 3e5);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("rig.json: /sweeps/0/material: sweep \"tail\" gives no \"youngs_modulus_pa\": it takes " +
                             format_number(def.material->youngs_modulus, 4) + " Pa, which makes it sway at 2 Hz"),
            std::string::npos)
      << warnings[0];
  // Written back, the rig holds the modulus: read again, the same sweep and no warning.
  warnings.clear();
  const std::string text = format_rig(rig);
  EXPECT_EQ(format_rig(parse_rig(text, "again.json", [&](const std::string& w) { warnings.push_back(w); })), text);
  EXPECT_TRUE(warnings.empty());
}

TEST(RigJson, AMaterialFileMayNameAPresetOrTakeOneFromTheCommandLine) {
  const MaterialRequest named =
      parse_material_request(R"({"preset": "neck", "metres_per_unit": 0.01})", "m.json", nullptr);
  ASSERT_EQ(named.preset, find_preset("neck"));
  EXPECT_FALSE(named.youngs_modulus_given);
  EXPECT_EQ(named.material.metres_per_unit, 0.01);
  EXPECT_EQ(named.material.density, find_preset("neck")->density);
  const MaterialRequest over = parse_material_request(R"({"damping_ratio": 0.5})", "m.json", find_preset("tail"));
  EXPECT_EQ(over.material.damping_ratio, 0.5);
  EXPECT_EQ(over.material.density, find_preset("tail")->density);
  try {
    parse_material_request(R"({"preset": "neck"})", "m.json", find_preset("tail"));
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("m.json: /preset: the preset is given twice"), std::string::npos) << e.what();
  }
}

TEST(RigJson, MissingMembersAreNamed) {
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(format_rig(small_rig()));
  doc["sweeps"][0]["sections"][1].erase("center");
  expect_bad(doc.dump(), "/sweeps/0/sections/1: missing required member \"center\"");
  doc = nlohmann::ordered_json::parse(format_rig(small_rig()));
  doc["sweeps"][0]["sections"].erase(1);
  expect_bad(doc.dump(), "/sweeps/0/sections: a sweep needs at least 2 key sections, got 1");
}

TEST(RigJson, DuplicateNamesAreRefused) {
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(format_rig(small_rig()));
  doc["sweeps"].push_back(doc["sweeps"][0]);
  expect_bad(doc.dump(), "/sweeps/1/name: duplicate sweep name \"tail\"");
}

TEST(RigJson, OutOfRangeNumbersAreRefusedNotInfinite) {
  test::FpTrapsOff traps_off;  // the parser's strtod overflows on purpose here
  std::string text = format_rig(small_rig());
  const std::string needle = "\"rotational\": 0.75";
  text.replace(text.find(needle), needle.size(), "\"rotational\": 1e999");
  expect_bad(text, "rig.json: number overflow parsing '1e999'");
}

TEST(RigJson, UnknownMembersAreWarningsWithTheirName) {
  std::vector<std::string> warnings;
  const Rig rig = parse_rig(with("/sweeps/0/sections/0/colour", "red"), "rig.json",
                            [&](const std::string& w) { warnings.push_back(w); });
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "rig.json: /sweeps/0/sections/0/colour: unknown member \"colour\" ignored");
  EXPECT_EQ(rig.sweeps.size(), 1u);
}

TEST(RigJson, OverridesApplyOverTheSweepDefaults) {
  const Rig rig = parse_rig(with("/sweeps/0/springs/radial/frequency_hz", 9.5), "rig.json");
  const SweepDef& def = rig.sweeps[0];
  EXPECT_EQ(def.default_springs.radial.frequency_hz, 9.5);
  EXPECT_EQ(def.springs[0].radial.frequency_hz, 9.5);  // inherited
  EXPECT_EQ(def.springs[1].radial.frequency_hz, 9.5);
  EXPECT_EQ(def.springs[1].bend.frequency_hz, 4.25);  // the section's own override stays
  EXPECT_EQ(def.springs[0].bend.frequency_hz, def.default_springs.bend.frequency_hz);
}

TEST(RigJson, FilesAreWrittenAtomicallyAndMissingFilesNamed) {
  const auto dir = std::filesystem::temp_directory_path() / "sweep_rig_json_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_rig(dir / "a.rig.json", small_rig());
  EXPECT_EQ(read_rig(dir / "a.rig.json").sweeps[0].name, "tail");
  // Nothing but the file itself is left in the folder (no temporary).
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
  try {
    read_rig(dir / "missing.json");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::bad_input);
    EXPECT_NE(std::string(e.what()).find("missing.json: no such file"), std::string::npos);
  }
  try {
    write_rig(dir / "no-such-dir" / "b.json", small_rig());
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::output);
  }
  std::filesystem::remove_all(dir);
}

TEST(RigJson, MeshPathIsRelativeToTheRigFile) {
  Rig rig;
  rig.mesh = mesh_path_for_rig("/a/rigs/x.json", "/a/meshes/m.obj");
  EXPECT_EQ(rig.mesh, "../meshes/m.obj");
  EXPECT_EQ(resolve_mesh_path("/a/rigs/x.json", rig), std::filesystem::path("/a/meshes/m.obj"));
}

}  // namespace
}  // namespace sweep::io

namespace sweep::io {
namespace {

// A part cut on the tip side too is version 2's one addition; a rig without one is
// written as version 1, byte for byte as before.
TEST(RigJson, TipCutIsVersionTwoAndOnlyWrittenWhenSet) {
  Rig rig = small_rig();
  const std::string plain = format_rig(rig);
  EXPECT_EQ(plain.find("tip_cut"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(plain)["version"], 1);
  EXPECT_FALSE(parse_rig(plain, "rig.json").sweeps[0].part->tip_cut);

  rig.sweeps[0].part->tip_cut = true;
  const std::string cut = format_rig(rig);
  const auto doc = nlohmann::json::parse(cut);
  EXPECT_EQ(doc["version"], 2);
  EXPECT_EQ(doc["sweeps"][0]["part"]["tip_cut"], true);
  const Rig back = parse_rig(cut, "rig.json");
  ASSERT_TRUE(back.sweeps[0].part.has_value());
  EXPECT_TRUE(back.sweeps[0].part->tip_cut);
  EXPECT_EQ(format_rig(back), cut);

  // A version 1 file cannot carry it; a wrong type is named.
  nlohmann::ordered_json old = nlohmann::ordered_json::parse(cut);
  old["version"] = 1;
  expect_bad(old.dump(), "rig.json: /sweeps/0/part/tip_cut: needs rig format version 2 (the file says version 1)");
  nlohmann::ordered_json wrong = nlohmann::ordered_json::parse(cut);
  wrong["sweeps"][0]["part"]["tip_cut"] = "yes";
  expect_bad(wrong.dump(), "rig.json: /sweeps/0/part/tip_cut: must be");
  expect_bad(with("/version", 5), "/version: rig format version 5 is not supported (this build reads versions 1 to 4)",
             ErrorCategory::unsupported);
}

// Several meshes in one file: the mesh of the file a rig belongs to is version 3's
// addition, written only when the rig names one; a rig without it reads the whole file.
TEST(RigJson, MeshNameIsVersionThreeAndOnlyWrittenWhenSet) {
  Rig rig = small_rig();
  EXPECT_EQ(format_rig(rig).find("mesh_name"), std::string::npos);
  EXPECT_EQ(parse_rig(format_rig(rig), "rig.json").mesh_name, "");
  rig.mesh_name = "Tail";
  rig.sweeps[0].part->tip_cut = true;  // version 2's member, carried by version 3
  const std::string named = format_rig(rig);
  const auto doc = nlohmann::ordered_json::parse(named);
  EXPECT_EQ(doc["version"], 3);
  EXPECT_EQ(doc["mesh_name"], "Tail");
  const Rig back = parse_rig(named, "rig.json");
  EXPECT_EQ(back.mesh_name, "Tail");
  EXPECT_TRUE(back.sweeps[0].part->tip_cut);
  EXPECT_EQ(format_rig(back), named);

  nlohmann::ordered_json old = doc;
  old["version"] = 2;
  expect_bad(old.dump(), "rig.json: /mesh_name: needs rig format version 3 (the file says version 2)");
  nlohmann::ordered_json empty = doc;
  empty["mesh_name"] = "";
  expect_bad(empty.dump(), "rig.json: /mesh_name: must not be empty");
}

// A rig over several meshes of one file names them all, in order, as a list (version 4); in memory
// Rig::mesh_name holds them joined by NUL. A list of one is that name; a name twice, an empty one
// or a NUL in one is refused with its pointer.
TEST(RigJson, SeveralMeshesAreAnOrderedListInVersionFour) {
  Rig rig = small_rig();
  rig.mesh_name = join_mesh_names({"Body", "LegL", "LegR"});
  EXPECT_EQ(rig.mesh_name, std::string("Body\0LegL\0LegR", 14));
  const std::string text = format_rig(rig);
  const auto doc = nlohmann::ordered_json::parse(text);
  EXPECT_EQ(doc["version"], 4);
  EXPECT_EQ(doc["mesh_name"], nlohmann::ordered_json::array({"Body", "LegL", "LegR"}));
  const Rig back = parse_rig(text, "rig.json");
  EXPECT_EQ(split_mesh_names(back.mesh_name), (std::vector<std::string>{"Body", "LegL", "LegR"}));
  EXPECT_EQ(format_rig(back), text);
  EXPECT_EQ(shown_mesh_names(back.mesh_name), "the meshes 'Body', 'LegL', 'LegR'");
  EXPECT_EQ(shown_mesh_names("Tail"), "'Tail'");

  nlohmann::ordered_json one = doc;
  one["mesh_name"] = nlohmann::ordered_json::array({"Tail"});
  EXPECT_EQ(parse_rig(one.dump(), "rig.json").mesh_name, "Tail");
  nlohmann::ordered_json old = doc;
  old["version"] = 3;
  expect_bad(old.dump(), "rig.json: /mesh_name: a list of meshes needs rig format version 4 (the file says version 3)");
  nlohmann::ordered_json twice = doc;
  twice["mesh_name"][2] = "Body";
  expect_bad(twice.dump(), "rig.json: /mesh_name/2: names the mesh 'Body' again (it is /mesh_name/0)");
  nlohmann::ordered_json empty = doc;
  empty["mesh_name"] = nlohmann::ordered_json::array();
  expect_bad(empty.dump(), "rig.json: /mesh_name: must not be empty");
  nlohmann::ordered_json blank = doc;
  blank["mesh_name"][1] = "";
  expect_bad(blank.dump(), "rig.json: /mesh_name/1: must not be empty");
  nlohmann::ordered_json nul = doc;
  nul["mesh_name"] = std::string("Le\0gL", 6);
  expect_bad(nul.dump(), "rig.json: /mesh_name: must not hold a NUL character");
  nlohmann::ordered_json number = doc;
  number["mesh_name"][0] = 3;
  expect_bad(number.dump(), "rig.json: /mesh_name/0: must be a string");
}

}  // namespace
}  // namespace sweep::io
