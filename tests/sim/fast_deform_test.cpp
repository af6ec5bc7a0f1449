// The fast deformation path against the exact per-vertex path.
#include "sim/fast_deform.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <random>

#include "core/elastic_sweep.h"
#include "core/sample_sweeps.h"
#include "sim/sweep_cloud.h"

namespace sweep::sim {
namespace {

// Points inside and on the sweep, s from 0.2 to 1, caps beyond both ends.
using Cloud = test::SweepCloud;
Cloud cloud_on(const SweepShape& shape, int count) {
  return test::sweep_cloud(shape, count, 0.2, 0.8);
}

double worst_error(const SweepShape& deformed, const Cloud& c, FastDeformer& fast) {
  std::vector<Vec3f> out = c.rest;
  fast.deform(deformed, out);
  double worst = 0;
  for (std::size_t v = 0; v < out.size(); ++v) {
    const Vec3 exact = deform_point(deformed, c.bound.coords(v));
    worst = std::max(worst, (out[v].cast<double>() - exact).norm());
  }
  return worst;
}

TEST(FastDeform, RestIsReproducedToFloatPrecision) {
  const SweepShape shape = test::irregular_shape(8, 8);
  const Cloud c = cloud_on(shape, 3000);
  FastDeformer fast(shape, c.bound, c.rest, 8);
  std::vector<Vec3f> out(c.rest.size(), Vec3f::Zero());
  fast.deform(shape, out);
  double worst = 0;
  for (std::size_t v = 0; v < out.size(); ++v)
    worst = std::max(worst, double((out[v] - c.rest[v]).norm()));
  // Stations interpolate linearly in t, so between stations the rest pose is not exact: the error
  // is the chord error of the centre curve and frames, which falls as (station spacing)².
  EXPECT_LT(worst, 1e-3 * shape.length());
}

TEST(FastDeform, ErrorAgainstTheExactPathFallsQuadraticallyWithStations) {
  ElasticSweep sweep(test::sweep_def(test::irregular_shape(8, 8)));
  sweep.set_section_pose(3, Vec3(0.05, 0, 0), Vec3(0.3, 0.1, 0.4));
  sweep.set_radial_offset(5, 2, 0.15);
  const Cloud c = cloud_on(sweep.rest(), 4000);
  double previous = 0;
  for (int stations : {2, 4, 8, 16}) {
    FastDeformer fast(sweep.rest(), c.bound, c.rest, stations);
    const double e = worst_error(sweep.deformed(), c, fast);
    if (previous > 0) {
      EXPECT_LT(e, previous / 3) << stations << " stations";  // ~4× per doubling
    }
    previous = e;
  }
  EXPECT_LT(previous, 2e-4 * sweep.rest().length());
}

TEST(FastDeform, BlendWeightMixesRestAndSweep) {
  ElasticSweep sweep(test::sweep_def(test::straight_shape(5, 6, 0.5)));
  Cloud c = cloud_on(sweep.rest(), 50);
  c.bound.weight[7] = 0.0f;
  c.bound.weight[8] = 0.5f;
  sweep.set_section_pose(1, Vec3::Zero(), Vec3(0.5, 0, 0));
  FastDeformer fast(sweep.rest(), c.bound, c.rest, 8);
  std::vector<Vec3f> out = c.rest;
  fast.deform(sweep.deformed(), out);
  EXPECT_EQ(out[7], c.rest[7]);
  const Vec3f full = deform_point(sweep.deformed(), c.bound.coords(8)).cast<float>();
  EXPECT_LT((out[8] - 0.5f * (full + c.rest[8])).norm(), 1e-3f);
}

TEST(FastDeform, OnlyItsOwnVerticesAreWritten) {
  const SweepShape shape = test::straight_shape(4, 6, 0.5);
  Cloud c = cloud_on(shape, 20);
  // Vertex indices 100.. in a 200-vertex mesh.
  for (auto& v : c.bound.vertices) v += 100;
  std::vector<Vec3f> rest(200, Vec3f(9, 9, 9));
  FastDeformer fast(shape, c.bound, rest, 4);
  std::vector<Vec3f> out(200, Vec3f(7, 7, 7));
  fast.deform(shape, out);
  for (int v = 0; v < 100; ++v) EXPECT_EQ(out[v], Vec3f(7, 7, 7));
  for (int v = 120; v < 200; ++v) EXPECT_EQ(out[v], Vec3f(7, 7, 7));
  EXPECT_NE(out[100], Vec3f(7, 7, 7));
}

TEST(FastDeform, AtStationsAndSampleAnglesTheTableIsTheExactSweep) {
  // At a station (u = 0) and a sample angle (w = 0) nothing is interpolated by the fast path: what
  // is left is the station table itself (slerp by recurrence, Hermite centre, radius cubics), which
  // must match the exact evaluation to float precision, also across a twist of more than 180°
  // between sections (the quaternion sign flip) and with a cap offset.
  SweepShape shape = test::irregular_shape(6, 8);
  shape.frames[4].rotation = shape.frames[4].rotation * Quat(Eigen::AngleAxisd(3.6, Vec3::UnitZ()));
  shape.frames[5].rotation = shape.frames[4].rotation;
  ElasticSweep sweep(test::sweep_def(shape));
  sweep.set_section_pose(2, Vec3(0.02, 0, 0.01), Vec3(0.4, -0.3, 1.9));
  sweep.set_radial_offset(3, 5, -0.2);
  const int stations = 4;
  bind::SweepBinding b;
  std::vector<Vec3f> rest;
  for (int s = 0; s + 1 < shape.section_count(); ++s) {
    for (int q = 0; q < stations; ++q) {
      for (int j = 0; j < shape.radial_count; ++j) {
        b.vertices.push_back(static_cast<std::uint32_t>(b.vertices.size()));
        b.t.push_back(
            static_cast<float>(shape.t[s] + (shape.t[s + 1] - shape.t[s]) * q / stations));
        b.theta.push_back(static_cast<float>(shape.sample_angle(j)));
        b.s.push_back(0.9f);
        b.z.push_back(s == 0 && q == 0 && j == 0 ? -0.3f : 0.0f);
        b.weight.push_back(1.0f);
        rest.push_back(Vec3f::Zero());
      }
    }
  }
  FastDeformer fast(shape, b, rest, stations);
  std::vector<Vec3f> out = rest;
  fast.deform(sweep.deformed(), out);
  for (std::size_t v = 0; v < out.size(); ++v) {
    // The float-stored coordinates, as the fast path sees them.
    const Vec3 exact = deform_point(sweep.deformed(), b.coords(v));
    EXPECT_LT((out[v].cast<double>() - exact).norm(), 2e-6 * shape.length()) << "vertex " << v;
  }
}

TEST(FastDeform, RingOrderedMeshIsWrittenInPlaceAndMatchesTheExactPath) {
  // A mesh in ring order (as generated tubes and many scanned parts are): each block is one
  // contiguous range of mesh indices, computed straight into the mesh. Every vertex must land
  // where the exact path puts it, and nothing outside the bound range may be touched.
  ElasticSweep sweep(test::sweep_def(test::irregular_shape(6, 8)));
  sweep.set_section_pose(2, Vec3(0.02, 0, 0), Vec3(0.3, 0.1, 0.5));
  sweep.set_radial_offset(4, 1, 0.1);
  const int rings = 200, segments = 96, offset = 7;
  bind::SweepBinding b;
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      b.vertices.push_back(static_cast<std::uint32_t>(offset + i * segments + j));
      b.t.push_back(static_cast<float>(sweep.rest().length() * i / (rings - 1)));
      b.theta.push_back(static_cast<float>(2 * std::numbers::pi * j / segments));
      b.s.push_back(1.0f);
      b.z.push_back(0.0f);
      b.weight.push_back(1.0f);
    }
  }
  const std::size_t total = offset + b.size() + 5;
  std::vector<Vec3f> rest(total, Vec3f(9, 9, 9));
  FastDeformer fast(sweep.rest(), b, rest, 16);
  EXPECT_EQ(fast.direct_block_count(), fast.block_count());
  std::vector<Vec3f> out(total, Vec3f(7, 7, 7));
  fast.deform(sweep.deformed(), out);
  double worst = 0;
  for (std::size_t k = 0; k < b.size(); ++k) {
    const Vec3 exact = deform_point(sweep.deformed(), b.coords(k));
    worst = std::max(worst, (out[b.vertices[k]].cast<double>() - exact).norm());
  }
  EXPECT_LT(worst, 2e-4 * sweep.rest().length());
  for (int v = 0; v < offset; ++v) EXPECT_EQ(out[v], Vec3f(7, 7, 7));
  for (std::size_t v = offset + b.size(); v < total; ++v) EXPECT_EQ(out[v], Vec3f(7, 7, 7));
}

TEST(FastDeform, MeshOrderChangesTheLayoutButNotOneBit) {
  // Ring order lets a span keep mesh order and write each block straight into the mesh; the same
  // vertices numbered at random are grouped by angle cell and written back one by one. Each
  // vertex is computed by the same operations either way, so the positions must agree bit for bit.
  // More vertices than a tile holds, with a tile boundary inside a ring (96 a ring), cap vertices
  // beyond both ends (the axial kernel) and a ring in the blend zone (the fix-up pass).
  ElasticSweep sweep(test::sweep_def(test::irregular_shape(6, 8)));
  sweep.set_section_pose(3, Vec3(0.01, 0.02, 0), Vec3(0.2, -0.3, 0.6));
  sweep.set_radial_offset(2, 5, -0.1);
  const int rings = 700, segments = 96;  // 12 vertices a ring in each of the 8 angle cells
  const int count = rings * segments;
  static_assert(700 * 96 > FastDeformer::kTileVertices && FastDeformer::kTileVertices % 96 != 0);
  static_assert(96 / 8 > FastDeformer::kMinMeanSegmentLength);
  std::vector<std::uint32_t> renumber(count);
  for (int v = 0; v < count; ++v) renumber[v] = static_cast<std::uint32_t>(v);
  std::shuffle(renumber.begin(), renumber.end(), std::mt19937(11));

  // The binding of ring vertex k under a numbering, sorted by mesh index as bind() makes them.
  const double length = sweep.rest().length();
  const auto binding = [&](const std::vector<std::uint32_t>& number) {
    std::vector<int> order(count);
    for (int k = 0; k < count; ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](int x, int y) { return number[x] < number[y]; });
    bind::SweepBinding b;
    for (int k : order) {
      const int ring = k / segments;
      b.vertices.push_back(number[k]);
      b.t.push_back(static_cast<float>(length * ring / (rings - 1)));
      b.theta.push_back(static_cast<float>(2 * std::numbers::pi * (k % segments) / segments));
      b.s.push_back(0.95f);
      b.z.push_back(ring == 0 ? -0.02f : ring == rings - 1 ? 0.03f : 0.0f);
      b.weight.push_back(ring == 1 ? 0.4f : 1.0f);
    }
    return b;
  };
  std::vector<std::uint32_t> identity(count);
  for (int v = 0; v < count; ++v) identity[v] = static_cast<std::uint32_t>(v);
  std::vector<Vec3f> rest(count);
  for (int v = 0; v < count; ++v) rest[v] = Vec3f(0.001f * (v % 7), 0.002f * (v % 5), 0.0f);
  std::vector<Vec3f> renumbered_rest(count);
  for (int v = 0; v < count; ++v) renumbered_rest[renumber[v]] = rest[v];
  FastDeformer ring(sweep.rest(), binding(identity), rest, 16);
  FastDeformer shuffled(sweep.rest(), binding(renumber), renumbered_rest, 16);
  EXPECT_EQ(ring.direct_block_count(), ring.block_count());
  EXPECT_EQ(shuffled.direct_block_count(), 0u);
  std::vector<Vec3f> a(count), b(count);
  ring.deform(sweep.deformed(), a);
  shuffled.deform(sweep.deformed(), b);
  for (int k = 0; k < count; ++k) ASSERT_EQ(a[k], b[renumber[k]]) << "ring vertex " << k;
  // And against the exact path (cap rings included; the blend ring mixes in its rest position).
  const bind::SweepBinding in_ring_order = binding(identity);
  for (int k = 0; k < count; k += 97) {
    Vec3 exact = deform_point(sweep.deformed(), in_ring_order.coords(k));
    const double w = in_ring_order.weight[k];
    exact = rest[k].cast<double>() + w * (exact - rest[k].cast<double>());
    EXPECT_LT((a[k].cast<double>() - exact).norm(), 2e-4 * length) << k;
  }
}

}  // namespace
}  // namespace sweep::sim
