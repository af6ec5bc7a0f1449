// Loose pieces (bind/loose_pieces.h) on the straight tube with its hand-made sweep: a tuft of 48
// separate quads past the tip goes with the part and is carried rigidly by the tip section as the
// sweep bends; a piece reaching behind the root, and one a few radii off, stay unbound and are
// named in warnings.
#include <cmath>
#include <numbers>

#include "support.h"
#include "sweep/bind/deform.h"
#include "sweep/core/elastic_sweep.h"

namespace sweep::test {
namespace {

constexpr int kTuftQuads = 48;

// A quad of its own 4 vertices (a separate piece): corner `at`, sides `a` and `b`.
void add_quad(Mesh& m, const Vec3& at, const Vec3& a, const Vec3& b) {
  const auto base = static_cast<std::uint32_t>(m.positions.size());
  m.positions.insert(m.positions.end(), {at, at + a, at + a + b, at + b});
  m.add_face({base, base + 1, base + 2, base + 3});
}

// The tube (length 1, radius 0.1, tip cap at z = 1) with a tuft: 48 quads fanning out of the
// tip cap, each from a point on the cap 0.06 from the axis, 0.15 long outwards and up.
Mesh tufted_tube(std::size_t& tuft_first) {
  Mesh m = tube::make_tube(straight_tube_params());
  tuft_first = m.positions.size();
  for (int k = 0; k < kTuftQuads; ++k) {
    const double a = 2 * std::numbers::pi * k / kTuftQuads;
    const Vec3 out(std::cos(a), std::sin(a), 0), side(-std::sin(a), std::cos(a), 0);
    add_quad(m, Vec3(0, 0, 1) + 0.06 * out, 0.1 * out + 0.1 * Vec3::UnitZ(), 0.01 * side);
  }
  return m;
}

TEST(BindLoose, ATuftOfLooseQuadsIsCarriedRigidlyByTheTipSection) {
  std::size_t first = 0;
  const Mesh mesh = tufted_tube(first);
  const Rig rig = rig_of({straight_sweep()});
  const bind::BindResult r = bind::bind(rig, mesh);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  EXPECT_EQ(r.sweeps[0].loose_piece_count, static_cast<std::size_t>(kTuftQuads));
  EXPECT_EQ(r.sweeps[0].loose_vertex_count, static_cast<std::size_t>(4 * kTuftQuads));
  EXPECT_EQ(r.unbound_vertex_count, 0u);

  // Bend the sweep at several sections; the tip section's frame moves from (C, R) to (C', R').
  ElasticSweep sweep(rig.sweeps[0]);
  sweep.set_section_pose(2, Vec3(0.01, 0, 0), Vec3(0.2, 0, 0));
  sweep.set_section_pose(4, Vec3::Zero(), Vec3(0, -0.3, 0.1));
  sweep.set_section_pose(5, Vec3(0, 0.02, 0), Vec3(0.1, 0.2, 0));
  const SweepShape& moved = sweep.deformed();
  std::vector<Vec3> out(mesh.vertex_count());
  bind::deform_exact(r.binding, std::vector<SweepShape>{moved}, mesh.positions, out);
  const Frame& rest_tip = rig.sweeps[0].rest.frames.back();
  const Frame& moved_tip = moved.frames.back();
  const Mat3 turn = moved_tip.rotation.toRotationMatrix() * rest_tip.rotation.toRotationMatrix().transpose();
  ASSERT_GT((moved_tip.center - rest_tip.center).norm(), 0.05) << "the tip section moved";
  double worst = 0;
  for (std::size_t v = first; v < mesh.vertex_count(); ++v) {
    const Vec3 carried = moved_tip.center + turn * (mesh.positions[v] - rest_tip.center);
    worst = std::max(worst, (out[v] - carried).norm());
  }
  EXPECT_LE(worst, 1e-6) << "every tuft vertex where the tip section's rigid motion takes it";
}

TEST(BindLoose, APieceBehindTheRootOrAFewRadiiOffIsLeftUnboundAndNamed) {
  Mesh mesh = tube::make_tube(straight_tube_params());
  const std::size_t behind = mesh.positions.size();
  add_quad(mesh, Vec3(0.11, 0, -0.05), Vec3(0, 0, 0.1), Vec3(0, 0.02, 0));  // across the root plane
  const std::size_t off = mesh.positions.size();
  add_quad(mesh, Vec3(0.35, 0, 0.5), Vec3(0, 0, 0.1), Vec3(0, 0.02, 0));  // 2.5 radii off the surface
  add_quad(mesh, Vec3(2, 0, 0.5), Vec3(0, 0, 0.1), Vec3(0, 0.02, 0));     // far off: not next to it
  const bind::BindResult r = bind::bind(rig_of({straight_sweep()}), mesh);
  EXPECT_EQ(r.sweeps[0].loose_piece_count, 0u);
  EXPECT_EQ(r.unbound_vertex_count, 12u);
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_NE(r.warnings[0].find("vertex " + std::to_string(behind)), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("behind the part's root section"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[1].find("vertex " + std::to_string(off)), std::string::npos) << r.warnings[1];
  EXPECT_NE(r.warnings[1].find("2.5 mean radii"), std::string::npos) << r.warnings[1];
}

}  // namespace
}  // namespace sweep::test
