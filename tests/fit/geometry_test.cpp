// Small exact cases: loops in a plane, rotation-minimizing frames, the part flood.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <numbers>

#include "sweep/core/error.h"
#include "sweep/core/topology.h"
#include "sweep/fit/loop.h"
#include "sweep/fit/slicer.h"
#include "sweep/fit/trace.h"

namespace sweep::fit {
namespace {

// A square of half-side a in the z = 0 plane, centred at the origin.
std::vector<Vec3> square(double a, double z = 0) {
  return {{-a, -a, z}, {a, -a, z}, {a, a, z}, {-a, a, z}};
}

TEST(Loop, SquareRadiiAreExact) {
  // Rays at 0, 45, 90, ... degrees from the centre of a square of half-side 1: 1, √2, 1, ...
  const RaySamples s = sample_radii(Frame{}, square(1), 8);
  ASSERT_EQ(s.radii.size(), 8u);
  for (int j = 0; j < 8; ++j) {
    EXPECT_NEAR(s.radii[j], j % 2 == 0 ? 1.0 : std::sqrt(2.0), 1e-12) << "ray " << j;
  }
  EXPECT_EQ(s.multi_crossing_rays, 0);
  EXPECT_EQ(s.missed_rays, 0);
}

TEST(Loop, NotStarShapedIsReportedAndOutermostCrossingUsed) {
  // A C open to +x, centre c = (1, 0.75) in its upper arm:
  //   (-1,1) +------------+ (2,1)
  //          |      c     |
  //          |    +-------+ (2,0.5)       the ray from c towards -y crosses the arm's lower
  //          |    |  notch                edge (y = 0.5), the notch's lower edge (y = -0.5)
  //          |    +-------+ (2,-0.5)      and the outside (y = -1): outermost 1.75
  //  (-1,-1) +------------+ (2,-1)
  const std::vector<Vec3> c = {{-1, -1, 0},   {2, -1, 0},  {2, -0.5, 0}, {0.5, -0.5, 0},
                               {0.5, 0.5, 0}, {2, 0.5, 0}, {2, 1, 0},    {-1, 1, 0}};
  Frame f;
  f.center = {1, 0.75, 0};
  const RaySamples s = sample_radii(f, c, 4);
  EXPECT_NEAR(s.radii[0], 1.0, 1e-12);   // +x
  EXPECT_NEAR(s.radii[1], 0.25, 1e-12);  // +y
  EXPECT_NEAR(s.radii[2], 2.0, 1e-12);   // -x
  EXPECT_NEAR(s.radii[3], 1.75, 1e-12);  // -y: outermost of three crossings
  EXPECT_EQ(s.multi_crossing_rays, 1);
  EXPECT_EQ(s.missed_rays, 0);
}

TEST(Loop, PicksTheLeastLoopAroundThePointOrTheNearest) {
  std::vector<SlicePolyline> slice = {{square(3), true}, {square(1), true}, {square(0.5, 0), true}};
  for (Vec3& p : slice[2].points) p += Vec3(5, 0, 0);  // a separate loop to the side
  const std::optional<Loop> inner = loop_around(slice, Vec3::Zero(), Vec3::UnitZ(), 0);
  ASSERT_TRUE(inner);
  EXPECT_NEAR(inner->area, 4.0, 1e-12);  // the 2x2 square, not the 6x6 around it
  EXPECT_NEAR(inner->radius, std::sqrt(4.0 / std::numbers::pi), 1e-12);
  EXPECT_LT(inner->centroid.norm(), 1e-12);
  // Outside every loop: the nearest one within reach, else none.
  const Vec3 p(5.8, 0, 0);
  const std::optional<Loop> near = loop_around(slice, p, Vec3::UnitZ(), 0.5);
  ASSERT_TRUE(near);
  EXPECT_NEAR((near->centroid - Vec3(5, 0, 0)).norm(), 0, 1e-12);
  EXPECT_FALSE(loop_around(slice, p, Vec3::UnitZ(), 0.1));
}

// A closed polyline in the z = 0 plane, as a slice gives it.
SlicePolyline outline(const std::vector<Vec2>& q) {
  SlicePolyline line;
  line.closed = true;
  for (const Vec2& x : q) line.points.emplace_back(x.x(), x.y(), 0);
  return line;
}

// n + 1 points on the unit circle around `centre` from angle `from` to `to` (counter-clockwise).
void arc(std::vector<Vec2>& q, const Vec2& centre, double from, double to, int n) {
  for (int k = 0; k <= n; ++k) {
    const double a = from + (to - from) * k / n;
    q.push_back(centre + Vec2(std::cos(a), std::sin(a)));
  }
}

// Two unit discs whose centres are D = 1.99 apart, the outline of their union: a figure 8 pinched
// to a neck 0.2 wide between them (homer's thighs cut just above the crotch). The disc around the
// point, cut by the neck's chord, is the loop:
//
//      ___   ___
//    /     \/     \       the corners (D/2, ±h), h = sqrt(1 - D²/4); the neck is the chord
//   |   A   |   B   |     between them; the kept piece of A is the unit disc less the circular
//    \ ___ /\ ___ /       segment beyond the chord (of B, the same mirrored)
//
// Before necks were cut, loop_around returned the whole figure 8 (area ≈ 2π, centroid D/2).
TEST(Loop, AFigure8IsCutAtItsNeckAndThePointsDiscKept) {
  const double d = 1.99;
  const double alpha = std::acos(d / 2);  // the corners, seen from A's centre
  const int n = 2000;                     // points on each disc's arc
  std::vector<Vec2> q;
  arc(q, {0, 0}, alpha, 2 * std::numbers::pi - alpha, n);                     // A, the upper corner round
  q.pop_back();                                                               // the lower corner, once
  arc(q, {d, 0}, std::numbers::pi + alpha, 3 * std::numbers::pi - alpha, n);  // B, back up
  q.pop_back();
  const std::vector<SlicePolyline> slice = {outline(q)};
  // The disc less its segment beyond the chord: area π − (α − sin α cos α), centroid at
  // −(2/3) sin³α / area from the disc's centre, towards the far side from the neck.
  const double area = std::numbers::pi - (alpha - std::sin(alpha) * std::cos(alpha));
  const double shift = 2.0 / 3 * std::pow(std::sin(alpha), 3) / area;
  // The 2000-gon inscribed in the arc falls short of it by (2π/n)²/6 of the area (1.6e-6).
  const double tolerance = 1e-5;
  for (const bool in_a : {true, false}) {
    const Vec3 point = in_a ? Vec3(0.2, 0.3, 0) : Vec3(d - 0.4, -0.1, 0);
    const std::optional<Loop> loop = loop_around(slice, point, Vec3::UnitZ(), 0, Necks::cut);
    ASSERT_TRUE(loop);
    EXPECT_EQ(loop->necks_cut, 1);
    EXPECT_TRUE(loop->around);
    EXPECT_NEAR(loop->area, area, tolerance * area) << (in_a ? "A" : "B");
    EXPECT_NEAR(loop->radius, std::sqrt(area / std::numbers::pi), tolerance);
    const Vec3 centroid = in_a ? Vec3(-shift, 0, 0) : Vec3(d + shift, 0, 0);
    EXPECT_NEAR((loop->centroid - centroid).norm(), 0, tolerance) << (in_a ? "A" : "B");
    EXPECT_EQ(loop->points.size(), static_cast<std::size_t>(n + 1));  // the arc, corner to corner
  }
  // Necks::keep (the axis tracer's): the figure 8 as it is.
  const std::optional<Loop> whole = loop_around(slice, Vec3(0.2, 0.3, 0), Vec3::UnitZ(), 0);
  ASSERT_TRUE(whole);
  EXPECT_EQ(whole->necks_cut, 0);
  EXPECT_EQ(whole->points.size(), q.size());
  EXPECT_NEAR(whole->centroid.x(), d / 2, 1e-9);
}

// Sections of real parts that are no necks, however close two stretches of them come: a flat ear
// (an ellipse 50:1), a lobed tube (tube_lobed's 5 lobes of 0.2, and 3 lobes of 0.5), two discs
// fused broadly (a peanut: 1.6 wide between discs of radius 1), a C whose mouth is narrow (the
// chord across it runs outside). Each comes back whole, its area the polygon's own.
TEST(Loop, EllipsesLobesPeanutsAndCsAreNotCut) {
  const auto polygon_area = [](const std::vector<Vec2>& q) {
    double a2 = 0;
    for (std::size_t i = 0, j = q.size() - 1; i < q.size(); j = i++) {
      a2 += q[j].x() * q[i].y() - q[j].y() * q[i].x();
    }
    return std::abs(a2) / 2;
  };
  const auto polar = [](const auto& r, int n) {
    std::vector<Vec2> q;
    for (int k = 0; k < n; ++k) {
      const double a = 2 * std::numbers::pi * k / n;
      q.push_back(r(a) * Vec2(std::cos(a), std::sin(a)));
    }
    return q;
  };
  struct Case {
    const char* name;
    std::vector<Vec2> q;
    Vec2 point;
  };
  std::vector<Case> cases;
  {
    std::vector<Vec2> q;
    for (int k = 0; k < 400; ++k) {
      const double a = 2 * std::numbers::pi * k / 400;
      q.emplace_back(std::cos(a), 0.02 * std::sin(a));
    }
    cases.push_back({"ellipse 50:1", q, {0, 0}});
    cases.push_back({"ellipse 50:1, point off centre", q, {0.6, 0.005}});
  }
  cases.push_back({"5 lobes of 0.2", polar([](double a) { return 1 + 0.2 * std::cos(5 * a); }, 400), {0, 0}});
  cases.push_back({"3 lobes of 0.5", polar([](double a) { return 1 + 0.5 * std::cos(3 * a); }, 400), {0, 0}});
  {
    const double d = 1.2, alpha = std::acos(d / 2);
    std::vector<Vec2> q;
    arc(q, {0, 0}, alpha, 2 * std::numbers::pi - alpha, 200);
    q.pop_back();
    arc(q, {d, 0}, std::numbers::pi + alpha, 3 * std::numbers::pi - alpha, 200);
    q.pop_back();
    cases.push_back({"peanut", q, {-0.3, 0}});
  }
  {
    // An annulus 0.6 to 1 less a wedge of ±6° around +x: a mouth 0.21 wide, a band 0.4 wide.
    std::vector<Vec2> q;
    const double gap = 6 * std::numbers::pi / 180;
    for (int k = 0; k <= 200; ++k) {
      const double a = gap + (2 * std::numbers::pi - 2 * gap) * k / 200;
      q.emplace_back(std::cos(a), std::sin(a));
    }
    for (int k = 200; k >= 0; --k) {
      const double a = gap + (2 * std::numbers::pi - 2 * gap) * k / 200;
      q.emplace_back(0.6 * std::cos(a), 0.6 * std::sin(a));
    }
    cases.push_back({"C", q, {-0.8, 0}});
  }
  for (const Case& c : cases) {
    const std::optional<Loop> loop =
        loop_around({outline(c.q)}, Vec3(c.point.x(), c.point.y(), 0), Vec3::UnitZ(), 0, Necks::cut);
    ASSERT_TRUE(loop) << c.name;
    EXPECT_TRUE(loop->around) << c.name;
    EXPECT_EQ(loop->necks_cut, 0) << c.name;
    EXPECT_EQ(loop->points.size(), c.q.size()) << c.name;
    EXPECT_NEAR(loop->area, polygon_area(c.q), 1e-12 * polygon_area(c.q)) << c.name;
    std::vector<Vec2> q = c.q;
    EXPECT_EQ(cut_at_necks(q, c.point), 0) << c.name;
  }
}

TEST(Frames, RotationMinimizingOnAPlanarArcAddsNoTwist) {
  // A quarter circle in the x-z plane: the RMF of a planar curve keeps its binormal (here y).
  std::vector<Vec3> p, t;
  for (int i = 0; i <= 40; ++i) {
    const double a = std::numbers::pi / 2 * i / 40;
    p.emplace_back(1 - std::cos(a), 0, std::sin(a));
    t.emplace_back(std::sin(a), 0, std::cos(a));
  }
  const std::vector<Quat> f = rotation_minimizing_frames(p, t, Vec3::UnitY());
  for (std::size_t i = 0; i < f.size(); ++i) {
    const Mat3 m = f[i].toRotationMatrix();
    EXPECT_NEAR((m.transpose() * m - Mat3::Identity()).norm(), 0, 1e-12);
    EXPECT_NEAR((m.col(2) - t[i]).norm(), 0, 1e-12) << i;
    EXPECT_NEAR(m.col(0).dot(Vec3::UnitY()), 1, 1e-12) << i;
  }
}

TEST(Frames, RotationMinimizingOnAHelixHasNoSpin) {
  // On a helix the RMF's angular velocity has no component along the tangent: between close
  // stations the x axis turns only as much as the tangent does.
  std::vector<Vec3> p, t;
  for (int i = 0; i <= 400; ++i) {
    const double a = 4 * std::numbers::pi * i / 400;
    p.emplace_back(std::cos(a), std::sin(a), 0.5 * a);
    t.push_back(Vec3(-std::sin(a), std::cos(a), 0.5).normalized());
  }
  const std::vector<Quat> f = rotation_minimizing_frames(p, t);
  for (std::size_t i = 1; i + 1 < f.size(); ++i) {
    // Twist rate: dx/ds projected on y = t × x (central difference), 0 for an RMF up to the
    // discretisation (~1e-4 here); the Frenet frame would turn at the torsion, 0.4 rad per unit.
    const Vec3 dx = f[i + 1] * Vec3::UnitX() - f[i - 1] * Vec3::UnitX();
    EXPECT_NEAR(dx.dot(f[i] * Vec3::UnitY()) / (p[i + 1] - p[i - 1]).norm(), 0, 1e-3) << i;
  }
}

// A strip of triangles along x (a "body" and "tail") with a "leg" in front of the root plane
// that is attached only to the body behind it:
//
//   b0---b1---b2---b3---b4        y = 1        root plane x = 1.5, normal +x, disc radius 1
//   | \  | \  | \  | \  |                      tip at (4, 0.5): part = {a2..a4, b2..b4}
//   a0---a1---a2---a3---a4        y = 0
//   leg: l0 (3, -5), l1 (4, -5), joined to a0 by the triangle (a0, l1, l0)
TEST(Part, FloodStopsAtTheRootPlaneAndLeavesLegsOut) {
  Mesh m;
  for (int i = 0; i < 5; ++i) m.positions.emplace_back(i, 0, 0);  // a_i = i
  for (int i = 0; i < 5; ++i) m.positions.emplace_back(i, 1, 0);  // b_i = 5 + i
  m.positions.emplace_back(3, -5, 0);                             // l0 = 10
  m.positions.emplace_back(4, -5, 0);                             // l1 = 11
  for (std::uint32_t i = 0; i < 4; ++i) {
    m.add_face({i, i + 1, 5 + i});
    m.add_face({i + 1, 6 + i, 5 + i});
  }
  m.add_face({0, 11, 10});
  Frame root;
  root.rotation = Quat::FromTwoVectors(Vec3::UnitZ(), Vec3::UnitX());
  root.center = {1.5, 0.5, 0};
  const Topology topology = build_topology(m);
  const std::vector<std::uint32_t> part = select_part(m, topology, root, 1.0, {4, 0.5, 0});
  EXPECT_EQ(part, (std::vector<std::uint32_t>{2, 3, 4, 7, 8, 9}));
  // A half-space would have taken the leg too.
  EXPECT_GT((m.positions[10] - root.center).dot(root.axis()), 0);
  // The tip behind the root section itself is a bad request.
  EXPECT_THROW(select_part(m, topology, root, 1.0, {1, 0.1, 0}), Error);
  // A disc too small to close the strip off: the flood passes the plane beside it, and takes
  // the body and the leg as well.
  EXPECT_EQ(select_part(m, topology, root, 0.2, {4, 0.5, 0}).size(), 12u);
}

// A bound on the walk (select_sweep_part's: near the sweep) stops it where the part touches
// another surface, and what lies beyond the bound is judged: a bridge that leads behind the root
// (a tusk into the head) stays out, and so does a limb that reaches farther than the protrusion
// reach (however few its vertices: the rule is a length, not a count), each with its foot inside
// the bound where that is off the part's surface; a protrusion that leads nowhere near (a spike)
// stays in.
TEST(Part, ABoundStopsTheFloodAtABridgeButKeepsAProtrusion) {
  Mesh m;
  for (int i = 0; i < 10; ++i) m.positions.emplace_back(i, 0, 0);  // a_i = i
  for (int i = 0; i < 10; ++i) m.positions.emplace_back(i, 1, 0);  // b_i = 10 + i
  const std::uint32_t c0 = 20, c1 = 21, c2 = 22, c3 = 23;          // the bridge, from a_5 round to x = 0
  m.positions.insert(m.positions.end(), {{5, -1, 0}, {5, -2, 0}, {5, -3, 0}, {0, -3, 0}});
  const std::uint32_t d0 = 24, d1 = 25, d2 = 26;  // the spike, out from a_7
  m.positions.insert(m.positions.end(), {{7, -1, 0}, {7, -2, 0}, {7, -3, 0}});
  const std::uint32_t e0 = 27, e1 = 28, e2 = 29;  // the limb, out from a_9: two long triangles
  m.positions.insert(m.positions.end(), {{9, -1, 0}, {9, -2, 0}, {9, -6, 0}});
  for (std::uint32_t i = 0; i < 9; ++i) {
    m.add_face({i, i + 1, 10 + i});
    m.add_face({i + 1, 11 + i, 10 + i});
  }
  m.add_face({5, c0, 6});
  m.add_face({c0, c1, 6});
  m.add_face({c1, c2, c0});
  m.add_face({c2, c3, c1});
  m.add_face({7, d0, 8});
  m.add_face({d0, d1, 8});
  m.add_face({d1, d2, d0});
  m.add_face({8, e0, 9});
  m.add_face({e0, e1, 8});
  m.add_face({e1, e2, e0});
  const Topology topology = build_topology(m);
  Frame root;
  root.rotation = Quat::FromTwoVectors(Vec3::UnitZ(), Vec3::UnitX());
  root.center = {1.5, 0.5, 0};
  PartBound near_strip;
  near_strip.within = [](const Vec3& p) { return p.y() >= -1.5; };
  near_strip.protrusion_reach = [](const Vec3&) { return 3.5; };
  std::vector<std::uint32_t> expected;
  for (std::uint32_t i = 2; i < 10; ++i) expected.insert(expected.end(), {i, 10 + i});
  expected.insert(expected.end(), {c0, d0, d1, d2, e0});
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(select_part(m, topology, root, 1.0, {9, 0.5, 0}, near_strip), expected);
  // Unbounded, the walk takes the bridge as well, to the vertex behind the root.
  EXPECT_EQ(select_part(m, topology, root, 1.0, {9, 0.5, 0}).size(), expected.size() + 5);
  // A bridge's foot inside the bound, off the part's surface (the strip, y in [0, 1]), goes with
  // it: c0 under the bridge and e0 under the limb; d0 under the spike stays, a protrusion's.
  near_strip.on_surface = [](const Vec3& p) { return p.y() >= -0.5; };
  std::vector<std::uint32_t> without_feet;
  std::copy_if(expected.begin(), expected.end(), std::back_inserter(without_feet),
               [&](std::uint32_t v) { return v != c0 && v != e0; });
  EXPECT_EQ(select_part(m, topology, root, 1.0, {9, 0.5, 0}, near_strip), without_feet);
  near_strip.on_surface = nullptr;
  // A reach past the limb's end keeps the limb as well.
  near_strip.protrusion_reach = [](const Vec3&) { return 7.0; };
  EXPECT_EQ(select_part(m, topology, root, 1.0, {9, 0.5, 0}, near_strip).size(), expected.size() + 2);
}

// A strip that goes on past the tip (the a/b strip above, longer: a_i = i, b_i = 10 + i, i = 0..9):
// cut at the root plane x = 1.5 and the tip plane x = 6.5, the part is x = 2..6 whatever side the
// tip point lies on; the one-sided flood takes the strip on to x = 9.
TEST(Part, TipCutBoundsTheFloodOnTheTipSideToo) {
  Mesh m;
  for (int i = 0; i < 10; ++i) m.positions.emplace_back(i, 0, 0);
  for (int i = 0; i < 10; ++i) m.positions.emplace_back(i, 1, 0);
  for (std::uint32_t i = 0; i < 9; ++i) {
    m.add_face({i, i + 1, 10 + i});
    m.add_face({i + 1, 11 + i, 10 + i});
  }
  const Topology topology = build_topology(m);
  Frame root, tip;
  root.rotation = tip.rotation = Quat::FromTwoVectors(Vec3::UnitZ(), Vec3::UnitX());
  root.center = {1.5, 0.5, 0};
  tip.center = {6.5, 0.5, 0};
  EXPECT_EQ(select_part(m, topology, root, 1.0, {6, 0.5, 0}).size(), 16u);
  const std::vector<std::uint32_t> part = select_part_between(m, topology, root, 1.0, tip, 1.0);
  EXPECT_EQ(part, (std::vector<std::uint32_t>{2, 3, 4, 5, 6, 12, 13, 14, 15, 16}));
  // A tip disc that meets no edge (off the strip) is a bad request, and so is one whose root side
  // reaches the root section only from behind (cut at x = 1, facing the body).
  tip.center = {6.5, 5, 0};
  EXPECT_THROW(select_part_between(m, topology, root, 1.0, tip, 1.0), Error);
  tip.center = {0.5, 0.5, 0};
  tip.rotation = Quat::FromTwoVectors(Vec3::UnitZ(), -Vec3::UnitX());
  EXPECT_THROW(select_part_between(m, topology, root, 1.0, tip, 1.0), Error);
}

// A vertex split along a UV seam (same position, two indices) is one vertex to the flood: the
// part goes on across the seam and takes both copies.
TEST(Part, SeamSplitVerticesAreWeldedForTheWalk) {
  Mesh m;
  for (int i = 0; i < 4; ++i) m.positions.emplace_back(i, 0, 0);  // 0..3
  for (int i = 0; i < 4; ++i) m.positions.emplace_back(i, 1, 0);  // 4..7
  m.positions.emplace_back(2, 0, 0);                              // 8: a copy of 2
  m.positions.emplace_back(2, 1, 0);                              // 9: a copy of 6
  m.add_face({0, 1, 4});
  m.add_face({1, 5, 4});
  m.add_face({1, 2, 5});
  m.add_face({2, 6, 5});
  m.add_face({8, 3, 9});  // the far side of the seam uses the copies
  m.add_face({3, 7, 9});
  const Topology topology = build_topology(m);
  EXPECT_EQ(topology.welded_count, 2u);
  EXPECT_EQ(topology.weld[8], 2u);
  EXPECT_EQ(topology.weld[9], 6u);
  Frame root;
  root.rotation = Quat::FromTwoVectors(Vec3::UnitZ(), -Vec3::UnitX());
  root.center = {-0.5, 0.5, 0};  // behind everything: nothing blocks
  EXPECT_EQ(select_part(m, topology, root, 0.1, {0, 0, 0}).size(), 10u);
  // Without the weld the walk would stop at the seam: the own-edges adjacency has no edge 2–3.
  const VertexAdjacency own = vertex_adjacency(m);
  EXPECT_EQ(std::count(own.neighbours.begin() + own.offsets[2], own.neighbours.begin() + own.offsets[3], 3u), 0);
}

// The slicer sees a seam as the walk does. A tube of 4 rings of 6 whose faces across the seam (from
// segment 5 to segment 0) use copies of segment 0's vertices, as an exporter splits a UV seam: a
// slice between rings is one closed loop, not an open polyline with a gap at the seam (a hole the
// fit warned about and closed across).
// The tube is turned about an oblique axis and cut by an oblique plane: the seam's edge and its copy
// run opposite ways, and each gives the plane's crossing with its own rounding, so the ends of an
// unwelded slice miss each other (on axis-aligned numbers they meet exactly and hide the gap).
TEST(Slicer, SeamSplitVerticesSliceAsOneClosedLoop) {
  constexpr int rings = 4, segments = 6;
  const Eigen::AngleAxisd turn(0.7, Vec3(1, 2, 3).normalized());
  Mesh m;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j <= segments; ++j) {  // j = segments: the seam's copy of j = 0
      const double th = 2 * std::numbers::pi * j / segments;
      m.positions.push_back(turn * Vec3(std::cos(th), std::sin(th), i));
    }
  for (int i = 0; i < rings; ++i)
    m.positions[i * (segments + 1) + segments] = m.positions[i * (segments + 1)];  // exactly
  const auto id = [](int i, int j) { return static_cast<std::uint32_t>(i * (segments + 1) + j); };
  for (int i = 0; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) m.add_face({id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)});
  const std::vector<SlicePolyline> slice = MeshSlicer(m).slice(turn * Vec3(0.1, 0.05, 1.37), turn * Vec3(0.1, 0.05, 1));
  ASSERT_EQ(slice.size(), 1u);
  EXPECT_TRUE(slice[0].closed);
  EXPECT_EQ(slice[0].points.size(), static_cast<std::size_t>(2 * segments));  // side edges and quads' diagonals
}

// Faces add_face refuses are taken locally: one turned against its neighbours goes in turned over
// (its ring stays one loop), and a fin on one of the tube's edges (three faces at an edge) with a
// copy of a corner, its slice a piece of its own beside the tube's closed loop.
TEST(Slicer, AFaceTurnedOverAndAFinOnAnEdgeLeaveTheTubesLoopClosed) {
  constexpr int rings = 4, segments = 8;
  const Eigen::AngleAxisd turn(0.7, Vec3(1, 2, 3).normalized());
  Mesh m;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = 2 * std::numbers::pi * j / segments;
      m.positions.push_back(turn * Vec3(std::cos(th), std::sin(th), i));
    }
  const auto id = [](int i, int j) { return static_cast<std::uint32_t>(i * segments + j % segments); };
  for (int i = 0; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      if (i == 1 && j == 3) {
        m.add_face({id(i, j), id(i + 1, j + 1), id(i, j + 1)});  // turned over
      } else {
        m.add_face({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
      }
      m.add_face({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
    }
  m.positions.push_back(turn * Vec3(2.5, 0, 1.5));  // a fin on the edge from (1, 0) to (2, 0)
  m.add_face({id(1, 0), id(2, 0), static_cast<std::uint32_t>(m.positions.size() - 1)});
  const MeshSlicer slicer(m);
  EXPECT_GE(slicer.repaired_face_count(), 2u) << "the turned face (or a neighbour) and the fin";
  const std::vector<SlicePolyline> slice = slicer.slice(turn * Vec3(0.1, 0.05, 1.37), turn * Vec3(0, 0, 1));
  int closed = 0;
  for (const SlicePolyline& pl : slice) {
    if (!pl.closed) continue;
    ++closed;
    EXPECT_EQ(pl.points.size(), static_cast<std::size_t>(2 * segments));  // side edges and diagonals
  }
  EXPECT_EQ(closed, 1);
  EXPECT_EQ(slice.size(), 2u) << "the tube's loop and the fin's piece";
}

}  // namespace
}  // namespace sweep::fit
