// find_parts on shapes whose parts are known: a body with one tube (one part, ending where the
// tube does, starting where it leaves the body), a lone tube (the whole mesh), and flat pieces
// (no part: rings that enclose nothing are no tube).
#include "sweep/fit/discover.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <set>
#include <utility>

#include "curve_tubes.h"
#include "sweep/core/topology.h"
#include "sweep/fit/fit.h"
#include "sweep/fit/hole_patches.h"

namespace sweep::test {
namespace {

constexpr double kTubeR = 0.1;  // the tubes' radius

TEST(Discover, ABodyWithOneTubeHasOnePartEndingWhereTheTubeEnds) {
  // A body 4r wide over 10r, then a straight tube of 12r along +Z.
  const double body_length = 10 * kTubeR, tube_length = 12 * kTubeR;
  CurveTube t;
  t.curve = [=](double u) { return Vec3(0, 0, u * (body_length + tube_length)); };
  t.radius = with_body(4 * kTubeR, body_length, [](double) { return kTubeR; });
  const Mesh mesh = t.mesh();
  const std::vector<fit::FoundPart> parts = fit::find_parts(mesh, build_topology(mesh));
  ASSERT_EQ(parts.size(), 1u);
  const fit::FoundPart& p = parts[0];
  EXPECT_NEAR(p.tip.z(), body_length + tube_length + kTubeR, 0.2 * kTubeR) << "the tip is the cap's end";
  EXPECT_NEAR(p.root.z(), body_length, 2 * kTubeR) << "the root is where the tube leaves the body";
  EXPECT_NEAR(p.mean_radius, kTubeR, 0.05 * kTubeR);
}

TEST(Discover, ALoneTubeIsOnePart) {
  CurveTube t;
  t.curve = [](double u) { return Vec3(0, 0, 2 * u); };
  t.radius = [](double) { return kTubeR; };
  const Mesh mesh = t.mesh();
  const std::vector<fit::FoundPart> parts = fit::find_parts(mesh, build_topology(mesh));
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_NEAR(parts[0].mean_radius, kTubeR, 0.05 * kTubeR);
  EXPECT_GT(parts[0].length, 1.5);
}

TEST(Discover, FlatPiecesHaveNoParts) {
  Mesh triangle;
  triangle.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  triangle.add_face({0, 1, 2});
  EXPECT_TRUE(fit::find_parts(triangle, build_topology(triangle)).empty());
  // A long strip of quads: long and thin, but flat.
  Mesh strip;
  for (int i = 0; i <= 40; ++i) {
    strip.positions.push_back(Vec3(0.1 * i, 0, 0));
    strip.positions.push_back(Vec3(0.1 * i, 0.1, 0));
  }
  for (std::uint32_t i = 0; i < 40; ++i) strip.add_face({2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1});
  EXPECT_TRUE(fit::find_parts(strip, build_topology(strip)).empty());
}

// The mesh without the triangles `drop` selects (by their centroid): holes punched in it.
Mesh without(const Mesh& mesh, const std::function<bool(const Vec3&)>& drop) {
  Mesh out;
  out.positions = mesh.positions;
  const std::vector<std::uint32_t> tris = mesh.triangles();
  for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
    const Vec3 c = (mesh.positions[tris[t]] + mesh.positions[tris[t + 1]] + mesh.positions[tris[t + 2]]) / 3;
    if (!drop(c)) out.add_face({tris[t], tris[t + 1], tris[t + 2]});
  }
  return out;
}

TEST(Discover, AHoleInTheBodyLeavesTheTubeAsItWas) {
  const double body_length = 10 * kTubeR, tube_length = 12 * kTubeR;
  CurveTube t;
  t.curve = [=](double u) { return Vec3(0, 0, u * (body_length + tube_length)); };
  t.radius = with_body(4 * kTubeR, body_length, [](double) { return kTubeR; });
  const Mesh whole = t.mesh();
  // A hole 2r across in the body's side, away from the tube.
  const Mesh holed = without(whole, [&](const Vec3& c) {
    return c.x() > 0 && std::abs(c.y()) < kTubeR && std::abs(c.z() - 0.4 * body_length) < kTubeR;
  });
  ASSERT_LT(holed.face_count(), whole.face_count());
  ASSERT_GT(hole_edge_count(build_topology(holed)), 0u);
  EXPECT_EQ(hole_edge_count(build_topology(whole)), 0u);
  const std::vector<fit::FoundPart> before = fit::find_parts(whole, build_topology(whole));
  const std::vector<fit::FoundPart> after = fit::find_parts(holed, build_topology(holed));
  ASSERT_EQ(before.size(), 1u);
  ASSERT_EQ(after.size(), 1u);
  EXPECT_EQ(after[0].tip_vertex, before[0].tip_vertex);
  EXPECT_NEAR(after[0].mean_radius, kTubeR, 0.05 * kTubeR);
  EXPECT_NEAR(after[0].root.z(), before[0].root.z(), kTubeR);
}

TEST(Discover, AnOpenSheetCutFromATubeHasNoParts) {
  // A tube 20 radii long cut open along its length and its end cut off: a trough, long and thin
  // like a tube, but rings of surface distance from any point of it run into its rims. (Such
  // rings, measured anyway, gave parts a vertex or two long and a hundredth of a radius wide on
  // open meshes: mech-holes-shark, holes, blobby_3cc.)
  CurveTube t;
  t.curve = [](double u) { return Vec3(0, 0, 20 * kTubeR * u); };
  t.radius = [](double) { return kTubeR; };
  const Mesh tube = t.mesh();
  const Mesh trough = without(tube, [](const Vec3& c) { return c.y() > 0.3 * kTubeR || c.z() < 0; });
  ASSERT_GT(hole_edge_count(build_topology(trough)), 0u);
  EXPECT_TRUE(fit::find_parts(trough, build_topology(trough)).empty());
  // sweep-fit searches the patched surface: its rim, as long as the mesh, is an open side, not a
  // gap in a part, and stays open.
  EXPECT_FALSE(fit::patched_topology(trough, build_topology(trough)).has_value());
}

// A body with a tube of 12r, and a hole about a radius across in the tube's side halfway along:
// the rings of surface distance from the tip run into it (CGAL's elephant-with-holes,
// 141 holes, once listed no part and fitted its legs 0.03–0.04 long).
struct HoledTube {
  static constexpr double kBody = 10 * kTubeR, kTube = 12 * kTubeR, kHoleAt = kBody + 0.5 * kTube;
  Mesh whole, holed;
  HoledTube() {
    CurveTube t;
    t.curve = [](double u) { return Vec3(0, 0, u * (kBody + kTube)); };
    t.radius = with_body(4 * kTubeR, kBody, [](double) { return kTubeR; });
    whole = t.mesh();
    holed = without(whole, [](const Vec3& c) {
      return c.x() > 0 && std::abs(c.y()) < 0.8 * kTubeR && std::abs(c.z() - kHoleAt) < kTubeR;
    });
  }
};

TEST(HolePatches, AHoleIsClosedOverItsRimsOwnVerticesKeepingTheOrientation) {
  const HoledTube t;
  const Topology topology = build_topology(t.holed);
  const std::vector<std::vector<std::uint32_t>> rims = hole_rims(topology);
  ASSERT_EQ(rims.size(), 1u);
  EXPECT_EQ(rims[0].size(), hole_edge_count(topology));
  for (const std::uint32_t v : rims[0]) {
    const Vec3& p = t.holed.positions[v];
    EXPECT_GT(p.x(), 0);
    EXPECT_LT(std::abs(p.z() - HoledTube::kHoleAt), kTubeR);
  }
  const std::optional<Topology> patched_or_none = fit::patched_topology(t.holed, topology);
  ASSERT_TRUE(patched_or_none.has_value());
  const Topology& patched = *patched_or_none;
  EXPECT_EQ(hole_edge_count(patched), 0u);
  EXPECT_EQ(patched.triangles.size() - topology.triangles.size(), 3 * (rims[0].size() - 2))
      << "a disc over the rim: two triangles fewer than its vertices";
  EXPECT_EQ(patched.weld, topology.weld) << "no vertex added";
  // Closed and oriented: every edge is run once each way.
  std::set<std::pair<std::uint32_t, std::uint32_t>> runs;
  for (std::size_t f = 0; f + 2 < patched.triangles.size(); f += 3) {
    for (std::size_t k = 0; k < 3; ++k) {
      const auto run = std::make_pair(patched.triangles[f + k], patched.triangles[f + (k + 1) % 3]);
      EXPECT_TRUE(runs.insert(run).second) << run.first << " -> " << run.second << " twice";
    }
  }
  for (const auto& [a, b] : runs) EXPECT_TRUE(runs.count({b, a})) << a << " -> " << b << " alone";
  // The rows follow the triangles: rim vertices now neighbour vertices across the hole.
  std::size_t gained = 0;
  for (const std::uint32_t v : rims[0]) gained += patched.adjacency.of(v).size() - topology.adjacency.of(v).size();
  EXPECT_EQ(gained, 2 * (rims[0].size() - 3)) << "each of the patch's diagonals, both ways";
  EXPECT_EQ(patched.vertex_triangles.neighbours.size(), patched.triangles.size());
}

TEST(HolePatches, TwoHolesTouchingAtAVertexAreTwoRimsEachPatched) {
  // Two triangles of the fan around one vertex that share nothing else, taken out: two holes
  // meeting at that vertex, whose rim edges chain into one figure-eight through it (its patch
  // folded over the surface between them, found in review).
  const Mesh whole = HoledTube().whole;
  const std::vector<std::uint32_t> tris = whole.triangles();
  const std::uint32_t v = tris[3 * (tris.size() / 6)];  // a vertex halfway through the faces
  std::vector<std::size_t> fan;
  for (std::size_t f = 0; f + 2 < tris.size(); f += 3) {
    if (tris[f] == v || tris[f + 1] == v || tris[f + 2] == v) fan.push_back(f);
  }
  const auto shared = [&](std::size_t f, std::size_t g) {
    int n = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) n += tris[f + i] == tris[g + j];
    return n;
  };
  // Every such pair (the walk along the rims picks its way at the shared vertex by index, so
  // some pairs chained into one figure-eight and some did not).
  int pairs = 0;
  for (std::size_t i = 0; i < fan.size(); ++i) {
    for (std::size_t j = i + 1; j < fan.size(); ++j) {
      if (shared(fan[i], fan[j]) != 1) continue;
      ++pairs;
      Mesh holed;
      holed.positions = whole.positions;
      for (std::size_t f = 0; f + 2 < tris.size(); f += 3) {
        if (f != fan[i] && f != fan[j]) holed.add_face({tris[f], tris[f + 1], tris[f + 2]});
      }
      const Topology topology = build_topology(holed);
      ASSERT_EQ(hole_edge_count(topology), 6u);
      const std::vector<std::vector<std::uint32_t>> rims = hole_rims(topology);
      ASSERT_EQ(rims.size(), 2u) << "fan triangles " << i << " and " << j;
      for (const std::vector<std::uint32_t>& rim : rims) {
        EXPECT_EQ(rim.size(), 3u);
        EXPECT_EQ(std::count(rim.begin(), rim.end(), v), 1);
      }
      const std::optional<Topology> patched = fit::patched_topology(holed, topology);
      ASSERT_TRUE(patched.has_value());
      EXPECT_EQ(hole_edge_count(*patched), 0u);
      EXPECT_EQ(patched->triangles.size(), tris.size()) << "each hole closed by its own triangle";
    }
  }
  EXPECT_GE(pairs, 3);
}

TEST(HolePatches, AClosedMeshIsLeftAsItWas) {
  const HoledTube t;
  const Topology topology = build_topology(t.whole);
  EXPECT_TRUE(hole_rims(topology).empty());
  EXPECT_TRUE(fit::hole_patches(t.whole, topology).empty());
  EXPECT_FALSE(fit::patched_topology(t.whole, topology).has_value());
}

TEST(HolePatches, AHoleInTheTubeNeitherHidesNorShortensThePart) {
  const HoledTube t;
  const std::vector<fit::FoundPart> whole = fit::find_parts(t.whole, build_topology(t.whole));
  const Topology topology = build_topology(t.holed);
  const std::vector<fit::FoundPart> patched =
      fit::find_parts(t.holed, fit::patched_topology(t.holed, topology).value());
  ASSERT_EQ(whole.size(), 1u);
  ASSERT_EQ(patched.size(), 1u);
  EXPECT_EQ(patched[0].tip_vertex, whole[0].tip_vertex);
  EXPECT_NEAR(patched[0].root.z(), whole[0].root.z(), 0.5 * kTubeR);
  EXPECT_NEAR(patched[0].mean_radius, kTubeR, 0.05 * kTubeR);

  // The fit from the tip, the root found: as on the whole mesh, the hole's side included.
  fit::FitOptions o;
  o.tip = whole[0].tip;
  o.measure_error = true;
  const fit::FitResult a = fit::fit_sweep(t.whole, o), b = fit::fit_sweep(t.holed, o);
  ASSERT_TRUE(b.problems.empty()) << b.problems.front();
  EXPECT_NEAR(b.traced_length, a.traced_length, 0.1 * kTubeR);
  EXPECT_NEAR(b.sweep.rest.frames.front().center.z(), a.sweep.rest.frames.front().center.z(), 0.5 * kTubeR);
  // Measured: the centres stay within 0.001r of the axis (unpatched, the slices across the hole
  // are closed by their gap and their centres slip 0.15r towards the other side).
  double off = 0;
  for (const Frame& f : b.sweep.rest.frames) off = std::max(off, std::hypot(f.center.x(), f.center.y()));
  EXPECT_LT(off, 0.02 * kTubeR);
  // The way back measures to the patch over the hole, not to faces a radius away from it:
  // measured 0.0043r as on the whole mesh (unpatched, 0.0108r).
  EXPECT_LT(b.error.surface_p90, 1.2 * a.error.surface_p90);
}

TEST(Discover, VerticesNoFaceUsesTakeNoSourceOfTheAverage) {
  // A file may list vertices no face uses (and cutting a hole leaves them): farthest-point
  // sampling took each as a source of its own, unreachable as it is, and with 24 samples and 23
  // such vertices the part had one source left, at its own tip, which then was no maximum: no part.
  const HoledTube t;
  Mesh loose = t.whole;
  for (int i = 0; i < 40; ++i) loose.positions.push_back(Vec3(5 + i * kTubeR, 0, 0));
  const std::vector<fit::FoundPart> whole = fit::find_parts(t.whole, build_topology(t.whole));
  const std::vector<fit::FoundPart> parts = fit::find_parts(loose, build_topology(loose));
  ASSERT_EQ(whole.size(), 1u);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].tip_vertex, whole[0].tip_vertex);
  EXPECT_NEAR(parts[0].root.z(), whole[0].root.z(), 1e-9);
  // Nor is a loose vertex 0 where the sampling starts (two samples: the first must be the far end
  // of the part, as without it).
  Mesh first;
  first.positions.push_back(Vec3(5, 0, 0));
  first.positions.insert(first.positions.end(), t.whole.positions.begin(), t.whole.positions.end());
  const std::vector<std::uint32_t> tris = t.whole.triangles();
  for (std::size_t f = 0; f + 2 < tris.size(); f += 3) first.add_face({tris[f] + 1, tris[f + 1] + 1, tris[f + 2] + 1});
  fit::DiscoverOptions two;
  two.samples = 2;
  const std::vector<fit::FoundPart> a = fit::find_parts(t.whole, build_topology(t.whole), two);
  const std::vector<fit::FoundPart> b = fit::find_parts(first, build_topology(first), two);
  ASSERT_EQ(a.size(), 1u);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].tip_vertex, a[0].tip_vertex + 1);
}

}  // namespace
}  // namespace sweep::test
