// Messages a newcomer trips on: seeds measured against the surface, fits the same at any
// scale, why the axis ends (report, -v, the stopped-short message), a report on every failure once
// the mesh is read, numbers by the format helper, one line for an .obj sequence, and tapered
// tubes whose sections are star-shaped however the section planes meet the mesh's vertices.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>

#include "pipeline.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/core/presets.h"
#include "sweep/core/sway.h"
#include "sweep/io/rig_json.h"

namespace sweep::test {
namespace {

using nlohmann::json;

json read_json(const fs::path& p) {
  return json::parse(slurp(p));
}

// A tube by sweep-tube into `dir`.
fs::path make_tube(const fs::path& dir, const fs::path& io, const std::string& name, const std::string& args) {
  const fs::path mesh = dir / name;
  const ToolRun r = run_tool(SWEEP_TUBE_EXE, "-q " + args + " -o " + quoted(mesh), io);
  EXPECT_EQ(r.code, 0) << r.err;
  return mesh;
}

// A point on a large face, far from every vertex, is on the mesh: the distance is to the
// surface. (A 50-unit tube of 3 rings: the point halfway between two rings lies 12.5 from the
// nearest vertex, more than the limit of a tenth of the diagonal, 5.)
TEST(NewcomerMessages, ASeedOnALargeFaceIsOnTheMesh) {
  const Workspace ws("messages-seed-face");
  const fs::path mesh = make_tube(ws.work, ws.io, "coarse.obj", "--length 50 --radius 2 --rings 3 --segments 6");
  // The middle of the side quad between θ = 0 and 60°, halfway between rings 0 and 1.
  const std::string root = "1.5,0.8660254037844386,12.5";
  const ToolRun r = run_tool(SWEEP_FIT_EXE,
                             quoted(mesh) + " -o " + quoted(ws / "c.rig.json") + " --root " + root +
                                 " --tip 0,0,50 --force --report " + quoted(ws / "c.json"),
                             ws.io);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("far from the mesh"), std::string::npos) << r.err;
  const json s = read_json(ws / "c.json").at("sweeps").at(0);
  EXPECT_LT(s.at("root_off_surface").get<double>(), 1e-9);
  EXPECT_NEAR(s.at("seed_limit").get<double>(), 0.1 * std::sqrt(4 * 4 + 4 * 4 * 0.75 + 50 * 50), 0.5);
}

// The same tube at 0.35, 1.5 and 50 units long (and at a thousandth and a thousand times) fits
// alike (to the precision of the coordinates the OBJ writer keeps): every threshold of the fit is
// relative to the part or the mesh.
TEST(NewcomerMessages, APartFitsTheSameAtAnyScale) {
  const Workspace ws("messages-scale");
  const Mesh tube = assets::read_mesh(fs::path(SWEEP_SOURCE_DIR) / "meshes" / "tube_tapered.off");
  json reference;
  for (const double scale : {1.0, 0.35 / 1.5, 50 / 1.5, 1e-3 / 1.5, 1e3 / 1.5}) {
    Mesh scaled = tube;
    for (Vec3& p : scaled.positions) p *= scale;
    const std::string name = "tube-" + std::to_string(scale);
    assets::write_obj(ws / (name + ".obj"), scaled);
    const ToolRun r =
        run_tool(SWEEP_FIT_EXE,
                 quoted(ws / (name + ".obj")) + " -o " + quoted(ws / (name + ".rig.json")) + " --tip 0,0," +
                     std::to_string(1.5 * scale) + " --report " + quoted(ws / (name + ".json")),
                 ws.io);
    ASSERT_EQ(r.code, 0) << "scale " << scale << ": " << r.err;
    const json s = read_json(ws / (name + ".json")).at("sweeps").at(0);
    if (reference.is_null()) {
      reference = s;
      continue;
    }
    for (const char* key : {"traced_over_surface", "tip_gap_relative", "in_range_share", "fit_rms_relative",
                            "fit_p90_relative", "surface_rms_relative"}) {
      EXPECT_NEAR(s.at(key).get<double>(), reference.at(key).get<double>(), 1e-4) << key << " at scale " << scale;
    }
    EXPECT_NEAR(s.at("length").get<double>() / scale, reference.at("length").get<double>(), 1e-6) << "scale " << scale;
    EXPECT_EQ(s.at("part_vertex_count"), reference.at("part_vertex_count")) << "scale " << scale;
  }
}

// sweep-fit --preset: the fitted part's stiffness is solved on its own sections, so the tapered
// tube at two sizes sways at the preset's frequency both times (E differs); a name it does not
// know is a usage error that lists the presets.
TEST(NewcomerMessages, APresetSwaysAtItsFrequencyAtAnyScale) {
  const Workspace ws("messages-preset");
  const Mesh tube = assets::read_mesh(fs::path(SWEEP_SOURCE_DIR) / "meshes" / "tube_tapered.off");
  std::vector<double> youngs;
  for (const double scale : {1.0, 50 / 1.5}) {
    Mesh scaled = tube;
    for (Vec3& p : scaled.positions) p *= scale;
    const std::string name = "tube-" + std::to_string(scale);
    assets::write_obj(ws / (name + ".obj"), scaled);
    const ToolRun r = run_tool(SWEEP_FIT_EXE,
                               quoted(ws / (name + ".obj")) + " -o " + quoted(ws / (name + ".rig.json")) +
                                   " --tip 0,0," + std::to_string(1.5 * scale) + " --preset tail",
                               ws.io);
    ASSERT_EQ(r.code, 0) << "scale " << scale << ": " << r.err;
    const Rig rig = io::read_rig(ws / (name + ".rig.json"));
    ASSERT_TRUE(rig.sweeps.at(0).material.has_value());
    EXPECT_EQ(rig.sweeps[0].material->density, find_preset("tail")->density);
    const SwayFigures f = sway_figures(rig.sweeps[0], Vec3::Zero());
    ASSERT_FALSE(f.frequencies_hz.empty());
    EXPECT_NEAR(f.frequencies_hz[0], find_preset("tail")->frequency_hz, 1e-9) << "scale " << scale;
    youngs.push_back(rig.sweeps[0].material->youngs_modulus);
  }
  EXPECT_GT(youngs[1], 100 * youngs[0]);  // a part 33× as long (in metres) needs ~1100× the E
  const ToolRun bad = run_tool(
      SWEEP_FIT_EXE,
      quoted(ws / "tube-1.000000.obj") + " -o " + quoted(ws / "bad.rig.json") + " --tip 0,0,1.5 --preset wing", ws.io);
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("--preset: unknown preset 'wing': one of tail, neck, ear, tentacle, strand"),
            std::string::npos)
      << bad.err;
  EXPECT_FALSE(fs::exists(ws / "bad.rig.json"));
}

// Why the axis ends where it does: in the report and with -v.
TEST(NewcomerMessages, WhyTheAxisEndsIsReported) {
  const Workspace ws("messages-end-reason");
  const ToolRun r = run_tool(SWEEP_FIT_EXE,
                             quoted(ws / "tube.obj") + " -o " + quoted(ws / "e.rig.json") +
                                 " --tip 0,0,1 -v --report " + quoted(ws / "e.json"),
                             ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string why = read_json(ws / "e.json").at("sweeps").at(0).at("trace_end_reason");
  EXPECT_NE(why.find("the slices reached the cap"), std::string::npos) << why;
  EXPECT_NE(r.out.find(why), std::string::npos) << r.out;
}

// A fit that fails once the mesh is read still writes its report (and preview): the error, its
// exit code, and the fit as far as it got with its numbers. No rig.
TEST(NewcomerMessages, AFailedFitWritesItsReport) {
  const Workspace ws("messages-failure-report");
  Mesh two = assets::read_mesh(ws / "tube.obj");
  const std::size_t n = two.positions.size(), faces = two.face_count();
  for (std::size_t v = 0; v < n; ++v) two.positions.push_back(two.positions[v] + Vec3(0.5, 0, 0));
  for (std::size_t f = 0; f < faces; ++f) {
    for (std::uint32_t k = two.face_offsets[f]; k < two.face_offsets[f + 1]; ++k)
      two.face_vertices.push_back(static_cast<std::uint32_t>(two.face_vertices[k] + n));
    two.face_offsets.push_back(static_cast<std::uint32_t>(two.face_vertices.size()));
  }
  assets::write_obj(ws / "two.obj", two);
  spit(ws / "flat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  struct Case {
    std::string args;
    int code;
    std::string message;
  };
  const std::string tube = quoted(ws / "tube.obj");
  const Case cases[] = {
      {tube + " --root 5,5,5 --tip 0,0,1", 2, "root 5,5,5 is far from the mesh"},
      {tube + " --root 0,0,0.1 --tip 0,3,1", 2, "tip 0,3,1 is far from the mesh"},
      {tube + " --tip-vertex 100000", 1, "tip_vertex 100000 is not a vertex of the mesh"},
      {quoted(ws / "two.obj") + " --root 0,0,0.1 --tip 0.5,0,1", 2, "not reachable"},
      {quoted(ws / "flat.off") + " --all", 2, "no tubular parts found"},
  };
  for (const Case& c : cases) {
    fs::remove(ws / "f.json");
    fs::remove(ws / "f.png");
    const ToolRun r = run_tool(SWEEP_FIT_EXE,
                               c.args + " -o " + quoted(ws / "f.rig.json") + " --report " + quoted(ws / "f.json") +
                                   " --preview " + quoted(ws / "f.png"),
                               ws.io);
    EXPECT_EQ(r.code, c.code) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(ws / "f.rig.json")) << c.args;
    EXPECT_TRUE(fs::exists(ws / "f.png")) << c.args;
    ASSERT_TRUE(fs::exists(ws / "f.json")) << c.args;
    const json rep = read_json(ws / "f.json");
    EXPECT_FALSE(rep.at("rig_written").get<bool>());
    EXPECT_EQ(rep.at("error").at("exit_code"), c.code);
    const std::string message = rep.at("error").at("message");
    EXPECT_NE(r.err.find("error: " + message), std::string::npos) << message;
    if (c.message.find("no tubular") != std::string::npos) continue;  // no fit began
    const json& s = rep.at("sweeps").at(0);
    EXPECT_FALSE(s.at("ok").get<bool>());
    EXPECT_EQ(s.at("problems").at(0), message);
    if (c.message.find("root 5,5,5") != std::string::npos) {
      EXPECT_GT(s.at("root_off_surface").get<double>(), s.at("seed_limit").get<double>());
      EXPECT_EQ(s.at("root"), json::array({5.0, 5.0, 5.0}));
    }
    if (c.message.find("tip 0,3,1") != std::string::npos) {
      EXPECT_GT(s.at("tip_off_surface").get<double>(), s.at("seed_limit").get<double>());
      EXPECT_LT(s.at("root_off_surface").get<double>(), 1e-9) << "on the root cap's plane";
    }
  }
}

// Numbers in messages and summaries come from the format helper (core/text.h): no "%f" or
// std::to_string of a double ("60.000000 degrees").
TEST(NewcomerMessages, NumbersInMessagesAreFormatted) {
  const Workspace ws("messages-numbers");
  const std::regex six_decimals("[0-9]\\.[0-9]{6}");
  spit(ws / "big.json",
       R"({"format": "sweep-scene", "version": 1, "duration": 0.5, "fps": 10,
  "forces": [{"sweep": "tube", "t": 1, "theta": 0, "vector": [2e9, 0, 0], "start": 0, "end": 0.2}]})");
  ToolRun r = run_tool(
      SWEEP_SIM_EXE, quoted(ws / "rig.json") + " -s " + quoted(ws / "big.json") + " -o " + quoted(ws / "a.pc2"), ws.io);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("got one of length 2e+09"), std::string::npos) << r.err;
  // The summaries of the three tools.
  r = run_tool(SWEEP_FIT_EXE,
               quoted(ws / "tube.obj") + " -o " + quoted(ws / "n.rig.json") +
                   " --name tube --root 0,0,0.02 --tip 0,0,1 -k 6 -n 8 -v",
               ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(std::regex_search(r.out, six_decimals)) << r.out;
  r = run_tool(SWEEP_BIND_EXE, quoted(ws / "n.rig.json"), ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(std::regex_search(r.out, six_decimals)) << r.out;
  r = run_tool(SWEEP_SIM_EXE,
               quoted(ws / "n.rig.json") + " -s " + quoted(ws / "scene.json") + " -o " + quoted(ws / "n.pc2"), ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(std::regex_search(r.out, six_decimals)) << r.out;
  EXPECT_NE(r.out.find("baked 6 frames (0.5 s at 10 fps"), std::string::npos) << r.out;
}

// An .obj sequence is one line of the summary: its pattern and its count.
TEST(NewcomerMessages, AnObjSequenceIsOneWroteLine) {
  const Workspace ws("messages-obj-sequence");
  fs::create_directories(ws / "seq");
  const ToolRun r = run_tool(SWEEP_SIM_EXE,
                             quoted(ws / "rig.json") + " -s " + quoted(ws / "scene.json") + " -o " +
                                 quoted(ws / "seq" / "b.obj") + " -o " + quoted(ws / "b.pc2"),
                             ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  int wrote = 0;
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) wrote += line.rfind("wrote ", 0) == 0;
  EXPECT_EQ(wrote, 2) << r.out;
  EXPECT_NE(
      r.out.find("wrote 6 files " + (ws / "seq" / "b_0000.obj").string() + " ... b_0005.obj (b_####.obj, one a frame)"),
      std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("wrote " + (ws / "b.pc2").string() + "\n"), std::string::npos) << r.out;
}

// A perfect tapered tube has star-shaped sections wherever they are cut: section 0 in the plane
// of the flat root cap (a fan the plane contains), or through a ring of vertices of a coarse tube.
TEST(NewcomerMessages, TaperedTubeSectionsAreStarShaped) {
  const Workspace ws("messages-star");
  const fs::path coarse =
      make_tube(ws.work, ws.io, "coarse.off", "--length 1.5 --radius 0.15 --taper 0.4 --rings 5 --segments 6");
  const fs::path committed = fs::path(SWEEP_SOURCE_DIR) / "meshes" / "tube_tapered.off";
  struct Case {
    fs::path mesh;
    std::string root;
  };
  const Case cases[] = {{committed, "0,0,0"},     {coarse, "0,0,0"}, {coarse, "0,0,0.375"},
                        {committed, "0,0,0.375"}, {committed, ""},   {coarse, ""}};
  for (const Case& c : cases) {
    fs::remove(ws / "s.rig.json");
    const ToolRun r = run_tool(SWEEP_FIT_EXE,
                               quoted(c.mesh) + " -o " + quoted(ws / "s.rig.json") + " --tip 0,0,1.5 --force" +
                                   (c.root.empty() ? "" : " --root " + c.root) + " --report " + quoted(ws / "s.json"),
                               ws.io);
    ASSERT_EQ(r.code, 0) << c.mesh << " " << c.root << ": " << r.err;
    EXPECT_EQ(r.err.find("star-shaped"), std::string::npos) << c.mesh << " " << c.root << ": " << r.err;
    EXPECT_EQ(read_json(ws / "s.json").at("sweeps").at(0).at("star_violations"), json::array())
        << c.mesh << " " << c.root;
  }
}

}  // namespace
}  // namespace sweep::test
