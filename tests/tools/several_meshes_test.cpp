// A rig over several meshes of one file: a walker whose body and two legs are three meshes of one
// .glb (each under its own node, placed by its translation), written by the test. sweep-fit --mesh
// given three times reads them as one mesh in world space (Body's vertices, then LegL's, then
// LegR's: the file's order, whatever order they were named in), as --list and --all read them
// when no --mesh is given; --list finds each leg once, from
// the body to the foot; --all fits both, sweep-bind binds them and a push on one leg bakes a .pc2
// in which the body's vertices never move, and a .glb that keeps all three meshes and nodes, passes
// the Khronos validator, and whose morphed positions are the .pc2's. A rig whose mesh was renamed
// since is refused, naming it.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "fit/creatures.h"
#include "glb_file.h"
#include "pipeline.h"
#include "textured_asset.h"

namespace sweep::test {
namespace {

using Json = nlohmann::json;
using Vec3 = Eigen::Vector3d;

// The walker's three pieces as the file holds them: local positions (float, as stored) and the
// node's translation.
struct Piece {
  std::string name;
  Vec3 translation;
  std::vector<float> local;  // 3 a vertex
  std::vector<std::uint32_t> triangles;
  // World position of vertex v as the importer reads it: the translation (a float in assimp's node
  // matrix) added to the float.
  Vec3 world(std::size_t v) const {
    return translation.cast<float>().cast<double>() + Vec3(local[3 * v], local[3 * v + 1], local[3 * v + 2]);
  }
  std::size_t vertices() const { return local.size() / 3; }
};

struct LegsAsset {
  Walker walker;              // hips and feet in world space
  std::vector<Piece> pieces;  // Body, LegL, LegR: the file's order
};

// make_walker(1, false): the body ellipsoid (its first 384 faces), then two legs of equal size.
LegsAsset legs_asset() {
  LegsAsset a;
  a.walker = make_walker(1, false);
  const Mesh& m = a.walker.mesh;
  const std::size_t body_vertices = 2 + 15 * 24, body_faces = 24 * 16;
  const std::size_t leg_vertices = (m.vertex_count() - body_vertices) / 2;
  const std::size_t starts[] = {0, body_vertices, body_vertices + leg_vertices, m.vertex_count()};
  const Vec3 origins[] = {Vec3(0, 0.8, 0), a.walker.hips[0], a.walker.hips[1]};
  const char* names[] = {"Body", "LegL", "LegR"};
  for (int k = 0; k < 3; ++k) {
    Piece p;
    p.name = names[k];
    p.translation = origins[k];
    for (std::size_t v = starts[k]; v < starts[k + 1]; ++v) {
      const Vec3 local = m.positions[v] - p.translation;
      for (int c = 0; c < 3; ++c) p.local.push_back(static_cast<float>(local[c]));
    }
    a.pieces.push_back(std::move(p));
  }
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    const std::uint32_t begin = m.face_offsets[f], end = m.face_offsets[f + 1];
    const std::uint32_t first = m.face_vertices[begin];
    const int k = f < body_faces ? 0 : first < starts[2] ? 1 : 2;
    const auto base = static_cast<std::uint32_t>(starts[k]);
    for (std::uint32_t c = begin + 1; c + 1 < end; ++c) {
      a.pieces[k].triangles.insert(a.pieces[k].triangles.end(),
                                   {first - base, m.face_vertices[c] - base, m.face_vertices[c + 1] - base});
    }
  }
  return a;
}

// The asset as a .glb whose nodes (and meshes) have `names` (Body, LegL, LegR by default).
void write_legs_glb(const LegsAsset& a, const fs::path& file, std::vector<std::string> names = {}) {
  if (names.empty()) names = {"Body", "LegL", "LegR"};
  std::string bin;
  Json views = Json::array(), accessors = Json::array(), nodes = Json::array(), meshes = Json::array();
  auto add = [&](const void* data, std::size_t bytes, int component, const char* type, std::size_t count, int target) {
    views.push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}, {"target", target}});
    bin.append(static_cast<const char*>(data), bytes);
    accessors.push_back(
        {{"bufferView", views.size() - 1}, {"componentType", component}, {"count", count}, {"type", type}});
    return accessors.size() - 1;
  };
  for (std::size_t k = 0; k < a.pieces.size(); ++k) {
    const Piece& p = a.pieces[k];
    const std::size_t position = add(p.local.data(), 4 * p.local.size(), 5126, "VEC3", p.vertices(), 34962);
    Json lo = Json::array(), hi = Json::array();
    for (int c = 0; c < 3; ++c) {
      float l = p.local[c], h = p.local[c];
      for (std::size_t i = c; i < p.local.size(); i += 3) l = std::min(l, p.local[i]), h = std::max(h, p.local[i]);
      lo.push_back(l);
      hi.push_back(h);
    }
    accessors[position]["min"] = lo;
    accessors[position]["max"] = hi;
    const std::size_t indices =
        add(p.triangles.data(), 4 * p.triangles.size(), 5125, "SCALAR", p.triangles.size(), 34963);
    meshes.push_back(
        {{"name", names[k]}, {"primitives", {{{"attributes", {{"POSITION", position}}}, {"indices", indices}}}}});
    nodes.push_back(
        {{"name", names[k]}, {"mesh", k}, {"translation", {p.translation.x(), p.translation.y(), p.translation.z()}}});
  }
  const Json doc = {{"asset", {{"version", "2.0"}, {"generator", "sweep tests: legs as meshes"}}},
                    {"scene", 0},
                    {"scenes", {{{"nodes", {0, 1, 2}}}}},
                    {"nodes", nodes},
                    {"meshes", meshes},
                    {"accessors", accessors},
                    {"bufferViews", views},
                    {"buffers", {{{"byteLength", bin.size()}}}}};
  spit(file, glb_bytes(doc, bin));
}

const std::string kMeshes = " --mesh LegR --mesh Body --mesh LegL";  // any order: the file's is kept

// The asset fitted (both legs, --all) and bound once per build of the tools: legs.glb, rig.json,
// rig.bind, fit.json (sweep-fit's report). The paper's springs (--springs): the bakes' pushes are
// sized for them.
fs::path legs_pipeline() {
  return cached_dir("legs-glb", [](const fs::path& dir, const fs::path& io) {
    write_legs_glb(legs_asset(), dir / "legs.glb");
    const ToolRun fit = run_tool(SWEEP_FIT_EXE,
                                 quoted(dir / "legs.glb") + kMeshes + " --all -o " + quoted(dir / "rig.json") +
                                     " -k 16 -n 12 --springs --report " + quoted(dir / "fit.json"),
                                 io);
    ASSERT_EQ(fit.code, 0) << fit.err;
    const ToolRun bind = run_tool(SWEEP_BIND_EXE, quoted(dir / "rig.json") + " -q", io);
    ASSERT_EQ(bind.code, 0) << bind.err;
  });
}

TEST(SeveralMeshes, ListFindsEachLegMeshOnceFromTheBodyToTheFoot) {
  const fs::path dir = scratch_dir("several-meshes-list");
  const LegsAsset a = legs_asset();
  write_legs_glb(a, dir / "legs.glb");
  const ToolRun r = run_tool(
      SWEEP_FIT_EXE, quoted(dir / "legs.glb") + kMeshes + " --list --report " + quoted(dir / "parts.json"), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("names go by up +Y (glTF is +Y up by its specification"), std::string::npos) << r.out;
  const Json parts = Json::parse(slurp(dir / "parts.json"));
  EXPECT_EQ(parts["up"]["axis"], "+Y");
  ASSERT_EQ(parts["parts"].size(), 2u) << r.out;  // the legs, not the body
  std::set<int> legs;
  for (const Json& p : parts["parts"]) {
    const Vec3 tip(p["tip"][0], p["tip"][1], p["tip"][2]), root(p["root"][0], p["root"][1], p["root"][2]);
    const int leg = (tip - a.walker.feet[0]).norm() < (tip - a.walker.feet[1]).norm() ? 0 : 1;
    legs.insert(leg);
    EXPECT_LT((tip - a.walker.feet[leg]).norm(), 2 * Walker::kFootRadius) << p.dump() << ": its tip is its foot";
    EXPECT_LT((root - a.walker.hips[leg]).norm(), 3 * Walker::kLegRadius) << p.dump() << ": its root is its hip";
    EXPECT_EQ(p["name"].get<std::string>().substr(0, 3), "leg") << p.dump();
    // The tip vertex is one of that leg mesh's vertices: Body's come first, then LegL's, LegR's.
    const std::size_t first = a.pieces[0].vertices() + (leg == 0 ? 0 : a.pieces[1].vertices());
    EXPECT_GE(p["tip_vertex"].get<std::size_t>(), first);
    EXPECT_LT(p["tip_vertex"].get<std::size_t>(), first + a.pieces[1 + leg].vertices());
  }
  EXPECT_EQ(legs.size(), 2u) << "each leg once";
  // --mesh all: every mesh of the file, in its order: the same mesh, so the same parts.
  const ToolRun all = run_tool(
      SWEEP_FIT_EXE, quoted(dir / "legs.glb") + " --mesh all --list --report " + quoted(dir / "all.json"), dir);
  ASSERT_EQ(all.code, 0) << all.err;
  EXPECT_EQ(Json::parse(slurp(dir / "all.json"))["parts"], parts["parts"]);
  // --export-obj: that mesh as read, every vertex where the importer puts it, in that order; it
  // goes with no other mode.
  const ToolRun exported = run_tool(
      SWEEP_FIT_EXE, quoted(dir / "legs.glb") + " --mesh all -q --export-obj " + quoted(dir / "legs.obj"), dir);
  ASSERT_EQ(exported.code, 0) << exported.err;
  std::istringstream obj(slurp(dir / "legs.obj"));
  std::size_t v = 0, wrong = 0;
  for (std::string line; std::getline(obj, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream xyz(line.substr(2));
    Vec3 p;
    xyz >> p.x() >> p.y() >> p.z();
    const std::size_t k = v < a.pieces[0].vertices() ? 0 : v < a.pieces[0].vertices() + a.pieces[1].vertices() ? 1 : 2;
    const std::size_t i = v - (k == 0   ? 0
                               : k == 1 ? a.pieces[0].vertices()
                                        : a.pieces[0].vertices() + a.pieces[1].vertices());
    wrong += p != a.pieces[k].world(i);
    ++v;
  }
  EXPECT_EQ(v, a.pieces[0].vertices() + a.pieces[1].vertices() + a.pieces[2].vertices());
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(
      run_tool(SWEEP_FIT_EXE, quoted(dir / "legs.glb") + " --list --export-obj " + quoted(dir / "x.obj"), dir).code, 1);
}

// No --mesh: --list and --all search every mesh of the file as one (not the largest, a leg alone),
// say so in a note listing them, and find both legs as --mesh all does; the rig records all three
// meshes.
TEST(SeveralMeshes, ListAndAllWithoutMeshSearchEveryMeshOfTheFile) {
  const fs::path dir = scratch_dir("several-meshes-default");
  const LegsAsset a = legs_asset();
  write_legs_glb(a, dir / "legs.glb");
  const ToolRun named = run_tool(
      SWEEP_FIT_EXE, quoted(dir / "legs.glb") + " --mesh all --list --report " + quoted(dir / "all.json"), dir);
  ASSERT_EQ(named.code, 0) << named.err;
  const ToolRun r =
      run_tool(SWEEP_FIT_EXE, quoted(dir / "legs.glb") + " --list --report " + quoted(dir / "parts.json"), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json parts = Json::parse(slurp(dir / "parts.json"))["parts"];
  EXPECT_EQ(parts.size(), 2u) << r.out;
  EXPECT_EQ(parts, Json::parse(slurp(dir / "all.json"))["parts"]);
  EXPECT_NE(r.err.find("note: " + (dir / "legs.glb").string() + " holds 3 meshes; searched them all as one (" +
                       std::to_string(a.pieces[0].vertices() + a.pieces[1].vertices() + a.pieces[2].vertices()) +
                       " vertices; --mesh NAME takes one): 'Body' "),
            std::string::npos)
      << r.err;
  const ToolRun all =
      run_tool(SWEEP_FIT_EXE, quoted(dir / "legs.glb") + " --all -q --springs -o " + quoted(dir / "rig.json"), dir);
  ASSERT_EQ(all.code, 0) << all.err;
  const Json rig = Json::parse(slurp(dir / "rig.json"));
  EXPECT_EQ(rig["mesh_name"], (Json{"Body", "LegL", "LegR"}));
  EXPECT_EQ(rig["sweeps"].size(), 2u);
}

TEST(SeveralMeshes, TheRigNamesItsMeshesInTheFilesOrderAndABakeMovesOnlyTheLegs) {
  const fs::path top = scratch_dir("several-meshes-bake");
  const fs::path work = top / "work", io = top / "io";
  fs::create_directories(io);
  fs::copy(legs_pipeline(), work, fs::copy_options::recursive);
  const LegsAsset a = legs_asset();
  const Json rig = Json::parse(slurp(work / "rig.json"));
  EXPECT_EQ(rig["version"], 4);
  EXPECT_EQ(rig["mesh_name"], Json::array({"Body", "LegL", "LegR"}));
  ASSERT_EQ(rig["sweeps"].size(), 2u);
  EXPECT_EQ(Json::parse(slurp(work / "fit.json"))["mesh_summary"]["mesh_name"], Json::array({"Body", "LegL", "LegR"}));

  // A sideways push near the first leg's foot.
  spit(work / "scene.json", R"({"format": "sweep-scene", "version": 1, "duration": 0.5, "fps": 10,
    "forces": [{"sweep": ")" + rig["sweeps"][0]["name"].get<std::string>() +
                                R"(", "t": 1, "theta": 0, "vector": [30, 0, 0], "start": 0, "end": 0.2}]})");
  const ToolRun bake = run_tool(SWEEP_SIM_EXE,
                                quoted(work / "rig.json") + " --scene " + quoted(work / "scene.json") + " -q -o " +
                                    quoted(work / "legs.pc2") + " -o " + quoted(work / "baked.glb"),
                                io);
  ASSERT_EQ(bake.code, 0) << bake.err;

  // The .pc2: every vertex of the three meshes, in world space; the body's exactly where it rests.
  const std::string pc2 = slurp(work / "legs.pc2");
  std::int32_t frames = 0;
  std::memcpy(&frames, pc2.data() + 28, 4);
  ASSERT_EQ(frames, 6);
  const std::size_t body = a.pieces[0].vertices();
  double leg_moved = 0;
  std::vector<std::vector<float>> frame_positions;
  for (int k = 0; k < frames; ++k) {
    int points = 0;
    frame_positions.push_back(pc2_frame(pc2, k, &points));
    const std::vector<float>& f = frame_positions.back();
    ASSERT_EQ(static_cast<std::size_t>(points), body + a.pieces[1].vertices() + a.pieces[2].vertices());
    std::size_t v = 0;
    for (const Piece& piece : a.pieces) {
      for (std::size_t i = 0; i < piece.vertices(); ++i, ++v) {
        const Vec3 rest = piece.world(i);
        const Vec3 got(f[3 * v], f[3 * v + 1], f[3 * v + 2]);
        if (&piece == &a.pieces[0]) {
          // Still: the same bits in every frame, and where it rests (to float rounding: the bake
          // adds in float what the importer added in double).
          const std::vector<float>& first = frame_positions.front();
          for (int c = 0; c < 3; ++c)
            ASSERT_EQ(f[3 * v + c], first[3 * v + c]) << "body vertex " << v << " frame " << k;
          ASSERT_LT((got - rest).norm(), 1e-7) << "body vertex " << v;
        } else {
          leg_moved = std::max(leg_moved, (got - rest).norm());
        }
      }
    }
  }
  EXPECT_GT(leg_moved, Walker::kLegRadius) << "the pushed leg swings";

  // The .glb: the input's three nodes and meshes, names and order kept; targets on the meshes that
  // moved, none on the body; node translation + POSITION + target k is the .pc2's frame k.
  const Glb out = read_glb(work / "baked.glb");
  ASSERT_EQ(out.json["meshes"].size(), 3u);
  ASSERT_EQ(out.json["nodes"].size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(out.json["meshes"][k]["name"], a.pieces[k].name);
    EXPECT_EQ(out.json["nodes"][k]["name"], a.pieces[k].name);
    EXPECT_EQ(out.json["nodes"][k]["mesh"], k);
  }
  EXPECT_FALSE(out.json["meshes"][0]["primitives"][0].contains("targets")) << "the body never moves";
  double worst = 0;
  int morphed = 0;
  std::size_t base = body;
  for (std::size_t m = 1; m < 3; ++m) {
    const Json& prim = out.json["meshes"][m]["primitives"][0];
    const Piece& piece = a.pieces[m];
    if (prim.contains("targets")) {
      ++morphed;
      ASSERT_EQ(prim["targets"].size(), 6u);
      const std::vector<float> rest = floats(out.json, out.bin, prim["attributes"]["POSITION"], 3);
      ASSERT_EQ(rest, piece.local);
      for (int k = 0; k < frames; ++k) {
        const std::vector<float> d = floats(out.json, out.bin, prim["targets"][k]["POSITION"], 3);
        for (std::size_t i = 0; i < piece.vertices(); ++i) {
          const Vec3 got = piece.world(i) + Vec3(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
          const std::vector<float>& f = frame_positions[static_cast<std::size_t>(k)];
          worst = std::max(worst, (got - Vec3(f[3 * (base + i)], f[3 * (base + i) + 1], f[3 * (base + i) + 2])).norm());
        }
      }
    }
    base += piece.vertices();
  }
  EXPECT_GE(morphed, 1) << "the pushed leg's mesh has targets";
  EXPECT_LT(worst, 1e-6) << "morphed positions against the .pc2 (the walker is 3 units across: float precision)";
  // (The Khronos validator passes the .glb of the moving body below, which holds these targets and
  // the nodes' keys: run once for both.)
}

// A moving body carries every mesh of the rig: in the .glb each of the three nodes gets the body's
// keys (the still body no morph weights), and node transform · (POSITION + target) at each frame's
// keys is the .pc2's frame, the body's vertices included; the Khronos validator finds no error.
TEST(SeveralMeshes, AMovingBodyCarriesEveryMeshOfTheRigInTheGlb) {
  const fs::path top = scratch_dir("several-meshes-body");
  const fs::path work = top / "work", io = top / "io";
  fs::create_directories(io);
  fs::copy(legs_pipeline(), work, fs::copy_options::recursive);
  const LegsAsset a = legs_asset();
  const Json rig = Json::parse(slurp(work / "rig.json"));
  spit(work / "scene.json", R"({"format": "sweep-scene", "version": 1, "duration": 0.5, "fps": 10,
    "body": {"interpolation": "linear", "keys": [{"time": 0, "translation": [0, 0, 0]},
                                                 {"time": 0.5, "translation": [1, 0, 0.5], "turn_degrees": 40}]},
    "forces": [{"sweep": ")" + rig["sweeps"][1]["name"].get<std::string>() +
                                R"(", "t": 1, "theta": 0, "vector": [30, 0, 0], "start": 0, "end": 0.2}]})");
  const ToolRun bake = run_tool(SWEEP_SIM_EXE,
                                quoted(work / "rig.json") + " --scene " + quoted(work / "scene.json") + " -q -o " +
                                    quoted(work / "legs.pc2") + " -o " + quoted(work / "baked.glb"),
                                io);
  ASSERT_EQ(bake.code, 0) << bake.err;
  const std::string pc2 = slurp(work / "legs.pc2");
  const Glb out = read_glb(work / "baked.glb");
  const Json& animation = out.json["animations"].back();
  ASSERT_EQ(animation["name"], "sweep bake");
  // node → path → its keys' values
  std::map<std::size_t, std::map<std::string, std::vector<float>>> keys;
  for (const Json& c : animation["channels"]) {
    const std::string path = c["target"]["path"];
    if (path == "weights") continue;
    const Json& sampler = animation["samplers"][c["sampler"].get<std::size_t>()];
    keys[c["target"]["node"]][path] = floats(out.json, out.bin, sampler["output"], path == "rotation" ? 4 : 3);
  }
  ASSERT_EQ(keys.size(), 3u) << "every mesh's node follows the body";
  double worst = 0, carried = 0;
  std::size_t base = 0;
  for (std::size_t m = 0; m < 3; ++m) {
    const Piece& piece = a.pieces[m];
    const Json& prim = out.json["meshes"][m]["primitives"][0];
    const std::vector<float>& t = keys[m]["translation"];
    const std::vector<float>& r = keys[m]["rotation"];
    for (int k = 0; k < 6; ++k) {
      int points = 0;
      const std::vector<float> f = pc2_frame(pc2, k, &points);
      const std::vector<float> d = prim.contains("targets")
                                       ? floats(out.json, out.bin, prim["targets"][k]["POSITION"], 3)
                                       : std::vector<float>(piece.local.size(), 0.0f);
      const Eigen::Quaterniond q(r[4 * k + 3], r[4 * k], r[4 * k + 1], r[4 * k + 2]);
      const Vec3 shift(t[3 * k], t[3 * k + 1], t[3 * k + 2]);
      for (std::size_t i = 0; i < piece.vertices(); ++i) {
        const Vec3 local(piece.local[3 * i] + d[3 * i], piece.local[3 * i + 1] + d[3 * i + 1],
                         piece.local[3 * i + 2] + d[3 * i + 2]);
        const Vec3 want(f[3 * (base + i)], f[3 * (base + i) + 1], f[3 * (base + i) + 2]);
        worst = std::max(worst, (q * local + shift - want).norm());
        carried = std::max(carried, (want - piece.world(i)).norm());
      }
    }
    base += piece.vertices();
  }
  EXPECT_GT(carried, 0.5) << "the body moved the meshes";
  EXPECT_LT(worst, 1e-5) << "the .glb's nodes and targets against the .pc2";
  EXPECT_FALSE(out.json["meshes"][0]["primitives"][0].contains("targets"));
  for (const Json& c : animation["channels"]) {
    if (c["target"]["path"] == "weights") {
      EXPECT_NE(c["target"]["node"], 0) << "no weights on the body, which has no targets";
    }
  }
  int code = -1;
  const std::string report = validate(work / "baked.glb", &code);
  EXPECT_EQ(code, 0) << report;
  EXPECT_NE(report.find("\"numErrors\": 0"), std::string::npos) << report;
}

// The file's meshes changed since the fit (LegR renamed): the rig's list no longer finds them, and
// sweep-bind says which mesh is missing and what the file holds; nothing is written.
TEST(SeveralMeshes, ARigWhoseMeshWasRenamedIsRefused) {
  const fs::path top = scratch_dir("several-meshes-stale");
  const fs::path work = top / "work", io = top / "io";
  fs::create_directories(io);
  fs::copy(legs_pipeline(), work, fs::copy_options::recursive);
  fs::remove(work / "rig.bind");
  write_legs_glb(legs_asset(), work / "legs.glb", {"Body", "LegL", "RightLeg"});
  const ToolRun bind = run_tool(SWEEP_BIND_EXE, quoted(work / "rig.json"), io);
  EXPECT_EQ(bind.code, 2) << bind.err;
  EXPECT_NE(bind.err.find("legs.glb: no mesh is named 'LegR' (one of the 3 meshes asked for: 'Body', 'LegL', 'LegR'); "
                          "its meshes: 'Body' 362 vertices"),
            std::string::npos)
      << bind.err;
  EXPECT_NE(bind.err.find("'RightLeg'"), std::string::npos) << bind.err;
  EXPECT_FALSE(fs::exists(work / "rig.bind"));
  // A mesh named twice, on the command line, is refused too (exit 2, as any name the file cannot
  // resolve).
  const ToolRun twice = run_tool(SWEEP_FIT_EXE, quoted(work / "legs.glb") + " --mesh Body --mesh Body --list", io);
  EXPECT_EQ(twice.code, 2);
  EXPECT_NE(twice.err.find("'Body' and 'Body' name the same mesh (node 'Body'); name each mesh once"),
            std::string::npos)
      << twice.err;
}

}  // namespace
}  // namespace sweep::test
