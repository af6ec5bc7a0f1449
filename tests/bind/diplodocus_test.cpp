// The paper's case: CGAL's 23,982-vertex diplodocus, tail and neck fitted by lib/fit in the test,
// bound, and rebuilt exactly; binding speed. Skips when meshes/cgal/ is absent.
#include <algorithm>
#include <chrono>
#include <cstdio>

#include "support.h"
#include "sweep/bind/deform.h"
#include "sweep/core/elastic_sweep.h"

namespace sweep::test {
namespace {

#define REQUIRE_DIPLODOCUS()             \
  const Diplodocus* dino = diplodocus(); \
  if (!dino) GTEST_SKIP() << diplodocus_path() << " is absent (tools/setup-deps.sh unpacks it)"

TEST(BindDiplodocus, TailAndNeckRestPoseIsRebuiltWithin1e5OfTheirLengthAtEveryVertex) {
  REQUIRE_DIPLODOCUS();
  const bind::BindResult r = bind::bind(dino->rig, dino->mesh);
  ASSERT_EQ(r.binding.sweeps.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const SweepDef& def = dino->rig.sweeps[i];
    const bind::SweepBinding& t = r.binding.sweeps[i];
    const double tolerance = 1e-5 * def.rest.length();
    std::printf("%s: length %.4f, %zu vertices bound, rest max error %.3g (%.3g of the length)\n", def.name.c_str(),
                def.rest.length(), t.size(), r.sweeps[i].rest_max_error,
                r.sweeps[i].rest_max_error / def.rest.length());
    // A tail or neck is a sizeable part of the model, and far from all of it.
    EXPECT_GT(t.size(), 1000u);
    EXPECT_LT(t.size(), dino->mesh.vertex_count() / 2);
    for (std::size_t k = 0; k < t.size(); ++k) {
      const Vec3 rebuilt = deform_point(def.rest, t.coords(k));
      ASSERT_LE((rebuilt - dino->mesh.positions[t.vertices[k]]).norm(), tolerance)
          << def.name << ": vertex " << t.vertices[k] << " (t " << t.t[k] << ", theta " << t.theta[k] << ", s "
          << t.s[k] << ", z " << t.z[k] << ")";
    }
    EXPECT_LE(r.sweeps[i].rest_max_error, tolerance);
  }
  // The same through deform_exact: with nothing moving, every vertex (bound or not) stays put.
  std::vector<SweepShape> rest{dino->rig.sweeps[0].rest, dino->rig.sweeps[1].rest};
  std::vector<Vec3> out(dino->mesh.vertex_count());
  bind::deform_exact(r.binding, rest, dino->mesh.positions, out);
  for (std::size_t v = 0; v < out.size(); ++v) {
    ASSERT_LE((out[v] - dino->mesh.positions[v]).norm(), 1e-5 * rest[0].length()) << "vertex " << v;
  }
}

TEST(BindDiplodocus, RootPlaneStaysPutAndTheBlendZoneFadesTheMotion) {
  REQUIRE_DIPLODOCUS();
  bind::BindOptions o;
  const double blend = 0.02;  // mesh units, about half the tail's root radius
  o.blend = blend;
  const bind::Binding b = bind::bind_rig(dino->rig, dino->mesh, o);
  ElasticSweep tail(dino->rig.sweeps[0]);
  ElasticSweep neck(dino->rig.sweeps[1]);
  for (int i = 1; i < tail.rest().section_count(); ++i) {
    tail.set_section_pose(i, Vec3(0, 0.002, 0), Vec3(0.05, 0.02, 0.01));
  }
  neck.set_section_pose(1, Vec3::Zero(), Vec3(0.1, 0, 0));
  const std::vector<const SweepShape*> shapes{&tail.deformed(), &neck.deformed()};
  std::vector<Vec3> out(dino->mesh.vertex_count());
  bind::deform_exact(b, shapes, dino->mesh.positions, out);
  for (std::size_t i = 0; i < 2; ++i) {
    const Frame& root = dino->rig.sweeps[i].rest.frames[0];
    const bind::SweepBinding& t = b.sweeps[i];
    std::size_t moved_far = 0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      const std::uint32_t v = t.vertices[k];
      const double g = (dino->mesh.positions[v] - root.center).dot(root.axis());
      const double move = (out[v] - dino->mesh.positions[v]).norm();
      if (g <= 1e-4 * blend) {
        // At the root plane the weight is (nearly) zero: the seam does not open.
        ASSERT_LE(move, 1e-6) << t.name << ": vertex " << v << " at the root plane moved";
      }
      if (g >= blend) {
        EXPECT_EQ(t.weight[k], 1.0f);
        moved_far += move > 1e-4;
      }
    }
    EXPECT_GT(moved_far, 100u) << t.name;
  }
}

TEST(BindDiplodocus, BindingTailAndNeckTakesUnder100Milliseconds) {
  REQUIRE_DIPLODOCUS();
  std::vector<double> ms;
  for (int run = 0; run < 7; ++run) {
    const auto start = std::chrono::steady_clock::now();
    const bind::Binding b = bind::bind_rig(dino->rig, dino->mesh);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    ASSERT_GT(b.bound_count(), 0u);
  }
  std::sort(ms.begin(), ms.end());
  std::printf("binding the diplodocus (tail and neck, %zu vertices): median %.1f ms, min %.1f ms\n",
              dino->mesh.vertex_count(), ms[ms.size() / 2], ms.front());
#if defined(NDEBUG) && !defined(SWEEP_SANITIZED)
  EXPECT_LT(ms[ms.size() / 2], 100.0);
#endif
}

}  // namespace
}  // namespace sweep::test
