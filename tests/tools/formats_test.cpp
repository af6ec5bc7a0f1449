// One asset, every format sweep-fit reads. The textured tail of textured_asset.h (UVs split
// at a seam as exporters split them, normals, a textured material, a rotated and non-uniformly
// scaled node) written as glTF (.gltf), GLB, OBJ + MTL, STL and FBX is fitted by sweep-fit with the
// same seeds: the rig (key sections' parameters, centres, frames, radii) and the part (which
// vertices, by position: orders and counts differ across formats) must be those of the .gltf, and
// no format may show a hole. And a seam-split tube fits as its welded twin does.
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <cfloat>
#include <iostream>
#include <nlohmann/json.hpp>

#include "pipeline.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/core/rig.h"
#include "sweep/core/topology.h"
#include "sweep/io/rig_json.h"
#include "textured_asset.h"

namespace sweep::test {
namespace {

using Json = nlohmann::json;

// Tolerances. Every format carries the tail's world positions to float precision, but not the same
// floats: the glTF keeps the local floats and its node's matrix (applied in double on reading),
// assimp's exporter writes the product rounded to float. So a vertex differs across formats by a
// few units in the last place of float: kPositionTolerance (8 ulps at the asset's extent, under 2;
// 2e-6, or 2e-5 of the tube's radius) bounds that, far below its vertices' spacing (> 0.03), so
// matching by position cannot pair the wrong vertices.
constexpr double kExtent = 2;
constexpr double kPositionTolerance = 8 * FLT_EPSILON * kExtent;
// The fit is a smooth function of the positions (slices, least squares): a perturbation of
// kPositionTolerance moves its numbers by less (measured: centres and radii 0.35 times it, frames
// 0.15 times it over the radius). Ten times that (2e-4 of the radius on lengths, 2e-4 radians on
// frames) leaves room for a worse-conditioned step and still tells a different fit (a section
// placed elsewhere, a frame turned about the axis) from rounding.
constexpr double kFitLengthTolerance = 10 * kPositionTolerance;
constexpr double kFitAngleTolerance = 10 * kPositionTolerance / TexturedAsset::kRadius;

// The seeds of the other tail tests, in world space.
std::string seeds() {
  const Eigen::Affine3d w = TexturedAsset::tail_world();
  auto csv = [](const Eigen::Vector3d& p) {
    return std::to_string(p.x()) + "," + std::to_string(p.y()) + "," + std::to_string(p.z());
  };
  return " --root " + csv(w * Eigen::Vector3d(0, 0, 0.02)) + " --tip " + csv(w * Eigen::Vector3d(0, 0, 1)) +
         " -k 6 -n 8";
}

// creature.gltf (+ .bin, skin.png) holding the tail alone, and the same asset as creature.glb,
// creature.obj (+ .mtl) and creature.stl, made once per build of the tools.
fs::path formats_dir() {
  return cached_dir("formats", [](const fs::path& dir, const fs::path&) {
    Json doc = write_textured_asset(dir);
    // The Ground left out: STL and OBJ hold one mesh, and read whole they would fit the plane too.
    doc["meshes"].erase(1);
    doc["nodes"].erase(3);
    doc["scenes"][0]["nodes"] = {0};
    doc.erase("animations");  // the Ground's
    spit(dir / "creature.gltf", doc.dump(1));
    Json glb = doc;
    glb["buffers"][0].erase("uri");
    spit(dir / "creature.glb", glb_bytes(glb, slurp(dir / "creature.bin")));
    // OBJ and STL by assimp's exporter from the glTF as assimp reads it, the node's transform
    // applied to the vertices (OBJ and STL have no nodes). Its OBJ keeps the seam split: a `v` for
    // each glTF vertex (a seam's copies differ in colour); the STL reader welds by position.
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile((dir / "creature.gltf").string(), 0);
    ASSERT_NE(scene, nullptr) << importer.GetErrorString();
    Assimp::Exporter exporter;
    for (const auto& [format, file] : {std::pair{"obj", "creature.obj"}, std::pair{"stlb", "creature.stl"}}) {
      ASSERT_EQ(exporter.Export(scene, format, (dir / file).string(), aiProcess_PreTransformVertices), aiReturn_SUCCESS)
          << file << ": " << exporter.GetErrorString();
    }
  });
}

// What sweep-fit made of one file: its streams, report and rig, and the part that rig picks.
struct FormatFit {
  ToolRun run;
  Json report;
  Rig rig;
  std::vector<Vec3> part;  // the part's positions, each once (seam copies are one), sorted
};

FormatFit fit_format(const fs::path& mesh, const fs::path& work, const fs::path& io) {
  FormatFit f;
  const fs::path rig = work / (mesh.filename().string() + ".rig.json"),
                 report = work / (mesh.filename().string() + ".json");
  f.run = run_tool(SWEEP_FIT_EXE,
                   quoted(mesh) + " -o " + quoted(rig) + " --name tail --report " + quoted(report) + seeds(), io);
  EXPECT_EQ(f.run.code, 0) << mesh << "\n" << f.run.out << f.run.err;
  if (f.run.code != 0) return f;
  f.report = Json::parse(slurp(report));
  f.rig = io::read_rig(rig);
  // The part as sweep-bind takes it: the rig's mesh of the file, its seeds, its rest shape.
  const Mesh m = assets::read_scene_mesh(mesh, f.rig.mesh_name, assets::MeshPick::whole_file).mesh;
  const SweepDef& sweep = f.rig.sweeps.at(0);
  for (const std::uint32_t v : select_sweep_part(m, build_topology(m), sweep.rest, sweep.part.value()))
    f.part.push_back(m.positions[v]);
  std::sort(f.part.begin(), f.part.end(), [](const Vec3& a, const Vec3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  f.part.erase(std::unique(f.part.begin(), f.part.end()), f.part.end());
  return f;
}

// The largest distance from a point of `a` to the nearest point of `b`.
double farthest_from(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double worst = 0;
  for (const Vec3& p : a) {
    double nearest = INFINITY;
    for (const Vec3& q : b) nearest = std::min(nearest, (p - q).norm());
    worst = std::max(worst, nearest);
  }
  return worst;
}

// `got` against the reference fit `want`: the same sections, the same part, no hole.
void expect_same_fit(const FormatFit& got, const FormatFit& want, const std::string& format) {
  SCOPED_TRACE(format);
  for (const std::string& text : {got.run.out, got.run.err}) {
    EXPECT_EQ(text.find("open polyline"), std::string::npos) << text;
    EXPECT_EQ(text.find("(a hole in the mesh)"), std::string::npos) << text;
  }
  const Json& sweep = got.report.at("sweeps").at(0);
  EXPECT_TRUE(sweep.at("ok").get<bool>()) << sweep.dump(1);
  EXPECT_TRUE(sweep.at("warnings").empty()) << sweep.dump(1);
  const SweepShape& a = got.rig.sweeps.at(0).rest;
  const SweepShape& b = want.rig.sweeps.at(0).rest;
  ASSERT_EQ(a.section_count(), b.section_count());
  ASSERT_EQ(a.radial_count, b.radial_count);
  double t = 0, centre = 0, angle = 0, radius = 0;
  for (int i = 0; i < a.section_count(); ++i) {
    t = std::max(t, std::abs(a.t[i] - b.t[i]));
    centre = std::max(centre, (a.frames[i].center - b.frames[i].center).norm());
    angle = std::max(angle, a.frames[i].rotation.angularDistance(b.frames[i].rotation));
    for (int j = 0; j < a.radial_count; ++j)
      radius = std::max(radius, std::abs(a.radius_sample(i, j) - b.radius_sample(i, j)));
  }
  const double part = std::max(farthest_from(got.part, want.part), farthest_from(want.part, got.part));
  std::cout << format << ": " << got.part.size() << " part positions (farthest from the .gltf's " << part
            << "); against the .gltf's fit: t " << t << ", centres " << centre << ", frames " << angle << " rad, radii "
            << radius << "; fit RMS " << sweep.at("fit_rms_relative") << " of the radius\n";
  EXPECT_LE(t, kFitLengthTolerance);
  EXPECT_LE(centre, kFitLengthTolerance);
  EXPECT_LE(angle, kFitAngleTolerance);
  EXPECT_LE(radius, kFitLengthTolerance);
  EXPECT_EQ(got.part.size(), want.part.size());
  EXPECT_LE(part, kPositionTolerance);
}

// glTF, GLB, OBJ + MTL and STL (FBX below: Blender writes it).
TEST(Formats, TheTailFitsAlikeFromGltfGlbObjAndStl) {
  const fs::path dir = formats_dir(), top = scratch_dir("formats"), io = top / "io";
  fs::create_directories(io);
  const FormatFit gltf = fit_format(dir / "creature.gltf", top, io);
  ASSERT_EQ(gltf.run.code, 0);
  // Each position once: rings 1 to R - 1 and the tip cap's centre. Section 0 is cut through ring 1,
  // the ring nearest the root seed (z = 0.02 of 1, rings 1/32 apart): ring 0 and the root cap's
  // centre lie behind it.
  EXPECT_EQ(gltf.part.size(), static_cast<std::size_t>((TexturedAsset::kRings - 1) * TexturedAsset::kSegments + 1));
  expect_same_fit(gltf, gltf, "creature.gltf");  // against itself: its messages and report only
  for (const char* file : {"creature.glb", "creature.obj", "creature.stl"}) {
    expect_same_fit(fit_format(dir / file, top, io), gltf, file);
  }
}

// FBX as Blender writes it from the OBJ above (metres: UnitScaleFactor 100, the OBJ's coordinates;
// assimp reads them unscaled, so the fit is in the same space as the others). Skipped without
// Blender.
TEST(Formats, TheTailFitsFromFbxAsFromGltf) {
  if (!have_blender()) GTEST_SKIP() << "blender is not installed (it writes the FBX)";
  const fs::path dir = formats_dir(), top = scratch_dir("formats-fbx"), io = top / "io";
  fs::create_directories(io);
  const ToolRun x = obj_to_fbx(dir / "creature.obj", top / "creature.fbx", io);
  ASSERT_EQ(x.code, 0) << x.out << x.err;
  const FormatFit gltf = fit_format(dir / "creature.gltf", top, io);
  ASSERT_EQ(gltf.run.code, 0);
  expect_same_fit(fit_format(top / "creature.fbx", top, io), gltf, "creature.fbx");
}

// The .gltf read as it is (each seam position twice, the caps' rims apart from the side's) and
// welded: every position once, written by the project's own OBJ writer, so both carry the same
// numbers. The seam is no hole to the slicer or the walk: the same fit, the same part.
TEST(Formats, ASeamSplitTubeFitsAsTheWeldedOne) {
  const fs::path dir = formats_dir(), top = scratch_dir("formats-seam"), io = top / "io";
  fs::create_directories(io);
  const Mesh split = assets::read_mesh(dir / "creature.gltf");
  const Topology topology = build_topology(split);
  // Each ring's seam vertex, and each cap's rim and centre against the side's rings.
  EXPECT_EQ(topology.welded_count, static_cast<std::size_t>(TexturedAsset::kRings + 2 * TexturedAsset::kSegments));
  Mesh welded;
  std::vector<std::uint32_t> index(split.vertex_count());
  for (std::uint32_t v = 0; v < split.vertex_count(); ++v) {
    if (topology.weld[v] != v) continue;
    index[v] = static_cast<std::uint32_t>(welded.positions.size());
    welded.positions.push_back(split.positions[v]);
  }
  for (const std::uint32_t v : split.face_vertices) welded.face_vertices.push_back(index[topology.weld[v]]);
  welded.face_offsets = split.face_offsets;
  assets::write_obj(top / "welded.obj", welded);
  EXPECT_EQ(build_topology(assets::read_mesh(top / "welded.obj")).welded_count, 0u);
  const FormatFit seamed = fit_format(dir / "creature.gltf", top, io);
  ASSERT_EQ(seamed.run.code, 0);
  const FormatFit one = fit_format(top / "welded.obj", top, io);
  expect_same_fit(one, seamed, "welded.obj");
  expect_same_fit(seamed, seamed, "creature.gltf (seam split)");  // its messages and report only
  EXPECT_LE(seamed.report["sweeps"][0]["fit_rms_relative"].get<double>(),
            one.report["sweeps"][0]["fit_rms_relative"].get<double>() + kFitLengthTolerance / TexturedAsset::kRadius);
}

}  // namespace
}  // namespace sweep::test
