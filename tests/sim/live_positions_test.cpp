// The live runtime's world-space copy (sim/live_positions.h) against what it replaces: each part
// deformed into a mesh-order copy by deform_sweeps, then the whole copy transformed by
// transform_positions. Two parts whose vertices lie scattered among the mesh's, blend-zone
// vertices among them, a body turned and moved: the same bits, coordinate by coordinate.
#include "sweep/sim/live_positions.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <numeric>
#include <random>

#include "core/sample_sweeps.h"
#include "sim/sweep_cloud.h"
#include "sweep/core/elastic_sweep.h"

namespace sweep::sim {
namespace {

constexpr int kMeshVertices = 1000, kPartVertices = 300;

// `cloud`'s points as mesh vertices `where` (cloud point k is mesh vertex where[k]), the binding
// sorted by mesh index as bind() makes it.
bind::SweepBinding renumbered(const test::SweepCloud& cloud, const std::vector<std::uint32_t>& where) {
  std::vector<int> order(where.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return where[a] < where[b]; });
  bind::SweepBinding b;
  for (const int k : order) {
    b.vertices.push_back(where[k]);
    b.t.push_back(cloud.bound.t[k]);
    b.theta.push_back(cloud.bound.theta[k]);
    b.s.push_back(cloud.bound.s[k]);
    b.z.push_back(cloud.bound.z[k]);
    b.weight.push_back(k % 17 == 0 ? 0.5f : 1.0f);  // some in a blend zone
  }
  return b;
}

// Whether two sets of flat coordinates are the same floats, bit for bit.
int differing(const std::vector<float>& a, const std::vector<float>& b) {
  int n = 0;
  for (std::size_t c = 0; c < a.size(); ++c) n += a[c] != b[c];
  return n;
}

TEST(LivePositions, GivesTheBitsOfAMeshOrderDeformAndTransform) {
  ElasticSweep tail(test::sweep_def(test::irregular_shape(6, 8)));
  ElasticSweep neck(test::sweep_def(test::straight_shape(5, 6, 0.5)));
  const test::SweepCloud tail_cloud = test::sweep_cloud(tail.rest(), kPartVertices, 0.2, 0.8);
  const test::SweepCloud neck_cloud = test::sweep_cloud(neck.rest(), kPartVertices, 0.2, 0.8);
  // The mesh: the parts' vertices numbered at random among unbound ones.
  std::vector<std::uint32_t> number(kMeshVertices);
  std::iota(number.begin(), number.end(), 0u);
  std::shuffle(number.begin(), number.end(), std::mt19937(5));
  const std::vector<std::uint32_t> tail_at(number.begin(), number.begin() + kPartVertices);
  const std::vector<std::uint32_t> neck_at(number.begin() + kPartVertices, number.begin() + 2 * kPartVertices);
  std::vector<bind::Vec3f> rest(kMeshVertices);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> coordinate(-2.0f, 2.0f);
  for (bind::Vec3f& p : rest) p = bind::Vec3f(coordinate(rng), coordinate(rng), coordinate(rng));
  for (int k = 0; k < kPartVertices; ++k) {
    rest[tail_at[k]] = tail_cloud.rest[k];
    rest[neck_at[k]] = neck_cloud.rest[k];
  }
  bind::FastDeformer tail_fast(tail.rest(), renumbered(tail_cloud, tail_at), rest);
  bind::FastDeformer neck_fast(neck.rest(), renumbered(neck_cloud, neck_at), rest);
  const bind::FastDeformer* parts[] = {&tail_fast, &neck_fast};
  LivePositions live(rest, parts);

  const Eigen::Matrix3f turn = Eigen::AngleAxisf(0.7f, bind::Vec3f(0.3f, 1.0f, -0.2f).normalized()).toRotationMatrix();
  const bind::Vec3f move(1.5f, -0.25f, 3.0f);
  std::vector<bind::Vec3f> mesh = rest;  // the mesh-order copy
  std::vector<float> expected(3 * kMeshVertices), got(3 * kMeshVertices);
  // Nothing deformed yet: the rest positions, carried.
  bind::transform_positions(mesh, turn, move, expected.data());
  live.world(turn, move, got.data());
  EXPECT_EQ(differing(got, expected), 0);
  // The tail bent and swollen, deformed alone: the neck still at its rest positions.
  tail.set_section_pose(3, Vec3(0.01, 0.02, 0), Vec3(0.2, -0.3, 0.6));
  tail.set_radial_offset(2, 5, -0.1);
  const bind::DeformJob tail_job{&tail_fast, &tail.deformed()};
  bind::deform_sweeps(std::span(&tail_job, 1), mesh);
  bind::transform_positions(mesh, turn, move, expected.data());
  live.deform(0, tail_fast, tail.deformed());
  live.world(turn, move, got.data());
  EXPECT_EQ(differing(got, expected), 0);
  EXPECT_GT(differing(got, std::vector<float>(got.size(), 0.0f)), 0);
  // Both deformed, the neck twisted.
  neck.set_section_pose(4, Vec3(0, 0.05, 0), Vec3(0, 0.4, 0.3));
  const bind::DeformJob jobs[] = {{&tail_fast, &tail.deformed()}, {&neck_fast, &neck.deformed()}};
  bind::deform_sweeps(jobs, mesh);
  bind::transform_positions(mesh, turn, move, expected.data());
  live.deform(0, tail_fast, tail.deformed());
  live.deform(1, neck_fast, neck.deformed());
  live.world(turn, move, got.data());
  EXPECT_EQ(differing(got, expected), 0);
  // And the deformation did move the parts' vertices away from the rest ones.
  std::vector<float> rigid(3 * kMeshVertices);
  bind::transform_positions(rest, turn, move, rigid.data());
  EXPECT_GT(differing(got, rigid), 3 * kPartVertices);
}

// The banded product that carries the mesh reads two floats either side of each vertex and works
// 8 vertices at a time from the second: every mesh size around those edges (1 to 40 vertices, no
// part) comes out as transform_positions gives it, coordinate by coordinate.
TEST(LivePositions, CarriesMeshesOfEverySizeAsTransformPositions) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> coordinate(-3.0f, 3.0f);
  const Eigen::Matrix3f turn = Eigen::AngleAxisf(-1.1f, bind::Vec3f(0.5f, -0.2f, 1.0f).normalized()).toRotationMatrix();
  const bind::Vec3f move(-0.75f, 2.0f, 0.5f);
  for (int n = 1; n <= 40; ++n) {
    std::vector<bind::Vec3f> rest(static_cast<std::size_t>(n));
    for (bind::Vec3f& p : rest) p = bind::Vec3f(coordinate(rng), coordinate(rng), coordinate(rng));
    const LivePositions live(rest, std::span<const bind::FastDeformer* const>());
    // Guards either side of the output: the copy writes exactly its 3n floats.
    std::vector<float> expected(3 * n), got(3 * n + 6, 7.0f);
    bind::transform_positions(rest, turn, move, expected.data());
    live.world(turn, move, got.data() + 3);
    EXPECT_EQ(differing(std::vector<float>(got.begin() + 3, got.end() - 3), expected), 0) << n << " vertices";
    for (int g = 0; g < 3; ++g) {
      EXPECT_EQ(got[g], 7.0f) << n;
      EXPECT_EQ(got[3 * n + 3 + g], 7.0f) << n;
    }
  }
}

}  // namespace
}  // namespace sweep::sim
