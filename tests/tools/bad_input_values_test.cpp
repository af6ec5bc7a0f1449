// The bad-input matrix (bad_input_test.cpp's test), on what the earlier rounds let through: option
// values that were empty, NaN, zero, negative or past 64 bits; glTF files that crashed, hung or
// were blamed on the wrong thing; OBJ and MTL values that put NaN or an out-of-range index into a
// .glb; outputs that are not files; and every numeric option of each tool's --help given values no
// number can be (the matrix generated from the help text). Each is refused with the documented exit code and a message
// naming the place, nothing written, the inputs untouched; what a tool should take, it takes.
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <string>
#include <utility>

#include "bad_input_case.h"

namespace sweep::test {
namespace {

std::string fit_tube(const Workspace& ws, const std::string& extra) {
  return quoted(ws / "tube.obj") + " -o " + quoted(ws / "new.rig.json") + " --name tube" + extra;
}

std::string sim_tube(const Workspace& ws, const std::string& extra, const std::string& out = "out.glb") {
  return quoted(ws / "rig.json") + " -s " + quoted(ws / "scene.json") + " -q -o " + quoted(ws / out) + extra;
}

// One triangle (three float VEC3 positions, three uint16 indices) in t.gltf with its bytes in
// t.bin, changed by `change` before it is written: the smallest glTF to break one member of.
void write_triangle_gltf(const Workspace& ws, const std::function<void(json&)>& change) {
  std::string bin(44, '\0');
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint16_t i[4] = {0, 1, 2, 0};
  std::memcpy(bin.data(), p, sizeof p);
  std::memcpy(bin.data() + 36, i, sizeof i);
  spit(ws / "t.bin", bin);
  json doc = json::parse(R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0, "name": "Tri"}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "buffers": [{"byteLength": 44, "uri": "t.bin"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 8}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})");
  change(doc);
  spit(ws / "t.gltf", doc.dump(1));
}

Case gltf_case(std::string name, std::function<void(json&)> change, std::string expect,
               const std::string& mode = " --tip 0,0,1") {
  return Case{std::move(name),
              SWEEP_FIT_EXE,
              [change, mode](const Workspace& ws) {
                write_triangle_gltf(ws, change);
                return quoted(ws / "t.gltf") + (mode == " --list" ? mode : " -o " + quoted(ws / "new.rig.json") + mode);
              },
              2,
              {std::move(expect)}};
}

// The tube's OBJ (the rig's mesh) changed by `change`: the positions stay, so the binding holds.
Case obj_case(std::string name, std::function<void(const Workspace&, std::string&)> change,
              std::vector<std::string> expect) {
  return Case{std::move(name), SWEEP_SIM_EXE,
              [change](const Workspace& ws) {
                std::string obj = slurp(ws / "tube.obj");
                change(ws, obj);
                spit(ws / "tube.obj", obj);
                return sim_tube(ws, "");
              },
              2, std::move(expect)};
}

std::vector<Case> option_cases() {
  const char* fit = SWEEP_FIT_EXE;
  const char* sim = SWEEP_SIM_EXE;
  const char* bind = SWEEP_BIND_EXE;
  return {
      {"Fit_EmptyTip",
       fit,
       [](const Workspace& ws) { return fit_tube(ws, " --tip ''"); },
       1,
       {"--tip expects three finite numbers X,Y,Z, got ''"}},
      {"Fit_EmptyRoot",
       fit,
       [](const Workspace& ws) { return fit_tube(ws, " --root '' --tip 0,0,1"); },
       1,
       {"--root expects three finite numbers X,Y,Z, got ''"}},
      {"Fit_TipVertexNegative",
       fit,
       [](const Workspace& ws) { return fit_tube(ws, " --tip-vertex -1"); },
       1,
       {"--tip-vertex must be a whole number >= 0, got '-1'"}},
      {"Fit_TipVertexNotANumber",
       fit,
       [](const Workspace& ws) { return fit_tube(ws, " --tip-vertex abc"); },
       1,
       {"--tip-vertex must be a whole number >= 0, got 'abc'"}},
      {"Fit_TipVertexTwoToThe64Minus1",
       fit,
       [](const Workspace& ws) { return fit_tube(ws, " --tip-vertex 18446744073709551615"); },
       1,
       {"--tip-vertex 18446744073709551615 is past the vertices of any mesh (a mesh has at most 4294967294)"}},
      {"Fit_TipVertexPast64Bits",
       fit,
       [](const Workspace& ws) { return fit_tube(ws, " --tip-vertex 18446744073709551616"); },
       1,
       {"--tip-vertex is too large: 18446744073709551616 is beyond 2^64 - 1"}},
      {"Fit_AllWithANameTwice",
       fit,
       [](const Workspace& ws) {
         return quoted(ws / "tube.obj") + " --all -o " + quoted(ws / "new.rig.json") + " --names same,same";
       },
       1,
       {"--names: 'same' is given twice (parts 1 and 2 in 'same,same'); a rig holds one sweep a name"}},
      {"Fit_OutputIsAFolder",
       fit,
       [](const Workspace& ws) {
         fs::create_directory(ws / "rig.d");
         return quoted(ws / "tube.obj") + " -o " + quoted(ws / "rig.d") + " --name tube --tip 0,0,1";
       },
       4,
       {"rig.d: is a folder; outputs replace regular files only"}},
      {"Fit_OutputIsAFifo",
       fit,
       [](const Workspace& ws) {
         make_fifo(ws / "pipe.json");
         return quoted(ws / "tube.obj") + " -o " + quoted(ws / "pipe.json") + " --name tube --tip 0,0,1";
       },
       4,
       {"pipe.json: is a FIFO; outputs replace regular files only"}},
      {"Fit_OutputIsDevNull",
       fit,
       [](const Workspace& ws) { return quoted(ws / "tube.obj") + " -o /dev/null --name tube --tip 0,0,1"; },
       4,
       {"/dev/null: is a device; outputs replace regular files only"}},

      {"Bind_SubnormalBlendIsANumber",
       bind,
       [](const Workspace& ws) { return quoted(ws / "rig.json") + " -q --blend 1e-308 -o " + quoted(ws / "b.bind"); },
       0,
       {},
       {"b.bind"}},
      {"Sim_StepNan",
       sim,
       [](const Workspace& ws) { return sim_tube(ws, " --step nan"); },
       1,
       {"--step", "must be a finite number, got nan"}},
      {"Sim_MaxOutputSizeZero",
       sim,
       [](const Workspace& ws) { return sim_tube(ws, " --max-output-size 0"); },
       1,
       {"--max-output-size", "must be at least 1 byte, got '0' (leave the option out for no limit)"}},
      {"Sim_MaxOutputSizeNegative",
       sim,
       [](const Workspace& ws) { return sim_tube(ws, " --max-output-size -1"); },
       1,
       {"--max-output-size",
        "must be a whole number of bytes with an optional unit (K, M, G, KiB, MiB, GiB), got '-1'"}},
      {"Sim_MaxOutputSizePast64Bits",
       sim,
       [](const Workspace& ws) { return sim_tube(ws, " --max-output-size 18446744073709552616"); },
       1,
       {"--max-output-size", "is too large: 18446744073709552616 is beyond 2^64 - 1 bytes"}},
      {"Sim_MaxOutputSizeUnitPast64Bits",
       sim,
       [](const Workspace& ws) { return sim_tube(ws, " --max-output-size 18446744073709552G"); },
       1,
       {"--max-output-size", "is too large: 18446744073709552G is beyond 2^64 - 1 bytes"}},
  };
}

// Every numeric option each tool's --help lists (its value typed INT, FLOAT or SIZE), given each
// value no number can be: generated from the help text, so a new option joins the matrix by being
// added. Each run is otherwise valid, so the refusal can only be the value's, and it must name the
// option. The help text is the one the build wrote beside the tests when it built the tool
// (tests/tools/CMakeLists.txt): the cases are generated as every test process of this executable
// starts. A missing file gives no options, and OptionMatrix.FindsTheNumericOptions… fails.
std::string help_text(const char* exe) {
  const std::string name = std::filesystem::path(exe).filename().string();
  std::ifstream in(std::filesystem::path(SWEEP_TOOL_HELP_DIR) / (name + ".txt"));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> numeric_options(const char* exe) {
  std::vector<std::string> options;
  std::istringstream lines(help_text(exe));
  const std::regex typed(R"(^\s+(?:-\w,)?(--[a-z][a-z0-9-]*) (?:INT|FLOAT|UINT|TEXT:SIZE)\b)");
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_search(line, m, typed)) options.push_back(m[1]);
  }
  return options;
}

std::vector<Case> numeric_option_cases() {
  struct Tool {
    const char* exe;
    const char* tag;
    std::function<std::string(const Workspace&, const std::string&)> args;
  };
  const Tool tools[] = {
      {SWEEP_FIT_EXE, "Fit",
       [](const Workspace& ws, const std::string& o) { return fit_tube(ws, " --tip 0,0,1" + o); }},
      {SWEEP_BIND_EXE, "Bind",
       [](const Workspace& ws, const std::string& o) {
         return quoted(ws / "rig.json") + " -q -o " + quoted(ws / "b.bind") + o;
       }},
      {SWEEP_SIM_EXE, "Sim", [](const Workspace& ws, const std::string& o) { return sim_tube(ws, o); }},
  };
  const std::pair<const char*, const char*> values[] = {{"Nan", "nan"},  {"Inf", "inf"},  {"MinusInf", "-inf"},
                                                        {"Word", "abc"}, {"Empty", "''"}, {"PastDouble", "1e999"}};
  std::vector<Case> cases;
  for (const Tool& tool : tools) {
    for (const std::string& option : numeric_options(tool.exe)) {
      std::string id;
      for (const char c : option.substr(2)) id += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      for (const auto& [tag, value] : values) {
        const std::string extra = " " + option + "=" + value;
        const auto args = tool.args;
        cases.push_back({std::string(tool.tag) + "_Every_" + id + "_" + tag,
                         tool.exe,
                         [args, extra](const Workspace& ws) { return args(ws, extra); },
                         1,
                         {option}});
      }
    }
  }
  return cases;
}

// The generator itself: it must find the numeric options the tools are known to have.
TEST(OptionMatrix, FindsTheNumericOptionsInEachToolsHelp) {
  const auto has = [](const std::vector<std::string>& v, const char* o) {
    return std::find(v.begin(), v.end(), o) != v.end();
  };
  const auto fit = numeric_options(SWEEP_FIT_EXE), sim = numeric_options(SWEEP_SIM_EXE),
             bind = numeric_options(SWEEP_BIND_EXE);
  EXPECT_TRUE(has(fit, "--sections") && has(fit, "--radial") && has(fit, "--tolerance"));
  EXPECT_TRUE(has(bind, "--blend"));
  EXPECT_TRUE(has(sim, "--step") && has(sim, "--substeps") && has(sim, "--threads") && has(sim, "--stations") &&
              has(sim, "--max-output-size"));
}

std::vector<Case> gltf_cases() {
  return {
      gltf_case(
          "Fit_GltfIndexCountNotTriangles", [](json& j) { j["accessors"][1]["count"] = 4; },
          "t.gltf: mesh 0 primitive 0: 4 indices (/meshes/0/primitives/0/indices), not a multiple of 3"),
      gltf_case(
          "Fit_GltfNodeSkinPastTheSkins", [](json& j) { j["nodes"][0]["skin"] = 3; },
          "t.gltf: /nodes/0/skin: 3 is not a skin (the file has 0 skins)"),
      gltf_case(
          "Fit_GltfSkinJointPastTheNodes", [](json& j) { j["skins"] = json::parse(R"([{"joints": [7]}])"); },
          "t.gltf: /skins/0/joints/0: 7 is not a node (the file has 1)"),
      // assimp crashed (SIGSEGV) on this one, --list as well as a fit.
      gltf_case(
          "Fit_GltfSkinnedMeshWithoutJoints",
          [](json& j) {
            j["nodes"][0]["skin"] = 0;
            j["nodes"].push_back({{"name", "Bone"}});
            j["scenes"][0]["nodes"].push_back(1);
            j["skins"] = json::parse(R"([{"joints": [1]}])");
          },
          "t.gltf: /nodes/0/skin: node 0 is skinned by skin 0, but its mesh 0 primitive 0 has no JOINTS_0", " --list"),
      gltf_case(
          "Fit_GltfAccessorLongerThanItsView", [](json& j) { j["accessors"][0]["count"] = 4; },
          "t.gltf: /accessors/0: 4 elements of 12 bytes (stride 12) from byte 0 do not fit in bufferView 0's 36 bytes"),
      gltf_case(
          "Fit_GltfStrideShorterThanAnElement", [](json& j) { j["bufferViews"][0]["byteStride"] = 4; },
          "t.gltf: /accessors/0: its elements are 12 bytes, but its bufferView 0 has a byteStride of 4"),
      Case{"Fit_GltfBufferIsAFifo",
           SWEEP_FIT_EXE,
           [](const Workspace& ws) {
             write_triangle_gltf(ws, [](json& j) { j["buffers"][0]["uri"] = "pipe.bin"; });
             make_fifo(ws / "pipe.bin");
             return quoted(ws / "t.gltf") + " --list";
           },
           2,
           {"t.gltf: /buffers/0/uri: 'pipe.bin' is not a regular file"}},
  };
}

std::vector<Case> obj_cases() {
  return {
      obj_case("Sim_ObjTextureCoordinateOutOfRange",
               [](const Workspace&, std::string& obj) { obj += "vt 0 0\nf 1/99999 2/1 3/1\n"; },
               {"tube.obj: line ",
                "uses texture coordinate 99999 (as in the file), out of range (the file has 1 before this line)"}),
      obj_case("Sim_ObjNormalOutOfRange",
               [](const Workspace&, std::string& obj) { obj += "vn 0 0 1\nf 1//1 2//1 3//7\n"; },
               {"tube.obj: line ", "uses normal 7 (as in the file), out of range (the file has 1 before this line)"}),
      obj_case("Sim_ObjColourNan",
               [](const Workspace&, std::string& obj) {
                 const std::size_t v = obj.find("\nv ") + 1;
                 obj.insert(obj.find('\n', v), " nan 0 0");
               },
               {"tube.obj: line ", ": vertex 0 has a colour that is not finite (nan, 0, 0)"}),
      obj_case("Sim_MtlColourNan",
               [](const Workspace& ws, std::string& obj) {
                 spit(ws / "m.mtl", "newmtl skin\nKd nan inf 0.2\n");
                 obj = "mtllib m.mtl\nusemtl skin\n" + obj;
               },
               {"m.mtl: line 2: material 'skin': Kd must be three finite numbers, got 'nan inf 0.2'"}),
  };
}

// -q is accepted, as the README documents for every tool, and a successful fit then prints nothing.
TEST(FitQuiet, QuietIsAcceptedAndPrintsNothing) {
  const Workspace ws("fit-quiet");
  const ToolRun r = run_tool(SWEEP_FIT_EXE, fit_tube(ws, " --root 0,0,0.02 --tip 0,0,1 -k 6 -n 8 -q"), ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "");
  EXPECT_TRUE(fs::exists(ws / "new.rig.json"));
}

// --list on a tube open at both ends: the parts it finds end at rims, and it says the mesh is open
// (it used to say so only when it found no part).
TEST(FitList, AnOpenTubeIsSaidToBeOpen) {
  const Workspace ws("fit-list-open");
  ASSERT_EQ(run_tool(SWEEP_TUBE_EXE, "-q --no-caps --segments 24 -o " + quoted(ws / "open.obj"), ws.io).code, 0);
  const ToolRun r = run_tool(SWEEP_FIT_EXE, quoted(ws / "open.obj") + " --list", ws.io);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("the mesh is open: 48 edges rim holes the search left open"), std::string::npos) << r.out;
}

// A mesh far out of scale (a glTF node's scale of 1e30 did it) fits to sections past the ±1e9 of
// any length in a rig, which sweep-bind refuses: the rig is not written.
TEST(FitLimits, ARigPastTheLengthLimitIsNotWritten) {
  const Workspace ws("fit-rig-limit");
  std::istringstream in(slurp(ws / "tube.obj"));
  std::string out;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) == 0) {
      std::istringstream v(line.substr(2));
      double x = 0, y = 0, z = 0;
      v >> x >> y >> z;
      char text[128];
      std::snprintf(text, sizeof text, "v %.17g %.17g %.17g", x * 1e12, y * 1e12, z * 1e12);
      line = text;
    }
    out += line + "\n";
  }
  spit(ws / "huge.obj", out);
  const std::set<std::string> before = listing(ws.work);
  const ToolRun r = run_tool(SWEEP_FIT_EXE,
                             quoted(ws / "huge.obj") + " -o " + quoted(ws / "huge.rig.json") +
                                 " --name tube --root 0,0,2e10 --tip 0,0,1e12 -k 6 -n 8",
                             ws.io);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("huge.obj: the fitted rig would break the rig format's limits ("), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("must be between"), std::string::npos) << r.err;
  EXPECT_EQ(listing(ws.work), before);
}

// A tip 1e300 away: its distance squared overflows, and it used to be "inf from its surface" in
// the message and null in the report. Both say the distance.
TEST(FitSeeds, ATipFarAwayIsSaidHowFar) {
  const Workspace ws("fit-far-tip");
  const ToolRun r = run_tool(SWEEP_FIT_EXE, fit_tube(ws, " --tip 1e300,0,0 --report " + quoted(ws / "r.json")), ws.io);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("is far from the mesh: 1e+300 from its surface"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("inf"), std::string::npos) << r.err;
  const json report = json::parse(slurp(ws / "r.json"));
  const json& off = report["sweeps"][0]["tip_off_surface"];
  ASSERT_TRUE(off.is_number()) << report.dump(1);
  EXPECT_NEAR(off.get<double>() / 1e300, 1.0, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Options, BadInput, testing::ValuesIn(option_cases()), case_name);
INSTANTIATE_TEST_SUITE_P(NumericOptions, BadInput, testing::ValuesIn(numeric_option_cases()), case_name);
INSTANTIATE_TEST_SUITE_P(Gltf, BadInput, testing::ValuesIn(gltf_cases()), case_name);
INSTANTIATE_TEST_SUITE_P(ObjSurface, BadInput, testing::ValuesIn(obj_cases()), case_name);

}  // namespace
}  // namespace sweep::test
