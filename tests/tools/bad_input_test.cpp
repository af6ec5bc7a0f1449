// The bad-input matrix: every tool meets each kind of broken input with the documented exit code
// (core/error.h: 1 usage, 2 bad input, 3 unsupported, 4 output, 5 diverged), one line on stderr
// naming the file, the place (line, JSON pointer, vertex or face index) and what is wrong, nothing
// on stdout, and the folder exactly as it was: no output, no temporary, no input touched.
// Unknown JSON members are warnings naming the member, and the run succeeds.
//
// Cases already covered elsewhere are not repeated: tests/fit/tool_test.cpp (bad options, empty
// and NaN OFF, missing mesh, seeds off the mesh), tests/bind/file_test.cpp (missing rig or mesh,
// --check of stale, truncated, bit-flipped and foreign bindings).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <functional>
#include <map>
#include <nlohmann/json.hpp>

#include "bad_input_case.h"
#include "pipeline.h"
#include "sweep/assets/mesh_io.h"
#include "tube.h"

namespace sweep::test {

TEST_P(BadInput, ExitCodeMessageAndNothingLeftBehind) {
  const Case& c = GetParam();
  const Workspace ws(std::string("bad-input-") + c.name);
  const std::string args = c.setup(ws);
  const auto before = snapshot(ws.work);
  const ToolRun r = run_tool(c.tool, args, ws.io);
  SCOPED_TRACE(std::string(c.tool) + " " + args + "\nstdout: " + r.out + "\nstderr: " + r.err);
  EXPECT_EQ(r.code, c.code);
  for (const std::string& e : c.expect) EXPECT_NE(r.err.find(e), std::string::npos) << e;
  const auto after = snapshot(ws.work);
  if (c.code != 0) {
    const auto lines = r.err_lines();
    if (c.one_line) {
      ASSERT_EQ(lines.size(), 1u);
      EXPECT_EQ(lines[0].rfind("error: ", 0), 0u);
    }
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(names(after), names(before));
    EXPECT_TRUE(after == before) << "an input file was changed";
  } else {
    for (const std::string& f : c.creates) EXPECT_TRUE(after.count(f)) << f;
    for (const auto& [name, bytes] : after) {
      EXPECT_EQ(name.find(".tmp"), std::string::npos) << "temporary left: " << name;
    }
  }
}

namespace {

// ---- meshes ----

const char* const kNanObj = "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n";
const char* const kInfOff = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 -inf 0\n3 0 1 2\n";
const char* const kPastObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 9\n";
const char* const kPastOff = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
const char* const kNoFacesObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
// What the readers used to drop or shift silently.
const char* const kObjIndexPast32Bits = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4294967298\n";
const char* const kObjFaceOfTwo = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n";
// Announces 4 vertices and 1 face; holds 3 and 1, so the face line would be vertex 3.
const char* const kPlyMoreVertices =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
// Announces 2 faces, holds 1.
const char* const kPlyMoreFaces =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
// Three vertices and one triangle (0, 1, 9): index 9 is past the vertices.
const char* const kGltfIndexPast =
    R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAkAAAA="}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
const std::string kBom = "\xEF\xBB\xBF";

// An invalid UTF-8 byte in a file name.
const std::string kBadUtf8 = "\xff";

Mesh tube_mesh(bool caps) {
  tube::TubeParams p;
  p.caps = caps;
  return tube::make_tube(p);
}

// The tube with a fin: a triangle on a side edge that two quads already share (3 faces on one
// edge), and a second, separate triangle touching the tube at one vertex only.
Mesh non_manifold_tube() {
  Mesh m = tube_mesh(true);
  const auto add = [&](std::vector<std::uint32_t> f) {
    m.face_vertices.insert(m.face_vertices.end(), f.begin(), f.end());
    m.face_offsets.push_back(static_cast<std::uint32_t>(m.face_vertices.size()));
  };
  const auto n = static_cast<std::uint32_t>(m.positions.size());
  m.positions.push_back(Vec3(0.3, 0, 0.5));
  m.positions.push_back(Vec3(0.3, 0.1, 0.6));
  m.positions.push_back(Vec3(0.3, -0.1, 0.6));
  const std::uint32_t ring = 16, seg = 24;  // ring 16 of 33 (mid), vertex 0 at +x
  add({ring * seg, (ring + 1) * seg, n});
  add({(ring + 2) * seg, n + 1, n + 2});
  return m;
}

const std::string kFitSeeds = " --name tube --root 0,0,0.02 --tip 0,0,1";

std::string fit_args(const Workspace& ws, const std::string& mesh, const std::string& rig = "new.rig.json") {
  return quoted(ws / mesh) + " -o " + quoted(ws / rig) + kFitSeeds;
}

std::vector<Case> fit_cases() {
  const char* fit = SWEEP_FIT_EXE;
  return {
      {"Fit_UnreadableMesh",
       fit,
       [](const Workspace& ws) {
         make_unreadable(ws / "locked.obj", slurp(ws / "tube.obj"));
         return fit_args(ws, "locked.obj");
       },
       2,
       {"locked.obj: "}},
      {"Fit_EmptyObj",
       fit,
       [](const Workspace& ws) {
         spit(ws / "empty.obj", "");
         return fit_args(ws, "empty.obj");
       },
       2,
       {"empty.obj: empty file"}},
      {"Fit_JsonSavedAsOff",
       fit,
       [](const Workspace& ws) { return fit_args(ws, "scene.json"); },
       3,
       {"scene.json: ", "unsupported mesh format '.json'"}},
      {"Fit_WrongFormatOff",
       fit,
       [](const Workspace& ws) {
         spit(ws / "text.off", kScene);
         return fit_args(ws, "text.off");
       },
       2,
       {"text.off: line 1: not an OFF file"}},
      {"Fit_UnknownExtension",
       fit,
       [](const Workspace& ws) {
         fs::copy_file(ws / "tube.obj", ws / "tube.sweepmesh");
         return fit_args(ws, "tube.sweepmesh");
       },
       3,
       {"tube.sweepmesh: unsupported mesh format '.sweepmesh'"}},
      {"Fit_ObjWithoutFaces",
       fit,
       [](const Workspace& ws) {
         spit(ws / "points.obj", kNoFacesObj);
         return fit_args(ws, "points.obj");
       },
       2,
       {"points.obj: no faces"}},
      {"Fit_NanObj",
       fit,
       [](const Workspace& ws) {
         spit(ws / "nan.obj", kNanObj);
         return fit_args(ws, "nan.obj");
       },
       2,
       {"nan.obj: line 2: vertex 1 has a non-finite coordinate (1, nan, 0)"}},
      {"Fit_InfOff",
       fit,
       [](const Workspace& ws) {
         spit(ws / "inf.off", kInfOff);
         return fit_args(ws, "inf.off");
       },
       2,
       {"inf.off: line 5: vertex 2 has a non-finite coordinate (0, -inf, 0)"}},
      {"Fit_ObjFacePastVertices",
       fit,
       [](const Workspace& ws) {
         spit(ws / "past.obj", kPastObj);
         return fit_args(ws, "past.obj");
       },
       2,
       {"past.obj: line 5: face 1 uses vertex 9 (1-based, as in the file), out of range (the mesh "
        "has 3 vertices)"}},
      {"Fit_OffFacePastVertices",
       fit,
       [](const Workspace& ws) {
         spit(ws / "past.off", kPastOff);
         return fit_args(ws, "past.off");
       },
       2,
       {"past.off: line 6: face 0 uses vertex 3, out of range (the mesh has 3 vertices)"}},
      {"Fit_OpenTubeFits",
       fit,
       [](const Workspace& ws) {
         assets::write_obj(ws / "open.obj", tube_mesh(false));
         return fit_args(ws, "open.obj") + " -k 6 -n 8";
       },
       0,
       {},
       {"new.rig.json"}},
      {"Fit_NonManifoldTubeFits",
       fit,
       [](const Workspace& ws) {
         assets::write_obj(ws / "fin.obj", non_manifold_tube());
         return fit_args(ws, "fin.obj") + " -k 6 -n 8";
       },
       0,
       {},
       {"new.rig.json"}},
      {"Fit_MalformedRigToUpdate",
       fit,
       [](const Workspace& ws) {
         spit(ws / "rig.json", "{\n  \"format\": \"sweep-rig\",\n  \"version\" 1\n}\n");
         return fit_args(ws, "tube.obj", "rig.json");
       },
       2,
       {"rig.json:3:13: syntax error"}},
      {"Fit_RigWithWrongType",
       fit,
       [](const Workspace& ws) {
         edit_json(ws / "rig.json", [](json& j) { j["sweeps"][0]["radial_samples"] = "8"; });
         return fit_args(ws, "tube.obj", "rig.json");
       },
       2,
       {"rig.json: /sweeps/0/radial_samples: must be a whole number, got \"8\""}},
      {"Fit_RigMissingSections",
       fit,
       [](const Workspace& ws) {
         edit_json(ws / "rig.json", [](json& j) { j["sweeps"][0].erase("sections"); });
         return fit_args(ws, "tube.obj", "rig.json");
       },
       2,
       {"rig.json: /sweeps/0: missing required member \"sections\""}},
      {"Fit_RigNegativeMass",
       fit,
       [](const Workspace& ws) {
         edit_json(ws / "rig.json", [](json& j) { j["sweeps"][0]["springs"]["positional"]["mass"] = -1; });
         return fit_args(ws, "tube.obj", "rig.json");
       },
       2,
       {"rig.json: /sweeps/0/springs/positional/mass: must be a positive number, got -1"}},
      {"Fit_RigUnknownMemberWarns",
       fit,
       [](const Workspace& ws) {
         edit_json(ws / "rig.json", [](json& j) { j["sweeps"][0]["colour"] = "green"; });
         return fit_args(ws, "tube.obj", "rig.json") + " -k 6 -n 8";
       },
       0,
       {"warning: ", "rig.json: /sweeps/0/colour: unknown member \"colour\" ignored"},
       {"rig.json"}},
      {"Fit_AxisFileBadLine",
       fit,
       [](const Workspace& ws) {
         spit(ws / "axis.txt", "0 0 0.02\n0 0.5\n0 0 1\n");
         return quoted(ws / "tube.obj") + " -o " + quoted(ws / "new.rig.json") + " --axis " + quoted(ws / "axis.txt");
       },
       2,
       {"axis.txt:2: expected X Y Z"}},
      {"Fit_UnknownOption",
       fit,
       [](const Workspace& ws) { return fit_args(ws, "tube.obj") + " --frobnicate"; },
       1,
       {"--frobnicate"}},
      {"Fit_OutputInMissingFolder",
       fit,
       [](const Workspace& ws) { return fit_args(ws, "tube.obj", "no/such/dir/rig.json"); },
       4,
       {"no/such/dir/rig.json: cannot create a file in"}},
      {"Fit_ReportInMissingFolderWritesNoRig",
       fit,
       [](const Workspace& ws) { return fit_args(ws, "tube.obj") + " --report " + quoted(ws / "missing" / "r.json"); },
       4,
       {"missing/r.json: cannot create a file in"}},
      {"Fit_ObjIndexPast32BitsRefused",
       fit,
       [](const Workspace& ws) {
         spit(ws / "wrap.obj", kObjIndexPast32Bits);
         return fit_args(ws, "wrap.obj");
       },
       2,
       {"wrap.obj: line 4: face 0 uses vertex 4294967298 (1-based, as in the file), out of range"}},
      {"Fit_ObjFaceOfTwoRefused",
       fit,
       [](const Workspace& ws) {
         spit(ws / "two.obj", kObjFaceOfTwo);
         return fit_args(ws, "two.obj");
       },
       2,
       {"two.obj: line 5: face 1 has 2 vertices (a face needs at least 3)"}},
      {"Fit_PlyAnnouncingMoreVerticesRefused",
       fit,
       [](const Workspace& ws) {
         spit(ws / "more.ply", kPlyMoreVertices);
         return fit_args(ws, "more.ply");
       },
       2,
       {"more.ply: line 13: vertex 3: expected 3 values, found 4"}},
      {"Fit_PlyAnnouncingMoreFacesRefused",
       fit,
       [](const Workspace& ws) {
         spit(ws / "more.ply", kPlyMoreFaces);
         return fit_args(ws, "more.ply");
       },
       2,
       {"more.ply: line 13: unexpected end of file: the header announces 2 face elements, the "
        "file holds 1"}},
      {"Fit_GltfIndexPastVerticesRefused",
       fit,
       [](const Workspace& ws) {
         spit(ws / "past.gltf", kGltfIndexPast);
         return fit_args(ws, "past.gltf");
       },
       2,
       {"past.gltf: mesh 0 primitive 0: index 2 is 9, past its 3 vertices"}},
      {"Fit_OffWithBomFits",
       fit,
       [](const Workspace& ws) {
         spit(ws / "bom.off", kBom + assets::off_bytes(assets::read_mesh(ws / "tube.obj")));
         return fit_args(ws, "bom.off") + " -k 6 -n 8";
       },
       0,
       {},
       {"new.rig.json"}},
      {"Fit_MeshIsFifo",
       fit,
       [](const Workspace& ws) {
         make_fifo(ws / "pipe.obj");
         return fit_args(ws, "pipe.obj");
       },
       2,
       {"pipe.obj: is not a regular file"}},
      {"Fit_RadialAboveLimit",
       fit,
       [](const Workspace& ws) { return fit_args(ws, "tube.obj") + " -n 4097"; },
       1,
       {"--radial: Value 4097 not in range 3 to 4096"}},
      {"Fit_SectionsAboveLimit",
       fit,
       [](const Workspace& ws) { return fit_args(ws, "tube.obj") + " -k 100001"; },
       1,
       {"--sections: Value 100001 not in range 2 to 100000"}},
      {"Fit_NameNotUtf8",
       fit,
       [](const Workspace& ws) {
         return quoted(ws / "tube.obj") + " -o " + quoted(ws / "new.rig.json") +
                " --root 0,0,0.02 --tip 0,0,1 --name '" + kBadUtf8 + "'";
       },
       1,
       {"--name is not valid UTF-8"}},
      {"Fit_RigOntoMesh",
       fit,
       [](const Workspace& ws) { return fit_args(ws, "tube.obj", "tube.obj"); },
       1,
       {"tube.obj is the same file as the mesh"}},
      {"Fit_ReportOntoMesh",
       fit,
       [](const Workspace& ws) { return fit_args(ws, "tube.obj") + " --report " + quoted(ws / "tube.obj"); },
       1,
       {"--report ", "is the same file as the mesh"}},
      {"Fit_ReportOntoRig",
       fit,
       [](const Workspace& ws) {
         return fit_args(ws, "tube.obj", "rig.json") + " --report " + quoted(ws / "./rig.json");
       },
       1,
       {"--report ", "is the same file as -o "}},
      {"Fit_OutputInReadOnlyFolder",
       fit,
       [](const Workspace& ws) {
         fs::create_directory(ws / "ro");
         const fs::path out = read_only_output(ws / "ro", "rig.json");
         return quoted(ws / "tube.obj") + " -o " + quoted(out) + kFitSeeds;
       },
       4,
       {"rig.json: cannot create a file in"}},
  };
}

// ---- rigs (sweep-bind reads them first) ----

std::string bind_args(const Workspace& ws) {
  return quoted(ws / "rig.json") + " -q";
}

std::vector<Case> bind_cases() {
  const char* bind = SWEEP_BIND_EXE;
  auto rig_case = [&](std::string name, std::function<void(json&)> change, int code, std::string expect) {
    return Case{std::move(name),
                bind,
                [change](const Workspace& ws) {
                  fs::remove(ws / "rig.bind");
                  edit_json(ws / "rig.json", change);
                  return bind_args(ws);
                },
                code,
                {std::move(expect)}};
  };
  auto mesh_case = [&](std::string name, std::string mesh_text, std::string expect) {
    return Case{std::move(name),
                bind,
                [mesh_text](const Workspace& ws) {
                  fs::remove(ws / "rig.bind");
                  spit(ws / "tube.obj", mesh_text);
                  return bind_args(ws);
                },
                2,
                {std::move(expect)}};
  };
  return {
      {"Bind_UnreadableRig",
       bind,
       [](const Workspace& ws) {
         fs::remove(ws / "rig.bind");
         make_unreadable(ws / "locked.json", slurp(ws / "rig.json"));
         return quoted(ws / "locked.json");
       },
       2,
       {"locked.json: "}},
      {"Bind_EmptyRig",
       bind,
       [](const Workspace& ws) {
         fs::remove(ws / "rig.bind");
         spit(ws / "rig.json", "");
         return bind_args(ws);
       },
       2,
       {"rig.json:1:1: empty file, expected JSON"}},
      {"Bind_MeshGivenAsRig",
       bind,
       [](const Workspace& ws) {
         fs::remove(ws / "rig.bind");
         return quoted(ws / "tube.obj");
       },
       2,
       {"tube.obj:1:1: syntax error"}},
      {"Bind_SceneGivenAsRig",
       bind,
       [](const Workspace& ws) {
         fs::remove(ws / "rig.bind");
         return quoted(ws / "scene.json") + " -o " + quoted(ws / "scene.bind");
       },
       2,
       {"scene.json: /format: must be \"sweep-rig\", got \"sweep-scene\""}},
      {"Bind_MalformedRig",
       bind,
       [](const Workspace& ws) {
         fs::remove(ws / "rig.bind");
         const std::string text = slurp(ws / "rig.json");
         spit(ws / "rig.json", text.substr(0, text.size() / 2));
         return bind_args(ws);
       },
       2,
       {"rig.json:", ": syntax error while parsing"}},
      rig_case(
          "Bind_SweepsNotAnArray", [](json& j) { j["sweeps"] = json::object(); }, 2,
          "rig.json: /sweeps: must be an array, got an object"),
      rig_case(
          "Bind_RigMissingVersion", [](json& j) { j.erase("version"); }, 2,
          "rig.json: (document): missing required member \"version\""),
      rig_case(
          "Bind_RigNewerVersion", [](json& j) { j["version"] = 5; }, 3,
          "rig.json: /version: rig format version 5 is not supported (this build reads versions 1 to 4)"),
      rig_case(
          "Bind_TipCutInAVersion1Rig",
          [](json& j) {
            j["sweeps"][0]["part"] = {{"root", {0, 0, 0}}, {"tip", {0, 0, 1}}, {"tip_cut", true}};
          },
          2, "rig.json: /sweeps/0/part/tip_cut: needs rig format version 2 (the file says version 1)"),
      rig_case(
          "Bind_RadialSamplesBelow3", [](json& j) { j["sweeps"][0]["radial_samples"] = 2; }, 2,
          "rig.json: /sweeps/0/radial_samples: must be between 3 and 4096, got 2"),
      rig_case(
          "Bind_NegativeSectionMass",
          [](json& j) {
            j["sweeps"][0]["sections"][2]["springs"] = {{"bend", {{"mass", -0.5}}}};
          },
          2, "rig.json: /sweeps/0/sections/2/springs/bend/mass: must be a positive number, got -0.5"),
      rig_case(
          "Bind_NegativeRadius", [](json& j) { j["sweeps"][0]["sections"][1]["radii"][3] = -0.1; }, 2,
          "rig.json: /sweeps/0/sections/1/radii/3: must be a positive number, got -0.1"),
      rig_case(
          "Bind_NotAUnitQuaternion",
          [](json& j) {
            j["sweeps"][0]["sections"][1]["rotation"] = {0, 0, 0, 2};
          },
          2, "rig.json: /sweeps/0/sections/1/rotation: must be a unit quaternion"),
      rig_case(
          "Bind_SectionsOutOfOrder", [](json& j) { j["sweeps"][0]["sections"][2]["t"] = 0.0; }, 2,
          "rig.json: /sweeps/0/sections/2/t: must be greater than the previous section's t"),
      rig_case(
          "Bind_MeshPathMissing", [](json& j) { j["mesh"] = "elsewhere/tube.obj"; }, 2,
          "elsewhere/tube.obj: no such file"),
      {"Bind_UnknownMemberWarns",
       bind,
       [](const Workspace& ws) {
         fs::remove(ws / "rig.bind");
         edit_json(ws / "rig.json", [](json& j) { j["author"] = "someone"; });
         return bind_args(ws);
       },
       0,
       {"warning: ", "rig.json: /author: unknown member \"author\" ignored"},
       {"rig.bind"}},
      mesh_case("Bind_MeshEmpty", "", "tube.obj: empty file"),
      mesh_case("Bind_MeshWithoutFaces", kNoFacesObj, "tube.obj: no faces"),
      mesh_case("Bind_MeshWithNan", kNanObj, "tube.obj: line 2: vertex 1 has a non-finite"),
      mesh_case("Bind_MeshFacePastVertices", kPastObj, "tube.obj: line 5: face 1 uses vertex 9"),
      {"Bind_CheckBindingOfAnotherRig",
       bind,
       [](const Workspace& ws) {
         fs::copy_file(ws / "rig.json", ws / "other.rig.json");
         edit_json(ws / "other.rig.json", [](json& j) { j["sweeps"][0]["name"] = "hose"; });
         return quoted(ws / "other.rig.json") + " --check " + quoted(ws / "rig.bind");
       },
       2,
       {"rig.bind: was made for another version of the rig (sweeps changed since binding); run "
        "sweep-bind again"}},
      {"Bind_CheckEmptyBinding",
       bind,
       [](const Workspace& ws) {
         spit(ws / "rig.bind", "");
         return quoted(ws / "rig.json") + " --check " + quoted(ws / "rig.bind");
       },
       2,
       {"rig.bind: truncated binding: 0 bytes"}},
      {"Bind_OutputInMissingFolder",
       bind,
       [](const Workspace& ws) {
         fs::remove(ws / "rig.bind");
         return bind_args(ws) + " -o " + quoted(ws / "missing" / "out.bind");
       },
       4,
       {"missing/out.bind: cannot create a file in"}},
      rig_case(
          "Bind_SectionTBeyondLimit", [](json& j) { j["sweeps"][0]["sections"][2]["t"] = 1e39; }, 2,
          "rig.json: /sweeps/0/sections/2/t: must be between -1e+09 and 1e+09, got 1e+39"),
      rig_case(
          "Bind_FrequencyBeyondLimit", [](json& j) { j["sweeps"][0]["springs"]["bend"]["frequency_hz"] = 1e160; }, 2,
          "rig.json: /sweeps/0/springs/bend/frequency_hz: must be between 0.001 and 10000, got "
          "1e+160"),
      rig_case(
          "Bind_MassBelowLimit", [](json& j) { j["sweeps"][0]["springs"]["radial"]["mass"] = 1e-12; }, 2,
          "rig.json: /sweeps/0/springs/radial/mass: must be between 1e-06 and 1e+06, got 1e-12"),
      rig_case(
          "Bind_RadiusBeyondLimit", [](json& j) { j["sweeps"][0]["sections"][1]["radii"][0] = 1e308; }, 2,
          "rig.json: /sweeps/0/sections/1/radii/0: must be between 0 and 1e+09, got 1e+308"),
      rig_case(
          "Bind_RadialSamplesBeyondLimit", [](json& j) { j["sweeps"][0]["radial_samples"] = 4097; }, 2,
          "rig.json: /sweeps/0/radial_samples: must be between 3 and 4096, got 4097"),
      mesh_case("Bind_MeshObjWithWrappingIndex", kObjIndexPast32Bits,
                "tube.obj: line 4: face 0 uses vertex 4294967298"),
      mesh_case("Bind_MeshObjFaceOfTwo", kObjFaceOfTwo, "tube.obj: line 5: face 1 has 2 vertices"),
      {"Bind_MeshIsFifo",
       bind,
       [](const Workspace& ws) {
         fs::remove(ws / "rig.bind");
         make_fifo(ws / "tube.obj");
         return bind_args(ws);
       },
       2,
       {"tube.obj: is not a regular file"}},
      {"Bind_OutputOntoRig",
       bind,
       [](const Workspace& ws) { return bind_args(ws) + " -o " + quoted(ws / "rig.json"); },
       1,
       {"the binding ", "rig.json is the same file as the rig"}},
      {"Bind_ReportOntoMesh",
       bind,
       [](const Workspace& ws) { return bind_args(ws) + " --report " + quoted(ws / "tube.obj"); },
       1,
       {"--report ", "is the same file as the mesh"}},
      {"Bind_ReportOntoBinding",
       bind,
       [](const Workspace& ws) {
         return bind_args(ws) + " -o " + quoted(ws / "b.bind") + " --report " + quoted(ws / "b.bind");
       },
       1,
       {"--report ", "is the same file as the binding"}},
      {"Bind_OutputInReadOnlyFolder",
       bind,
       [](const Workspace& ws) {
         fs::remove(ws / "rig.bind");
         fs::create_directory(ws / "ro");
         return bind_args(ws) + " -o " + quoted(read_only_output(ws / "ro", "out.bind"));
       },
       4,
       {"out.bind: cannot create a file in"}},
      {"Bind_ReportInMissingFolderWritesNoBinding",
       bind,
       [](const Workspace& ws) {
         fs::remove(ws / "rig.bind");
         return bind_args(ws) + " --report " + quoted(ws / "missing" / "report.json");
       },
       4,
       {"missing/report.json: cannot create a file in"}},
  };
}

// ---- scenes, bindings and outputs (sweep-sim) ----

std::string sim_args(const Workspace& ws, const std::string& out = "out.glb") {
  return quoted(ws / "rig.json") + " -s " + quoted(ws / "scene.json") + " -q -o " + quoted(ws / out);
}

std::vector<Case> sim_cases() {
  const char* sim = SWEEP_SIM_EXE;
  auto scene_case = [&](std::string name, std::function<void(json&)> change, int code, std::string expect) {
    return Case{std::move(name),
                sim,
                [change](const Workspace& ws) {
                  edit_json(ws / "scene.json", change);
                  return sim_args(ws);
                },
                code,
                {std::move(expect)}};
  };
  auto binding_case = [&](std::string name, std::function<void(std::string&)> change, std::string expect) {
    return Case{std::move(name),
                sim,
                [change](const Workspace& ws) {
                  std::string b = slurp(ws / "rig.bind");
                  change(b);
                  spit(ws / "rig.bind", b);
                  return sim_args(ws);
                },
                2,
                {std::move(expect)}};
  };
  return {
      {"Sim_MissingScene",
       sim,
       [](const Workspace& ws) {
         fs::remove(ws / "scene.json");
         return sim_args(ws);
       },
       2,
       {"scene.json: no such file"}},
      {"Sim_UnreadableScene",
       sim,
       [](const Workspace& ws) {
         make_unreadable(ws / "locked.json", kScene);
         return quoted(ws / "rig.json") + " -s " + quoted(ws / "locked.json") + " -q -o " + quoted(ws / "out.glb");
       },
       2,
       {"locked.json: "}},
      {"Sim_EmptyScene",
       sim,
       [](const Workspace& ws) {
         spit(ws / "scene.json", "");
         return sim_args(ws);
       },
       2,
       {"scene.json:1:1: empty file, expected JSON"}},
      {"Sim_MalformedScene",
       sim,
       [](const Workspace& ws) {
         spit(ws / "scene.json", "{\"format\": \"sweep-scene\",\n \"fps\": 10,,\n}");
         return sim_args(ws);
       },
       2,
       {"scene.json:2:12: syntax error while parsing object key - unexpected ','"}},
      {"Sim_RigWithoutSceneGivenAsScene",
       sim,
       [](const Workspace& ws) { return quoted(ws / "rig.json") + " -q -o " + quoted(ws / "out.glb"); },
       2,
       {"rig.json: (document): this rig file has no \"scene\"; give a scene file"}},
      {"Sim_SceneNotAnObject",
       sim,
       [](const Workspace& ws) {
         spit(ws / "scene.json", "[1, 2, 3]");
         return sim_args(ws);
       },
       2,
       {"scene.json: (document): must be a JSON object"}},
      scene_case(
          "Sim_FpsNotANumber", [](json& j) { j["fps"] = "ten"; }, 2, "scene.json: /fps: must be a number, got \"ten\""),
      scene_case(
          "Sim_FormatNotAString", [](json& j) { j["format"] = 7; }, 2, "scene.json: /format: must be a string, got 7"),
      scene_case(
          "Sim_MissingDuration", [](json& j) { j.erase("duration"); }, 2,
          "scene.json: (document): missing required member \"duration\""),
      scene_case(
          "Sim_NegativeFps", [](json& j) { j["fps"] = -10; }, 2,
          "scene.json: /fps: must be a positive number, got -10"),
      scene_case(
          "Sim_ColliderOfNoSize",
          [](json& j) { j["colliders"] = json::parse(R"([{"shape": "sphere", "center": [0, 0, 0], "radius": 0}])"); },
          2, "scene.json: /colliders/0/radius: must be a positive number, got 0"),
      scene_case(
          "Sim_FlatBoxCollider",
          [](json& j) {
            j["colliders"] = json::parse(R"([{"shape": "box", "center": [0, 0, 0], "half_size": [1, 1, 0]}])");
          },
          2,
          "scene.json: /colliders/0/half_size: every half size must be positive (a plate is a thin box, not a flat "
          "one)"),
      scene_case(
          "Sim_PlaneWithoutNormal",
          [](json& j) {
            j["colliders"] = json::parse(R"([{"shape": "plane", "point": [0, 0, 0], "normal": [0, 0, 0]}])");
          },
          2, "scene.json: /colliders/0/normal: must not be zero: it points out of the solid side"),
      scene_case(
          "Sim_BodyColliderOfNoSpheres", [](json& j) { j["body_collider"] = json::parse(R"({"spheres": 0})"); }, 2,
          "scene.json: /body_collider/spheres: must be between 1 and 256, got 0"),
      scene_case(
          "Sim_ForceBeyondTheTip", [](json& j) { j["forces"][0]["t"] = 1.5; }, 2,
          "scene.json: /forces/0/t: must be between 0 (root) and 1 (tip), got 1.5"),
      scene_case(
          "Sim_ForceOnUnknownSweep", [](json& j) { j["forces"][0]["sweep"] = "tail"; }, 2,
          "scene.json: /forces/0/sweep: the rig has no sweep named \"tail\""),
      scene_case(
          "Sim_ForceEndsBeforeItStarts", [](json& j) { j["forces"][0]["end"] = -1; }, 2,
          "scene.json: /forces/0/end: must not be before \"start\""),
      scene_case(
          "Sim_SceneNewerVersion", [](json& j) { j["version"] = 2; }, 3,
          "scene.json: /version: scene format version 2 is not supported"),
      {"Sim_UnknownMemberWarns",
       sim,
       [](const Workspace& ws) {
         edit_json(ws / "scene.json", [](json& j) { j["forces"][0]["colour"] = "red"; });
         return sim_args(ws);
       },
       0,
       {"warning: ", "scene.json: /forces/0/colour: unknown member \"colour\" ignored"},
       {"out.glb"}},
      {"Sim_RigNegativeMass",
       sim,
       [](const Workspace& ws) {
         edit_json(ws / "rig.json", [](json& j) { j["sweeps"][0]["springs"]["twist"]["mass"] = -2; });
         return sim_args(ws);
       },
       2,
       {"rig.json: /sweeps/0/springs/twist/mass: must be a positive number, got -2"}},
      {"Sim_MissingBinding",
       sim,
       [](const Workspace& ws) {
         fs::remove(ws / "rig.bind");
         return sim_args(ws);
       },
       2,
       {"rig.bind: no such file"}},
      binding_case(
          "Sim_TruncatedBinding", [](std::string& b) { b.resize(b.size() - 9); },
          "rig.bind: truncated binding: the header announces"),
      binding_case(
          "Sim_BitFlippedBinding", [](std::string& b) { b[b.size() / 3] ^= 0x10; },
          "rig.bind: corrupt binding: checksum mismatch"),
      binding_case(
          "Sim_BindingWithTrailingBytes", [](std::string& b) { b += "extra"; },
          "rig.bind: corrupt binding: 5 unexpected bytes after the payload"),
      binding_case(
          "Sim_NotABinding", [](std::string& b) { b.replace(0, 4, "glTF"); },
          "rig.bind: not a sweep binding file (wrong magic bytes)"),
      {"Sim_BindingOfAnotherMesh",
       sim,
       [](const Workspace& ws) {
         Mesh m = assets::read_mesh(ws / "tube.obj");
         m.positions[5].z() += 1e-3;
         assets::write_obj(ws / "tube.obj", m);
         return sim_args(ws);
       },
       2,
       {"rig.bind: made for a mesh with other vertex positions (the mesh changed since binding); "
        "run sweep-bind again"}},
      {"Sim_BindingOfAnotherRig",
       sim,
       [](const Workspace& ws) {
         edit_json(ws / "rig.json", [](json& j) {
           j["sweeps"][0]["sections"][1]["radii"][0] = j["sweeps"][0]["sections"][1]["radii"][0].get<double>() * 1.05;
         });
         return sim_args(ws);
       },
       2,
       {"rig.bind: was made for another version of the rig (sweeps changed since binding); run "
        "sweep-bind again"}},
      {"Sim_MeshWithNan",
       sim,
       [](const Workspace& ws) {
         spit(ws / "tube.obj", kNanObj);
         return sim_args(ws);
       },
       2,
       {"tube.obj: line 2: vertex 1 has a non-finite coordinate"}},
      {"Sim_UnsupportedOutput", sim, [](const Workspace& ws) { return sim_args(ws, "out.fbx"); }, 3, {"out.fbx"}},
      {"Sim_GlbInMissingFolder",
       sim,
       [](const Workspace& ws) { return sim_args(ws, "missing/out.glb"); },
       4,
       {"missing/out.glb: cannot create a file in"}},
      {"Sim_Pc2InMissingFolder",
       sim,
       [](const Workspace& ws) { return sim_args(ws, "missing/out.pc2"); },
       4,
       {"missing/out.pc2: cannot create a file in"}},
      {"Sim_ObjInMissingFolder",
       sim,
       [](const Workspace& ws) { return sim_args(ws, "missing/out.obj"); },
       4,
       {"missing/out.obj: cannot create a file in"}},
      {"Sim_GlbInReadOnlyFolder",
       sim,
       [](const Workspace& ws) {
         fs::create_directory(ws / "ro");
         return sim_args(ws, fs::relative(read_only_output(ws / "ro", "out.glb"), ws.work).string());
       },
       4,
       {"out.glb: cannot create a file in"}},
      {"Sim_GoodGlbAndPc2InMissingFolderWriteNeither",
       sim,
       [](const Workspace& ws) { return sim_args(ws, "out.glb") + " -o " + quoted(ws / "missing" / "out.pc2"); },
       4,
       {"missing/out.pc2: cannot create a file in"}},
      {"Sim_ReportInMissingFolder",
       sim,
       [](const Workspace& ws) { return sim_args(ws, "out.pc2") + " --report " + quoted(ws / "missing" / "r.json"); },
       4,
       {"missing/r.json: cannot create a file in"}},
      {"Sim_DivergesWritesNothing",
       sim,
       [](const Workspace& ws) {
         edit_json(ws / "rig.json", [](json& j) { j["sweeps"][0]["springs"]["bend"]["frequency_hz"] = 1000; });
         // Springs are not part of the binding's rig hash: the binding still matches.
         edit_json(ws / "scene.json", [](json& j) {
           j["integrator"] = "semi-implicit-euler";
           j["substeps"] = 1;
           j["forces"][0]["vector"] = {0, 100, 0};
         });
         return sim_args(ws, "out.pc2");
       },
       5,
       {"the simulation diverged: sweep \"tube\""}},
      scene_case(
          "Sim_FpsBelowLimit", [](json& j) { j["fps"] = 5e-324; }, 2,
          "scene.json: /fps: must be between 0.001 and 10000, got 5e-324"),
      scene_case(
          "Sim_TooManyFrames",
          [](json& j) {
            j["duration"] = 86400;
            j["fps"] = 10000;
          },
          2, "scene.json: /fps: duration × fps makes more than 1000000 frames"),
      scene_case(
          "Sim_ForceBeyondLimit",
          [](json& j) {
            j["forces"][0]["vector"] = {0, 1e300, 0};
          },
          2, "scene.json: /forces/0/vector: a force of at most 1e+09 N"),
      {"Sim_ForceAfterTheEndWarns",
       sim,
       [](const Workspace& ws) {
         edit_json(ws / "scene.json", [](json& j) {
           j["forces"][0]["start"] = 5;
           j["forces"][0]["end"] = 6;
         });
         return sim_args(ws);
       },
       0,
       {"warning: ",
        "scene.json: /forces/0/start: the force starts after the scene ends "
        "(duration 0.5 s): it never acts"},
       {"out.glb"}},
      {"Sim_ExactRunawayIsBadInput",
       sim,
       [](const Workspace& ws) {
         edit_json(ws / "rig.json", [](json& j) {
           j["sweeps"][0]["springs"]["bend"] = {{"mass", 1e-6}, {"frequency_hz", 1e-3}};
         });
         edit_json(ws / "scene.json", [](json& j) { j["forces"][0]["vector"] = {0, 1e9, 0}; });
         return sim_args(ws, "out.pc2");
       },
       2,
       {"the scene's forces are far too large for its springs"}},
      {"Sim_SceneIsFifo",
       sim,
       [](const Workspace& ws) {
         make_fifo(ws / "scene.json");
         return sim_args(ws);
       },
       2,
       {"scene.json: is not a regular file"}},
      {"Sim_SceneAboveSizeLimit",
       sim,
       [](const Workspace& ws) {
         fs::resize_file(ws / "scene.json", 100u << 20);  // sparse: no 100 MB written
         return sim_args(ws);
       },
       2,
       {"scene.json: 104857600 bytes, more than the limit of 67108864"}},
      {"Sim_SceneNameNotUtf8",
       sim,
       [](const Workspace& ws) {
         fs::rename(ws / "scene.json", ws / ("s" + kBadUtf8 + ".json"));
         return quoted(ws / "rig.json") + " -s " + quoted(ws / ("s" + kBadUtf8 + ".json")) + " -q -o " +
                quoted(ws / "out.glb");
       },
       1,
       {"the scene file name is not valid UTF-8"}},
      {"Sim_ReportEmptyName",
       sim,
       [](const Workspace& ws) { return sim_args(ws) + " --report ''"; },
       1,
       {"--report", "the file name is empty"}},
      {"Sim_ReportOntoScene",
       sim,
       [](const Workspace& ws) { return sim_args(ws) + " --report " + quoted(ws / "scene.json"); },
       1,
       {"--report ", "is the same file as the scene"}},
      {"Sim_ReportOntoOutput",
       sim,
       [](const Workspace& ws) { return sim_args(ws) + " --report " + quoted(ws / "out.glb"); },
       1,
       {"--report ", "is the same file as -o "}},
      {"Sim_TwoOutputsOneFile",
       sim,
       [](const Workspace& ws) { return sim_args(ws, "out.pc2") + " -o " + quoted(ws / "./out.pc2"); },
       1,
       {"is the same file as -o "}},
      {"Sim_ObjFrameOntoMesh",
       sim,
       [](const Workspace& ws) {
         fs::rename(ws / "tube.obj", ws / "m_0000.obj");
         edit_json(ws / "rig.json", [](json& j) { j["mesh"] = "m_0000.obj"; });
         return sim_args(ws, "m.obj");
       },
       1,
       {"m_0000.obj is the same file as the mesh"}},
      {"Sim_OutputOntoFifo",
       sim,
       [](const Workspace& ws) {
         make_fifo(ws / "out.pc2");
         return sim_args(ws, "out.pc2");
       },
       4,
       {"out.pc2: is a FIFO; outputs replace regular files only"}},
      {"Sim_OutputOntoSymlink",
       sim,
       [](const Workspace& ws) {
         spit(ws / "target.pc2", "keep me");
         fs::create_symlink("target.pc2", ws / "out.pc2");
         return sim_args(ws, "out.pc2");
       },
       4,
       {"out.pc2: is a symbolic link; outputs replace regular files only"}},
      {"Sim_LongOutputName",
       sim,
       [](const Workspace& ws) { return sim_args(ws, std::string(245, 'a') + ".glb"); },
       0,
       {},
       {std::string(245, 'a') + ".glb"}},
      {"Sim_ThreadsZeroIsUsage",
       sim,
       [](const Workspace& ws) { return sim_args(ws) + " --threads 0"; },
       1,
       {"--threads"}},
  };
}

// ---- sweep-tube (writes only) ----

std::vector<Case> tube_cases() {
  const char* tube = SWEEP_TUBE_EXE;
  return {
      {"Tube_OutputInMissingFolder",
       tube,
       [](const Workspace& ws) { return "-q -o " + quoted(ws / "missing" / "t.obj"); },
       4,
       {"missing/t.obj: cannot create a file in"}},
      {"Tube_OutputInReadOnlyFolder",
       tube,
       [](const Workspace& ws) {
         fs::create_directory(ws / "ro");
         return "-q -o " + quoted(read_only_output(ws / "ro", "t.off"));
       },
       4,
       {"t.off: cannot create a file in"}},
      {"Tube_UnwritableFormat",
       tube,
       [](const Workspace& ws) { return "-q -o " + quoted(ws / "t.stl"); },
       1,
       {"t.stl: the extension must be .obj, .off or .ply"}},
      {"Tube_TwoSegments",
       tube,
       [](const Workspace& ws) { return "-q --segments 2 -o " + quoted(ws / "t.obj"); },
       1,
       {"--segments must be at least 3 (got 2)"}},
      {"Tube_OneRing",
       tube,
       [](const Workspace& ws) { return "-q --rings 1 -o " + quoted(ws / "t.obj"); },
       1,
       {"--rings must be at least 2 (got 1)"}},
  };
}

INSTANTIATE_TEST_SUITE_P(Fit, BadInput, testing::ValuesIn(fit_cases()), case_name);
INSTANTIATE_TEST_SUITE_P(Bind, BadInput, testing::ValuesIn(bind_cases()), case_name);
INSTANTIATE_TEST_SUITE_P(Sim, BadInput, testing::ValuesIn(sim_cases()), case_name);
INSTANTIATE_TEST_SUITE_P(Tube, BadInput, testing::ValuesIn(tube_cases()), case_name);

}  // namespace
}  // namespace sweep::test
