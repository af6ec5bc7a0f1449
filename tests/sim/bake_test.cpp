// The whole bake on a generated tube, read back from the files it wrote: physics at the level of
// the vertices a user sees, and frame k of each file equal to the simulator's frame k.
#include <gtest/gtest.h>
#include <omp.h>
#include <tiny_gltf.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "bind/support.h"
#include "pc2_reader.h"
#include "sweep/assets/bake_run.h"
#include "sweep/bind/bind.h"
#include "sweep/bind/fast_deform.h"

using sweep::assets::run_bake;

namespace sweep::sim {
namespace {

namespace fs = std::filesystem;
using Frames = std::vector<std::vector<bind::Vec3f>>;
using test::read_pc2;

// The straight tube of tests/bind/support.h: 41 rings of 24 vertices (ring r at z = r/40), then
// the two cap centres; the hand-made sweep has K = 6 sections and n = 8 radii.
constexpr int kRings = 41, kSegments = 24;

struct Tube {
  Mesh mesh = tube::make_tube(test::straight_tube_params());
  Rig rig = test::rig_of({test::straight_sweep()});
  bind::Binding binding = bind::bind_rig(rig, mesh);
};

// Bakes `scene` to a .pc2 (and a .glb when asked) in a fresh folder and reads the .pc2 back.
Frames bake(const Tube& tube, const Scene& scene, bool exact, const fs::path& glb = {}) {
  const fs::path dir = fs::temp_directory_path() / ("sweep_bake_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  sweep::assets::BakeOptions o;
  o.outputs = {dir / "out.pc2"};
  if (!glb.empty()) o.outputs.push_back(glb);
  o.exact = exact;
  run_bake(tube.mesh, tube.rig, tube.binding, scene, o);
  Frames f = read_pc2(dir / "out.pc2");
  fs::remove_all(dir);
  return f;
}

Scene scene_with(std::vector<SceneForce> forces, double duration = 3.0) {
  Scene s;
  s.duration = duration;
  s.fps = 30;
  s.substeps = 4;
  s.forces = std::move(forces);
  for (SceneForce& f : s.forces) f.sweep_index = 0;
  return s;
}

SceneForce force_at(double t, double theta, Vec3 vector, double start, double end, std::uint8_t components) {
  SceneForce f;
  f.sweep = "tube";
  f.spec.t = t;
  f.spec.theta = theta;
  f.spec.vector = vector;
  f.spec.components = components;
  f.start = start;
  f.end = end;
  return f;
}

bind::Vec3f ring_centroid(const std::vector<bind::Vec3f>& p, int ring) {
  bind::Vec3f c = bind::Vec3f::Zero();
  for (int s = 0; s < kSegments; ++s) c += p[ring * kSegments + s];
  return c / kSegments;
}

TEST(Bake, NoForceEveryFrameIsTheRestMeshExactly) {
  const Tube tube;
  for (bool exact : {false, true}) {
    const Frames f = bake(tube, scene_with({}, 1.0), exact);
    ASSERT_EQ(f.size(), 31u);
    for (const auto& frame : f) {
      for (std::size_t v = 0; v < frame.size(); ++v) ASSERT_EQ(frame[v], tube.mesh.positions[v].cast<float>()) << v;
    }
  }
}

TEST(Bake, TipForceWithChainBendsAlongTheForceAndDecaysAfterRelease) {
  const Tube tube;
  SceneForce push = force_at(1.0, 0.0, Vec3(0, 2, 0), 0.0, 0.5, kRotational | kRadial);
  push.spec.target = RotationTarget::chain;
  const Frames f = bake(tube, scene_with({push}, 6.0), false);
  const int tip = kRings - 1, mid = kRings / 2;
  // At the end of the push the tip ring has moved mostly along +y, and the middle too (the whole
  // part bends, not only the tip).
  const bind::Vec3f tip_shift = ring_centroid(f[15], tip) - ring_centroid(f[0], tip);
  const bind::Vec3f mid_shift = ring_centroid(f[15], mid) - ring_centroid(f[0], mid);
  EXPECT_GT(tip_shift.y(), 0.02f);  // a fifth of the tube's radius at least
  EXPECT_GT(tip_shift.y(), 3 * std::abs(tip_shift.x()));
  EXPECT_GT(mid_shift.y(), 0.005f);
  // The root section is fixed exactly (tests/core); its ring's vertices, rebuilt in float once the
  // sweep moves, stay at the file's positions to float precision. After release the motion decays.
  for (const auto& frame : f) EXPECT_LT((ring_centroid(frame, 0) - ring_centroid(f[0], 0)).norm(), 1e-6f);
  const bind::Vec3f late = ring_centroid(f.back(), tip) - ring_centroid(f[0], tip);
  EXPECT_LT(late.norm(), 0.01f * tip_shift.norm());
}

TEST(Bake, RadialOnlyForceKeepsTheAxisAndChangesRadiiOnlyNearThePoint) {
  // K = 11 sections (every 0.1) so that locality shows: a handle of section i changes radii only
  // within two spans of it (its own Catmull-Rom/Hermite support), here t ∈ [0.3, 0.7].
  Tube tube;
  SweepDef def = tube.rig.sweeps[0];
  SweepShape shape;
  shape.radial_count = 8;
  for (int i = 0; i <= 10; ++i) {
    shape.t.push_back(0.1 * i);
    shape.frames.push_back({Quat::Identity(), Vec3(0, 0, 0.1 * i)});
    for (int j = 0; j < 8; ++j) shape.radii.push_back(0.1);
  }
  SweepDef fine = make_sweep("tube", shape);
  fine.part = def.part;
  tube.rig.sweeps = {fine};
  tube.binding = bind::bind_rig(tube.rig, tube.mesh);
  // Inward at t = 0.5 (section 5, ring 20), θ = π/2 (handle 2, segment 6).
  const Frames f =
      bake(tube, scene_with({force_at(0.5, std::numbers::pi / 2, Vec3(0, -3, 0), 0.0, 1.0, kRadial)}), true);
  const std::vector<bind::Vec3f>& p = f[20];
  const int ring = 20, seg = kSegments / 4;
  for (int r = 0; r < kRings; ++r) {
    // The axis stays where it was: rings are pushed in on one side, in their own planes.
    EXPECT_NEAR(ring_centroid(p, r).z(), ring_centroid(f[0], r).z(), 1e-6f) << "ring " << r;
  }
  EXPECT_LT(p[ring * kSegments + seg].y(), f[0][ring * kSegments + seg].y() - 1e-3f);  // pushed in
  // Outside the support (rings below t = 0.3 and above t = 0.7) nothing moves beyond the float
  // precision of rebuilding a vertex (~1e-8 here; the pushed vertex moves by millimetres).
  double far = 0;
  for (int r = 0; r < kRings; ++r) {
    if (r > 12 && r < 28) continue;
    for (int s = 0; s < kSegments; ++s)
      far = std::max(far, double((p[r * kSegments + s] - f[0][r * kSegments + s]).norm()));
  }
  EXPECT_LT(far, 1e-6);
}

TEST(Bake, RotationalOnlyForceLeavesEverySectionShapeUnchanged) {
  const Tube tube;
  SceneForce push = force_at(0.9, 0.3, Vec3(0.5, 2, 0.3), 0.0, 1.0, kRotational);
  push.spec.target = RotationTarget::chain;
  const Frames f = bake(tube, scene_with({push}, 1.5), true);
  for (std::size_t k : {10u, 25u, 40u}) {
    double moved = 0;
    for (int r = 0; r < kRings; ++r) {
      const bind::Vec3f c0 = ring_centroid(f[0], r), ck = ring_centroid(f[k], r);
      moved = std::max(moved, double((ck - c0).norm()));
      for (int s = 0; s < kSegments; ++s) {
        // Rigid per section: distances to the ring's centre keep their length.
        const float d0 = (f[0][r * kSegments + s] - c0).norm(), dk = (f[k][r * kSegments + s] - ck).norm();
        ASSERT_NEAR(dk, d0, 2e-6f) << "frame " << k << " ring " << r << " segment " << s;
      }
    }
    EXPECT_GT(moved, 0.01) << "frame " << k;
  }
}

TEST(Bake, ForceTangentialToTheSurfaceAcrossTheAxisTwists) {
  const Tube tube;
  // At θ = 0 the surface tangent across the axis is +y; on the section under the point (the
  // default target) its lever arm is radial, so the torque is about the axis: the ring turns in
  // place. (With "chain", sections nearer the root see a lever arm along the axis too, and the same
  // push mostly bends the tube, as a beam would.)
  SceneForce twist = force_at(1.0, 0.0, Vec3(0, 20, 0), 0.0, 4.0, kRotational);
  twist.spec.frame = VectorFrame::surface;
  const Frames f = bake(tube, scene_with({twist}, 4.0), true);
  const int tip = kRings - 1;
  auto turn = [&](std::size_t k) {
    const bind::Vec3f a = f[0][tip * kSegments] - ring_centroid(f[0], tip);
    const bind::Vec3f b = f[k][tip * kSegments] - ring_centroid(f[k], tip);
    return std::atan2(double(b.y()), double(b.x())) - std::atan2(double(a.y()), double(a.x()));
  };
  // Held until the motion has settled (ζ = 0.3 at 2 Hz decays by e^-15 in 4 s): the tip ring has
  // turned about +z by the static twist C_rot·|f| / k_twist, and the axis has not moved.
  const SpringSettings& spring = tube.rig.sweeps[0].springs.back().twist;
  const double expected = tube.rig.sweeps[0].rotational_scale * 20.0 / spring.stiffness();
  EXPECT_NEAR(turn(f.size() - 1), expected, 1e-3 * expected);
  EXPECT_LT((ring_centroid(f.back(), tip) - ring_centroid(f[0], tip)).norm(), 1e-5f);
}

TEST(Bake, ReportSaysWhichBlocksAreWrittenInPlace) {
  // The fast path writes a block straight into the mesh when the mesh's vertex order keeps it
  // contiguous (FastDeformer). One station a span: each span holds about 8 rings. With 128
  // vertices a ring and 8 angle cells each cell holds 16 consecutive vertices of a ring, so spans
  // keep mesh order: every block is in place but at most the two holding a cap centre, whose index
  // comes after all the rings. With 24 a ring (3 a cell) the vertices are sorted by cell, which
  // breaks every block into runs of 3: none in place. The exact path has no blocks.
  const auto report_of = [](int segments, bool exact) {
    tube::TubeParams p = test::straight_tube_params();
    p.segments = segments;
    const Mesh mesh = tube::make_tube(p);
    const Rig rig = test::rig_of({test::straight_sweep()});
    const bind::Binding binding = bind::bind_rig(rig, mesh);
    const fs::path dir = fs::temp_directory_path() / ("sweep_bake_blocks_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    sweep::assets::BakeOptions o;
    o.outputs = {dir / "out.pc2"};
    o.exact = exact;
    o.stations_per_span = 1;
    const Scene scene = scene_with({force_at(1.0, 0.0, Vec3(0, 2, 0), 0, 0.2, kRotational)}, 0.2);
    const sweep::assets::BakeReport r = run_bake(mesh, rig, binding, scene, o);
    fs::remove_all(dir);
    return r.sweeps.at(0);
  };
  const sweep::assets::SweepBakeStats ring = report_of(128, false);
  EXPECT_GT(ring.work_blocks, 2u);
  EXPECT_GE(ring.blocks_in_place, ring.work_blocks - 2);
  const sweep::assets::SweepBakeStats sorted = report_of(kSegments, false);
  EXPECT_GT(sorted.work_blocks, 0u);
  EXPECT_EQ(sorted.blocks_in_place, 0u);
  const sweep::assets::SweepBakeStats exact = report_of(128, true);
  EXPECT_EQ(exact.work_blocks, 0u);
  EXPECT_EQ(exact.blocks_in_place, 0u);
}

TEST(Bake, DiplodocusTailAndNeckSideBySideGiveTheSameBitsOnOneOrTwoThreads) {
  // Two small sweeps, both driven: the simulator steps them side by side and deform_sweeps
  // rebuilds them side by side on two threads, one after the other on one. Same bits either way.
  const test::Diplodocus* dino = test::diplodocus();
  if (dino == nullptr) GTEST_SKIP() << "CGAL's diplodocus is absent (tools/setup-deps.sh)";
  const bind::Binding binding = bind::bind_rig(dino->rig, dino->mesh);
  Scene scene = scene_with({}, 1.0);
  for (int i = 0; i < 2; ++i) {
    SceneForce f =
        force_at(0.9 * dino->rig.sweeps[i].rest.length(), 0.0, Vec3(0.5, 0.5, 0), 0, 0.4, kRotational | kRadial);
    f.sweep = dino->rig.sweeps[i].name;
    f.sweep_index = i;
    f.spec.target = RotationTarget::chain;
    scene.forces.push_back(f);
  }
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(2);
  if (omp_get_max_threads() != 2 || omp_get_thread_limit() < 2) {
    omp_set_num_threads(threads_before);
    GTEST_SKIP() << "OpenMP will not run two threads here (OMP_THREAD_LIMIT?)";
  }
  std::vector<std::string> bytes;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    const fs::path dir =
        fs::temp_directory_path() / ("sweep_bake_dino_" + std::to_string(::getpid()) + "_" + std::to_string(threads));
    fs::create_directories(dir);
    sweep::assets::BakeOptions o;
    o.outputs = {dir / "out.pc2"};
    const sweep::assets::BakeReport r = run_bake(dino->mesh, dino->rig, binding, scene, o);
    EXPECT_EQ(r.sweeps.at(0).frames_deformed, 30);
    EXPECT_EQ(r.sweeps.at(1).frames_deformed, 30);
    std::ifstream in(dir / "out.pc2", std::ios::binary);
    bytes.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    fs::remove_all(dir);
  }
  omp_set_num_threads(threads_before);
  ASSERT_GT(bytes[0].size(), 32u);
  EXPECT_TRUE(bytes[0] == bytes[1]) << "the pc2 differs between 1 and 2 threads";
}

TEST(Bake, ABindingThatGivesAVertexToTwoSweepsIsRefused) {
  // Sweeps are deformed side by side, so run_bake refuses (rather than races on) a binding that
  // binds a vertex twice — bind() and the binding file never make one; a hand-built one can.
  const Tube tube;
  Rig rig = test::rig_of({test::straight_sweep("a"), test::straight_sweep("b")});
  bind::Binding binding = tube.binding;
  binding.sweeps.push_back(binding.sweeps[0]);
  binding.sweeps[1].name = "b";
  Scene scene = scene_with(
      {force_at(1.0, 0.0, Vec3(0, 2, 0), 0, 0.2, kRotational), force_at(1.0, 0.0, Vec3(0, 2, 0), 0, 0.2, kRotational)},
      0.2);
  scene.forces[1].sweep_index = 1;
  const fs::path dir = fs::temp_directory_path() / ("sweep_bake_twice_" + std::to_string(::getpid()));
  sweep::assets::BakeOptions o;
  o.outputs = {dir / "out.pc2"};
  try {
    run_bake(tube.mesh, rig, binding, scene, o);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::bad_input);
    EXPECT_NE(std::string(e.what()).find("is bound by more than one sweep"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "out.pc2"));
}

TEST(Bake, FilesHoldTheSimulatorsFrames) {
  const Tube tube;
  SceneForce push = force_at(1.0, 0.0, Vec3(0, 2, 0.5), 0.0, 0.5, kRotational | kRadial);
  const Scene scene = scene_with({push}, 1.0);
  const fs::path dir = fs::temp_directory_path() / ("sweep_bake_files_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Frames pc2 = bake(tube, scene, false, dir / "out.glb");

  // The simulator's own frames, computed here independently of the bake loop.
  Simulator sim(tube.rig, scene);
  std::vector<bind::Vec3f> rest(tube.mesh.vertex_count());
  for (std::size_t v = 0; v < rest.size(); ++v) rest[v] = tube.mesh.positions[v].cast<float>();
  bind::FastDeformer fast(tube.rig.sweeps[0].rest, tube.binding.sweeps[0], rest,
                          sweep::assets::BakeOptions{}.stations_per_span);
  std::vector<bind::Vec3f> positions = rest;
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, (dir / "out.glb").string())) << err;
  const tinygltf::Primitive& prim = model.meshes.at(0).primitives.at(0);
  ASSERT_EQ(prim.targets.size(), pc2.size());
  auto accessor_floats = [&](int index, std::size_t count_of_3) {
    const tinygltf::Accessor& acc = model.accessors.at(index);
    std::vector<bind::Vec3f> out(count_of_3, bind::Vec3f::Zero());
    if (acc.bufferView >= 0) {
      const tinygltf::BufferView& bv = model.bufferViews.at(acc.bufferView);
      std::memcpy(static_cast<void*>(out.data()),
                  model.buffers.at(bv.buffer).data.data() + bv.byteOffset + acc.byteOffset, acc.count * 12);
    }
    if (acc.sparse.isSparse) {
      const auto& sp = acc.sparse;
      const auto& ib = model.bufferViews.at(sp.indices.bufferView);
      const auto& vb = model.bufferViews.at(sp.values.bufferView);
      for (int i = 0; i < sp.count; ++i) {
        std::uint32_t idx = 0;
        std::memcpy(&idx, model.buffers.at(ib.buffer).data.data() + ib.byteOffset + sp.indices.byteOffset + 4 * i, 4);
        std::memcpy(out[idx].data(),
                    model.buffers.at(vb.buffer).data.data() + vb.byteOffset + sp.values.byteOffset + 12 * i, 12);
      }
    }
    return out;
  };
  const std::vector<bind::Vec3f> base = accessor_floats(prim.attributes.at("POSITION"), rest.size());
  for (std::size_t k = 0; k < pc2.size(); ++k) {
    if (k > 0) {
      sim.advance_frame();
      if (sim.moved_last_frame(0)) fast.deform(sim.sweep(0).deformed(), positions);
    }
    const std::vector<bind::Vec3f> delta = accessor_floats(prim.targets[k].at("POSITION"), rest.size());
    for (std::size_t v = 0; v < rest.size(); ++v) {
      ASSERT_EQ(pc2[k][v], positions[v]) << "pc2 frame " << k << " vertex " << v;
      ASSERT_EQ(base[v] + delta[v], positions[v]) << "glb frame " << k << " vertex " << v;
    }
  }
  fs::remove_all(dir);
}

// The report's fold and self-crossing figures, and the warnings they give (core/fold_check.h).
TEST(Bake, AForcedFoldIsWarnedAndAQuietBakeIsNot) {
  const Tube tube;
  const auto run = [&](const SceneForce& force, std::vector<std::string>& warnings) {
    const fs::path dir = fs::temp_directory_path() / ("sweep_fold_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    sweep::assets::BakeOptions o;
    o.outputs = {dir / "out.pc2"};
    o.warn = [&](const std::string& w) { warnings.push_back(w); };
    const sweep::assets::BakeReport r = run_bake(tube.mesh, tube.rig, tube.binding, scene_with({force}, 1.0), o);
    fs::remove_all(dir);
    return r.sweeps.at(0);
  };
  // 2 N on the whole chain: a few degrees a span.
  SceneForce gentle = force_at(1.0, 0.0, Vec3(0, 2, 0), 0.0, 0.5, kRotational);
  gentle.spec.target = RotationTarget::chain;
  std::vector<std::string> quiet_warnings;
  const sweep::assets::SweepBakeStats quiet = run(gentle, quiet_warnings);
  EXPECT_TRUE(quiet_warnings.empty());
  EXPECT_GT(quiet.largest_bend, 0);
  EXPECT_LT(quiet.largest_bend, 0.2);
  EXPECT_EQ(quiet.fold_frame, -1);
  EXPECT_EQ(quiet.cross_frame, -1);
  // The paper's springs: each sways at its own bend frequency and feels no gravity.
  ASSERT_EQ(quiet.sway.frequencies_hz.size(), 1u);
  EXPECT_EQ(quiet.sway.frequencies_hz[0], tube.rig.sweeps[0].springs[1].bend.frequency_hz);
  EXPECT_FALSE(quiet.sway.feels_gravity);

  // 400 N at the tip on the whole chain, against bend springs of k = (2π 1.5 Hz)² ≈ 89 N·m/rad: its
  // spans turn past 90° (the report names the first that did, and the warning says the same).
  SceneForce hard = force_at(1.0, 0.0, Vec3(0, 400, 0), 0.0, 1.0, kRotational);
  hard.spec.target = RotationTarget::chain;
  std::vector<std::string> fold_warnings;
  const sweep::assets::SweepBakeStats folded = run(hard, fold_warnings);
  EXPECT_GT(folded.largest_bend, std::numbers::pi / 2);
  EXPECT_GE(folded.fold_frame, 1);
  EXPECT_GE(folded.fold_span, 1);
  EXPECT_LE(folded.fold_span, 5);
  ASSERT_FALSE(fold_warnings.empty());
  const std::string span = std::to_string(folded.fold_span - 1) + "-" + std::to_string(folded.fold_span);
  EXPECT_NE(fold_warnings[0].find("part \"tube\" folds past 90° within one span (sections " + span +
                                  ", first at frame " + std::to_string(folded.fold_frame)),
            std::string::npos)
      << fold_warnings[0];
}

}  // namespace
}  // namespace sweep::sim
