// Binding and exact deformation on generated tubes with hand-made sweeps (every number visible),
// and fitted sweeps on the committed example tubes: rest exactness, following a turned section and
// a grown radial handle, the seam at the root, ownership and blend rules.
#include <cmath>
#include <numbers>

#include "support.h"
#include "sweep/bind/deform.h"
#include "sweep/core/elastic_sweep.h"
#include "test_constants.h"

namespace sweep::test {
namespace {

using bind::Binding;
using bind::BindOptions;
using bind::SweepBinding;

using ::sweep::test::kPi;

// Every bound vertex rebuilt on the rest shape from the stored float32 coordinates lies within
// `tolerance` of the mesh vertex (asserted vertex by vertex).
void expect_rest_exact(const SweepBinding& table, const SweepShape& rest, const Mesh& mesh, double tolerance) {
  ASSERT_GT(table.size(), 0u);
  for (std::size_t k = 0; k < table.size(); ++k) {
    const Vec3 rebuilt = deform_point(rest, table.coords(k));
    ASSERT_LE((rebuilt - mesh.positions[table.vertices[k]]).norm(), tolerance)
        << table.name << ": vertex " << table.vertices[k] << " (t " << table.t[k] << ", theta " << table.theta[k]
        << ", s " << table.s[k] << ", z " << table.z[k] << ")";
  }
}

std::vector<Vec3> deform(const Binding& b, const std::vector<SweepShape>& shapes, const Mesh& mesh) {
  std::vector<Vec3> out(mesh.vertex_count());
  bind::deform_exact(b, shapes, mesh.positions, out);
  return out;
}

TEST(BindTube, EveryVertexOfTheStraightTubeIsBoundAndRebuiltExactly) {
  const Mesh mesh = tube::make_tube(straight_tube_params());
  const Rig rig = rig_of({straight_sweep()});
  const bind::BindResult r = bind::bind(rig, mesh);
  ASSERT_EQ(r.binding.sweeps.size(), 1u);
  const SweepBinding& t = r.binding.sweeps[0];
  EXPECT_EQ(t.size(), mesh.vertex_count());
  EXPECT_EQ(r.unbound_vertex_count, 0u);
  expect_rest_exact(t, rig.sweeps[0].rest, mesh, 1e-5 * rig.sweeps[0].rest.length());
  EXPECT_LE(r.sweeps[0].rest_max_error, 1e-5);
  // The cap centres: on the axis (s = 0), at the end sections with no axial offset.
  EXPECT_EQ(t.vertices[984], 984u);
  EXPECT_EQ(t.t[984], 0.0f);
  EXPECT_EQ(t.s[984], 0.0f);
  EXPECT_EQ(t.t[985], 1.0f);
  // Ring i at t = i/40, segment j at θ = 2πj/24, on the surface (s = 1).
  for (int i = 0; i < 41; ++i) {
    for (int j = 0; j < 24; ++j) {
      const std::size_t v = static_cast<std::size_t>(i) * 24 + j;
      EXPECT_NEAR(t.t[v], i / 40.0, 1e-6);
      EXPECT_NEAR(t.theta[v], 2 * kPi * j / 24, 1e-6);
      EXPECT_NEAR(t.s[v], 1.0, 1e-6);
      EXPECT_EQ(t.z[v], 0.0f);
      EXPECT_EQ(t.weight[v], 1.0f);
    }
  }
}

TEST(BindTube, SeedlessSweepBindsTheTubeAndLeavesDistantVerticesAlone) {
  // The tube plus a far-away copy of it shifted sideways by 1: a hand-made sweep without seeds
  // binds the first (s ≤ 1.5) and leaves the copy (s ≈ 10) unbound.
  Mesh mesh = tube::make_tube(straight_tube_params());
  const std::size_t n = mesh.vertex_count();
  Mesh other = mesh;
  for (Vec3& p : other.positions) p += Vec3(1, 0, 0);
  mesh.positions.insert(mesh.positions.end(), other.positions.begin(), other.positions.end());
  const Rig rig = rig_of({straight_sweep("tube", /*seeds=*/false)});
  const bind::BindResult r = bind::bind(rig, mesh);
  const SweepBinding& t = r.binding.sweeps[0];
  ASSERT_EQ(t.size(), n);
  for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(t.vertices[k], k);
  EXPECT_EQ(r.unbound_vertex_count, n);
  expect_rest_exact(t, rig.sweeps[0].rest, mesh, 1e-5);
  // Unbound vertices never move.
  SweepShape moved = rig.sweeps[0].rest;
  moved.frames[5].center += Vec3(0.3, 0, 0);
  const std::vector<Vec3> out = deform(r.binding, {moved}, mesh);
  for (std::size_t v = n; v < 2 * n; ++v) EXPECT_EQ(out[v], mesh.positions[v]) << v;
}

// Rest exactness on sweeps fitted by sweep-fit's library to the committed example tubes.
struct FittedTube {
  const char* file;
  double length;
};

class BindFittedTube : public testing::TestWithParam<FittedTube> {};

TEST_P(BindFittedTube, RestPoseIsRebuiltWithin1e5OfTheLength) {
  const FittedTube& c = GetParam();
  const Mesh mesh = assets::read_mesh(fs::path(SWEEP_SOURCE_DIR) / "meshes" / c.file);
  // Each tube starts at the origin heading +z; its tip is the last listed vertex (tip cap centre).
  fit::FitOptions o;
  o.name = "tube";
  o.root = Vec3(0, 0, 0.02 * c.length);
  o.tip = mesh.positions.back();
  o.measure_error = false;
  const fit::FitResult f = fit::fit_sweep(mesh, o);
  const Rig rig = rig_of({f.sweep});
  const bind::BindResult r = bind::bind(rig, mesh);
  const SweepBinding& t = r.binding.sweeps[0];
  EXPECT_EQ(t.size(), f.part_vertices.size());
  EXPECT_EQ(t.vertices, f.part_vertices);
  const double tolerance = 1e-5 * f.sweep.rest.length();
  expect_rest_exact(t, f.sweep.rest, mesh, tolerance);
  EXPECT_LE(r.sweeps[0].rest_max_error, tolerance);
  EXPECT_EQ(r.sweeps[0].bound_vertex_count, t.size());
}

INSTANTIATE_TEST_SUITE_P(Meshes, BindFittedTube,
                         testing::Values(FittedTube{"tube_straight.obj", 1.0}, FittedTube{"tube_bent.obj", 2.0},
                                         FittedTube{"tube_tapered.off", 1.5}, FittedTube{"tube_ellipse.ply", 1.0},
                                         FittedTube{"tube_lobed.obj", 1.2}),
                         [](const testing::TestParamInfo<FittedTube>& param_info) {
                           std::string s = param_info.param.file;
                           return s.substr(0, s.find('.'));
                         });

TEST(BindFollow, TurningASectionMovesEverythingBeyondItByThatRigidRotation) {
  const Mesh mesh = tube::make_tube(straight_tube_params());
  const Rig rig = rig_of({straight_sweep()});
  const Binding b = bind::bind_rig(rig, mesh);
  const SweepBinding& t = b.sweeps[0];
  const std::vector<Vec3> rest = deform(b, {rig.sweeps[0].rest}, mesh);

  ElasticSweep sweep(rig.sweeps[0]);
  const double angle = 0.3;  // radians, about section 3's own x axis (world x here)
  sweep.set_section_pose(3, Vec3::Zero(), Vec3(angle, 0, 0));
  const std::vector<Vec3> out = deform(b, {sweep.deformed()}, mesh);

  const Vec3 c3(0, 0, 0.6);
  const Mat3 turn = Eigen::AngleAxisd(angle, Vec3::UnitX()).toRotationMatrix();
  int beyond = 0, before = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const std::uint32_t v = t.vertices[k];
    if (t.t[k] >= 0.6) {
      // Exactly the rigid rotation of the rebuilt rest position, and of the mesh vertex to float.
      ++beyond;
      ASSERT_LE((out[v] - (c3 + turn * (rest[v] - c3))).norm(), 1e-12) << "vertex " << v;
      ASSERT_LE((out[v] - (c3 + turn * (mesh.positions[v] - c3))).norm(), 1e-5) << "vertex " << v;
    } else if (t.t[k] < 0.4 - 1e-6) {
      // Before section 2 nothing depends on section 3. (Ring 16 lies on section 2, but its float32
      // t = 0.4000000059 falls just inside span 2, where section 3 weighs ~1e-8.)
      ++before;
      ASSERT_LE((out[v] - rest[v]).norm(), 1e-12) << "vertex " << v;
    }
  }
  EXPECT_EQ(beyond, 17 * 24 + 1);  // rings 24..40 and the tip cap centre
  EXPECT_EQ(before, 16 * 24 + 1);  // rings 0..15 and the root cap centre
  // The tip moved where the rotation takes it: (0, -0.4 sin 0.3, 0.6 + 0.4 cos 0.3).
  EXPECT_NEAR((out[985] - Vec3(0, -0.4 * std::sin(angle), 0.6 + 0.4 * std::cos(angle))).norm(), 0, 1e-6);
}

TEST(BindFollow, GrowingARadialHandleMovesOnlyNearbyVerticesOutward) {
  const Mesh mesh = tube::make_tube(straight_tube_params());
  const Rig rig = rig_of({straight_sweep()});
  const Binding b = bind::bind_rig(rig, mesh);
  const SweepBinding& t = b.sweeps[0];
  const std::vector<Vec3> rest = deform(b, {rig.sweeps[0].rest}, mesh);

  ElasticSweep sweep(rig.sweeps[0]);
  const int section = 3, handle = 2;  // t = 0.6, θ = π/2 (mesh ring 24, segment 6)
  const double delta = 0.02;          // mesh units
  sweep.set_radial_offset(section, handle, delta);
  const std::vector<Vec3> out = deform(b, {sweep.deformed()}, mesh);

  // The handle reaches θ ∈ (θ_{j-2}, θ_{j+2}) (Catmull-Rom) and t ∈ (t_{i-2}, t_{i+2}) (Hermite
  // with finite-difference slopes); it pushes outward where it dominates, θ ∈ [θ_{j-1}, θ_{j+1}]
  // and t ∈ [t_{i-1}, t_{i+1}].
  const double step = 2 * kPi / 8;
  const double theta_j = handle * step;
  int moved_out = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const std::uint32_t v = t.vertices[k];
    const double dt = std::abs(t.t[k] - 0.6), dtheta = std::abs(t.theta[k] - theta_j);
    const Vec3 move = out[v] - rest[v];
    if (dt >= 0.4 - 1e-6 || dtheta >= 2 * step - 1e-6 || t.s[k] == 0) {
      ASSERT_LE(move.norm(), 1e-12) << "vertex " << v << " is outside the handle's reach";
      continue;
    }
    ASSERT_LE(move.norm(), delta * (1 + 1e-6)) << "vertex " << v;
    const double theta = t.theta[k];
    const Vec3 radial(std::cos(theta), std::sin(theta), 0);
    EXPECT_LE((move - move.dot(radial) * radial).norm(), 1e-12) << "vertex " << v;  // radial only
    if (dt <= 0.2 + 1e-6 && dtheta <= step + 1e-6 && dt < 0.2 - 1e-6 && dtheta < step - 1e-6) {
      ASSERT_GT(move.dot(radial), 0) << "vertex " << v << " should move outward";
      ++moved_out;
    }
  }
  EXPECT_GT(moved_out, 0);
  // The vertex at the handle itself moves by the handle's offset (s = 1).
  const std::uint32_t at_handle = 24 * 24 + 6;
  EXPECT_NEAR((out[at_handle] - rest[at_handle]).norm(), delta, 1e-6);
  EXPECT_NEAR(out[at_handle].y() - mesh.positions[at_handle].y(), delta, 1e-6);
}

TEST(BindSeam, RootPlaneVerticesStayPutWhileTheRestOfTheSweepMoves) {
  const Mesh mesh = tube::make_tube(straight_tube_params());
  const Rig rig = rig_of({straight_sweep()});
  const Binding b = bind::bind_rig(rig, mesh);
  const SweepBinding& t = b.sweeps[0];
  const std::vector<Vec3> rest = deform(b, {rig.sweeps[0].rest}, mesh);

  // Every section but the root moves: shifted, bent, twisted, radii grown and shrunk.
  ElasticSweep sweep(rig.sweeps[0]);
  for (int i = 1; i < 6; ++i) {
    sweep.set_section_pose(i, Vec3(0.01 * i, -0.02, 0.005), Vec3(0.2, -0.1 * i, 0.3));
    for (int j = 0; j < 8; ++j) sweep.set_radial_offset(i, j, (j % 2 ? 0.03 : -0.04));
  }
  const std::vector<Vec3> out = deform(b, {sweep.deformed()}, mesh);
  int at_root = 0;
  double farthest_tip_move = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const std::uint32_t v = t.vertices[k];
    if (t.t[k] == 0) {
      ++at_root;
      EXPECT_EQ(out[v], rest[v]) << "vertex " << v << " at the root plane moved";
      EXPECT_LE((out[v] - mesh.positions[v]).norm(), 1e-6);
    } else {
      farthest_tip_move = std::max(farthest_tip_move, (out[v] - rest[v]).norm());
    }
  }
  EXPECT_EQ(at_root, 24 + 1);  // ring 0 and the root cap centre
  EXPECT_GT(farthest_tip_move, 0.1);
}

TEST(BindOwnership, OverlappingPartsGoToTheNearestSurfaceAndTiesToTheEarlierSweep) {
  const Mesh mesh = tube::make_tube(straight_tube_params());
  // "fat" (radius 0.13) and "exact" (0.1) claim the same vertices; the exact one is nearer the
  // surface for every side vertex, whichever comes first in the rig.
  for (bool exact_first : {false, true}) {
    std::vector<SweepDef> sweeps{straight_sweep("fat", true, 0.13), straight_sweep("exact")};
    if (exact_first) std::swap(sweeps[0], sweeps[1]);
    const bind::BindResult r = bind::bind(rig_of(sweeps), mesh);
    const int exact = exact_first ? 0 : 1;
    const SweepBinding& e = r.binding.sweeps[exact];
    const SweepBinding& f = r.binding.sweeps[1 - exact];
    EXPECT_EQ(e.name, "exact");
    // Side vertices are on the exact surface (distance 0, 0.03 from the fat one); the cap
    // centres lie 0.1 from the exact surface and 0.13 from the fat one.
    EXPECT_EQ(e.size(), mesh.vertex_count());
    EXPECT_EQ(f.size(), 0u);
    EXPECT_EQ(r.sweeps[1 - exact].part_vertex_count, mesh.vertex_count());
    EXPECT_EQ(r.sweeps[1 - exact].bound_vertex_count, 0u);
  }
  // Identical sweeps: every vertex is a tie, the earlier sweep takes all.
  const bind::BindResult r = bind::bind(rig_of({straight_sweep("first"), straight_sweep("second")}), mesh);
  EXPECT_EQ(r.binding.sweeps[0].size(), mesh.vertex_count());
  EXPECT_EQ(r.binding.sweeps[1].size(), 0u);
}

TEST(BindBlend, WeightIsTheSmoothstepOfTheDistanceBeyondTheRootPlane) {
  const Mesh mesh = tube::make_tube(straight_tube_params());
  const Rig rig = rig_of({straight_sweep()});
  BindOptions o;
  o.blend = 0.1;  // four rings
  const bind::BindResult r = bind::bind(rig, mesh, o);
  const SweepBinding& t = r.binding.sweeps[0];
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double x = std::min(mesh.positions[t.vertices[k]].z() / 0.1, 1.0);
    EXPECT_NEAR(t.weight[k], x * x * (3 - 2 * x), 1e-7) << "vertex " << t.vertices[k];
  }
  EXPECT_EQ(r.sweeps[0].blended_vertex_count, 4u * 24 + 1);  // rings 0..3 and the root centre

  // Deformed = rest + w (sweep − rest): compare with the unblended deformation.
  const Binding plain = bind::bind_rig(rig, mesh);
  ElasticSweep sweep(rig.sweeps[0]);
  sweep.set_section_pose(1, Vec3(0.02, 0, 0), Vec3(0, 0.3, 0));
  const std::vector<Vec3> blended = deform(r.binding, {sweep.deformed()}, mesh);
  const std::vector<Vec3> full = deform(plain, {sweep.deformed()}, mesh);
  for (std::size_t k = 0; k < t.size(); ++k) {
    const std::uint32_t v = t.vertices[k];
    const Vec3 expected = mesh.positions[v] + double(t.weight[k]) * (full[v] - mesh.positions[v]);
    ASSERT_LE((blended[v] - expected).norm(), 1e-12) << "vertex " << v;
  }
  // Ring 2 (z = 0.05, w = 0.5) moves half as far as without the blend (up to float rest error).
  const std::uint32_t v = 2 * 24;
  EXPECT_NEAR((blended[v] - mesh.positions[v]).norm(), 0.5 * (full[v] - mesh.positions[v]).norm(), 1e-6);
}

TEST(BindAdjacency, RowsAreSortedUniqueAndSymmetric) {
  std::vector<Mesh> meshes{tube::make_tube(straight_tube_params())};
  meshes[0].add_face({0, 1, 1, 900});  // a repeated corner and a long edge
  if (const Diplodocus* d = diplodocus()) meshes.push_back(d->mesh);
  for (const Mesh& m : meshes) {
    const VertexAdjacency a = vertex_adjacency(m);
    ASSERT_EQ(a.offsets.size(), m.vertex_count() + 1);
    auto row = [&](std::uint32_t v) {
      return std::vector<std::uint32_t>(a.neighbours.begin() + a.offsets[v], a.neighbours.begin() + a.offsets[v + 1]);
    };
    for (std::uint32_t v = 0; v < m.vertex_count(); ++v) {
      const auto r = row(v);
      EXPECT_TRUE(std::is_sorted(r.begin(), r.end()) && std::adjacent_find(r.begin(), r.end()) == r.end()) << v;
      for (std::uint32_t w : r) {
        EXPECT_NE(w, v);
        const auto back = row(w);
        EXPECT_TRUE(std::binary_search(back.begin(), back.end(), v)) << v << "-" << w;
      }
    }
    // The repeated-corner face contributes the long edge 1–900 and no self-loop.
    if (&m == &meshes[0]) {
      const auto far_row = row(900);
      EXPECT_TRUE(std::binary_search(far_row.begin(), far_row.end(), 1u));
    }
  }
}

TEST(BindErrors, BadOptionsAndBadShapesAreRefusedWithMessages) {
  const Mesh mesh = tube::make_tube(straight_tube_params());
  BindOptions o;
  o.blend = -1;
  try {
    bind::bind(rig_of({straight_sweep()}), mesh, o);
    FAIL() << "negative blend accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::usage);
    // The library names its field, not a flag it never saw.
    EXPECT_NE(std::string(e.what()).find("BindOptions::blend"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
  }
  SweepDef broken = straight_sweep("bad");
  broken.rest.radii[3] = -1;
  try {
    bind::bind(rig_of({straight_sweep(), broken}), mesh);
    FAIL() << "negative radius accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::bad_input);
    EXPECT_NE(std::string(e.what()).find("sweep 1 ('bad')"), std::string::npos) << e.what();
  }
  // A tip seed on the body's side of the root section (the tube shifted to straddle it).
  Mesh shifted = mesh;
  for (Vec3& p : shifted.positions) p.z() -= 0.5;
  SweepDef backwards = straight_sweep("backwards");
  backwards.part->tip = Vec3(0, 0, -0.5);
  try {
    bind::bind(rig_of({backwards}), shifted);
    FAIL() << "tip behind the root accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::bad_input);
    EXPECT_NE(std::string(e.what()).find("behind the root section"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sweep::test
