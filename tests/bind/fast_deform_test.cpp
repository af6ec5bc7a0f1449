// The fast deformation path against the exact per-vertex path.
#include "sweep/bind/fast_deform.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>

#include "bind/support.h"
#include "core/sample_sweeps.h"
#include "sim/sweep_cloud.h"
#include "sweep/core/deform_point.h"
#include "sweep/core/elastic_sweep.h"
#include "sweep/sim/simulator.h"

namespace sweep::bind {
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

// Float's unit roundoff, 2^-24 ≈ 6e-8: a float holds a number to this fraction of its magnitude.
constexpr double kFloatRoundoff = std::numeric_limits<float>::epsilon() / 2;

// The largest coordinate magnitude of a set of points: float precision is relative to it.
double magnitude(const std::vector<Vec3f>& points) {
  double m = 0;
  for (const Vec3f& p : points) m = std::max(m, double(p.cwiseAbs().maxCoeff()));
  return m;
}

TEST(FastDeform, RestIsReproducedToFloatPrecisionAtTheStations) {
  // Vertices on the station planes (any angle, any depth, caps beyond both ends): there nothing is
  // interpolated in t, and the rest pose must come back to a few float roundings of the
  // coordinates' magnitude.
  const SweepShape shape = test::irregular_shape(8, 8);
  const int stations = 8;
  bind::SweepBinding b;
  std::vector<Vec3f> rest;
  for (int i = 0; i + 1 < shape.section_count(); ++i) {
    for (int q = 0; q <= stations; ++q) {
      const double t = shape.t[i] + (shape.t[i + 1] - shape.t[i]) * q / stations;
      for (int j = 0; j < 13; ++j) {
        const bool cap = (i == 0 && q == 0) || (i + 2 == shape.section_count() && q == stations);
        const SweepCoords c{t, 2 * std::numbers::pi * (j + 0.37) / 13, 0.2 + 0.8 * (j % 5) / 4,
                            cap ? (i == 0 ? -0.1 : 0.1) * (j % 3) : 0.0};
        b.vertices.push_back(static_cast<std::uint32_t>(b.vertices.size()));
        b.t.push_back(static_cast<float>(c.t));
        b.theta.push_back(static_cast<float>(c.theta));
        b.s.push_back(static_cast<float>(c.s));
        b.z.push_back(static_cast<float>(c.z));
        b.weight.push_back(1.0f);
        rest.push_back(deform_point(shape, b.coords(b.size() - 1)).cast<float>());
      }
    }
  }
  FastDeformer fast(shape, b, rest, stations);
  std::vector<Vec3f> out(rest.size(), Vec3f::Zero());
  fast.deform(shape, out);
  double worst = 0;
  for (std::size_t v = 0; v < out.size(); ++v)
    worst = std::max(worst, double((out[v] - rest[v]).cwiseAbs().maxCoeff()));
  // A few roundings of the table and of the vertex's sum (under 3 unit roundoffs here).
  EXPECT_LE(worst, 8 * kFloatRoundoff * magnitude(rest)) << "worst " << worst << " of " << magnitude(rest);
}

TEST(FastDeform, ErrorAgainstTheExactPathFallsQuadraticallyWithStations) {
  // Between two stations the fast path interpolates linearly in t: its error
  // against the exact path is that interpolation's error, which falls as the square of the
  // station spacing, a quarter with each doubling of the stations. So too at rest, where the
  // exact path gives back the rest positions to float precision (checked first): a bound vertex
  // comes back to its rest position to float precision only on a station plane
  // (RestIsReproducedToFloatPrecisionAtTheStations), elsewhere only to that interpolation error.
  ElasticSweep sweep(test::sweep_def(test::irregular_shape(8, 8)));
  sweep.set_section_pose(3, Vec3(0.05, 0, 0), Vec3(0.3, 0.1, 0.4));
  sweep.set_radial_offset(5, 2, 0.15);
  const Cloud c = cloud_on(sweep.rest(), 4000);
  double exact_worst = 0;
  for (std::size_t v = 0; v < c.rest.size(); ++v) {
    exact_worst = std::max(
        exact_worst, (deform_point(sweep.rest(), c.bound.coords(v)) - c.rest[v].cast<double>()).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(exact_worst, 8 * kFloatRoundoff * magnitude(c.rest));  // the coordinates in float
  for (const bool at_rest : {true, false}) {
    double previous = 0;
    for (int stations : {2, 4, 8, 16, 32}) {
      FastDeformer fast(sweep.rest(), c.bound, c.rest, stations);
      double e = 0;
      if (at_rest) {  // against the rest positions themselves
        std::vector<Vec3f> out(c.rest.size(), Vec3f::Zero());
        fast.deform(sweep.rest(), out);
        for (std::size_t v = 0; v < out.size(); ++v) {
          e = std::max(e, double((out[v] - c.rest[v]).norm()));
        }
      } else {
        e = worst_error(sweep.deformed(), c, fast);
      }
      const char* pose = at_rest ? "at rest" : "deformed";
      if (previous > 0) {
        EXPECT_GT(e, previous / 5) << pose << ", " << stations << " stations";
        EXPECT_LT(e, previous / 3) << pose << ", " << stations << " stations";
      }
      if (!at_rest && stations == 16) {
        EXPECT_LT(e, 2e-4 * sweep.rest().length());
      }
      std::printf("fast path %s, %d stations a span: largest error %.3g of the length\n", pose, stations,
                  e / sweep.rest().length());
      previous = e;
    }
  }
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
        b.t.push_back(static_cast<float>(shape.t[s] + (shape.t[s + 1] - shape.t[s]) * q / stations));
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

// Runs `scene` on a bound mesh and, every frame, rebuilds each sweep with each compiled form of the
// kernel (automatic, baseline x86-64, AVX2 where the CPU has it): all must give the same bits.
// Returns how many vertex positions moved away from the rest pose over the run.
std::size_t expect_kernel_forms_agree(const Mesh& mesh, const Rig& rig, const bind::Binding& binding,
                                      const sim::Scene& scene) {
  std::vector<Vec3f> rest(mesh.vertex_count());
  for (std::size_t v = 0; v < rest.size(); ++v) rest[v] = mesh.positions[v].cast<float>();
  std::vector<std::unique_ptr<FastDeformer>> fast;
  for (std::size_t i = 0; i < rig.sweeps.size(); ++i) {
    fast.push_back(std::make_unique<FastDeformer>(rig.sweeps[i].rest, binding.sweeps[i], rest));
  }
  std::vector<KernelForm> forms{KernelForm::automatic, KernelForm::baseline};
  if (cpu_has_avx2()) forms.push_back(KernelForm::avx2);
  sim::Simulator sim(rig, scene);
  std::size_t moved = 0;
  for (int k = 1; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    std::vector<std::vector<Vec3f>> out(forms.size(), rest);
    for (std::size_t f = 0; f < forms.size(); ++f) {
      for (std::size_t i = 0; i < fast.size(); ++i) {
        fast[i]->force_kernel_form(forms[f]);
        fast[i]->deform(sim.sweep(static_cast<int>(i)).deformed(), out[f]);
      }
    }
    for (std::size_t f = 1; f < forms.size(); ++f) {
      for (std::size_t v = 0; v < rest.size(); ++v) {
        if (std::memcmp(out[0][v].data(), out[f][v].data(), sizeof(Vec3f)) != 0) {
          ADD_FAILURE() << "frame " << k << ", vertex " << v << ": form " << static_cast<int>(forms[f]) << " gives "
                        << out[f][v].transpose() << ", automatic " << out[0][v].transpose();
          return moved;
        }
      }
    }
    for (std::size_t v = 0; v < rest.size(); ++v) moved += out[0][v] != rest[v];
  }
  return moved;
}

sim::Scene push_at_the_tips(const Rig& rig, double duration) {
  sim::Scene scene;
  scene.duration = duration;
  scene.fps = 30;
  for (std::size_t i = 0; i < rig.sweeps.size(); ++i) {
    sim::SceneForce f;
    f.sweep = rig.sweeps[i].name;
    f.sweep_index = static_cast<int>(i);
    f.spec.t = 0.9 * rig.sweeps[i].rest.length();
    f.spec.vector = Vec3(0.5, 0.5, 0.2);
    f.spec.components = kRotational | kRadial | kPositional;
    f.spec.target = RotationTarget::chain;
    f.start = 0;
    f.end = 0.4 * duration;
    scene.forces.push_back(f);
  }
  return scene;
}

TEST(FastDeform, BaselineAndAvx2KernelsGiveTheSameBits) {
  // The production dispatch picks one compiled form of the kernel at load time; the claim that
  // the other gives the same bits is checked here by running both on every frame of a bake of a
  // generated tube in ring order. The sweep stops 0.1 short of the tube's tip, so the tube has
  // blocks written straight into the mesh, cap vertices beyond the sweep's end (the axial form of
  // the kernel) and a blend zone at the root (each checked first). The diplodocus:
  // DiplodocusKernelFormsGiveTheSameBits.
  if (!cpu_has_avx2()) GTEST_SKIP() << "this CPU has no AVX2: only the baseline kernel runs";
  const Mesh mesh = tube::make_tube(test::straight_tube_params());
  SweepShape shorter = test::straight_sweep().rest;
  for (int i = 0; i < shorter.section_count(); ++i) {
    shorter.t[i] *= 0.9;
    shorter.frames[i].center *= 0.9;
  }
  SweepDef sweep = make_sweep("tube", shorter);
  sweep.part = PartSeeds{Vec3(0, 0, 0), Vec3(0, 0, 1)};
  const Rig rig = test::rig_of({sweep});
  const bind::Binding binding = bind::bind_rig(rig, mesh, {.blend = 0.05});
  const bind::SweepBinding& bound = binding.sweeps[0];
  EXPECT_TRUE(std::any_of(bound.z.begin(), bound.z.end(), [](float z) { return z > 0; }));
  EXPECT_TRUE(std::any_of(bound.weight.begin(), bound.weight.end(), [](float w) { return w < 1; }));
  std::vector<Vec3f> rest(mesh.vertex_count());
  for (std::size_t v = 0; v < rest.size(); ++v) rest[v] = mesh.positions[v].cast<float>();
  EXPECT_GT(FastDeformer(rig.sweeps[0].rest, bound, rest).direct_block_count(), 0u);
  EXPECT_GT(expect_kernel_forms_agree(mesh, rig, binding, push_at_the_tips(rig, 1.0)), mesh.vertex_count());
}

TEST(FastDeform, DiplodocusKernelFormsGiveTheSameBits) {
  // The same on the diplodocus's tail and neck: a scanned mesh's vertex order, two sweeps.
  if (!cpu_has_avx2()) GTEST_SKIP() << "this CPU has no AVX2: only the baseline kernel runs";
  const test::Diplodocus* dino = test::diplodocus();
  if (dino == nullptr) GTEST_SKIP() << "CGAL's diplodocus is absent (tools/setup-deps.sh)";
  const bind::Binding binding = bind::bind_rig(dino->rig, dino->mesh, {.blend = 0.02});
  EXPECT_GT(expect_kernel_forms_agree(dino->mesh, dino->rig, binding, push_at_the_tips(dino->rig, 1.0)),
            binding.bound_count());
}

TEST(FastDeform, TheAvx2KernelIsForcedOnlyWhereTheCpuHasIt) {
  const SweepShape shape = test::straight_shape(4, 6, 0.5);
  const Cloud c = cloud_on(shape, 20);
  FastDeformer fast(shape, c.bound, c.rest, 4);
  EXPECT_EQ(fast.kernel_form(), KernelForm::automatic);
  if (cpu_has_avx2()) {
    fast.force_kernel_form(KernelForm::avx2);
    EXPECT_EQ(fast.kernel_form(), KernelForm::avx2);
  } else {
    EXPECT_THROW(fast.force_kernel_form(KernelForm::avx2), Error);
  }
}

}  // namespace
}  // namespace sweep::bind
