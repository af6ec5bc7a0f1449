// The body as a collider (issue 16): spheres fitted in CGAL's diplodocus outside its tail and neck.
// They must lie inside the body, fill it, leave the parts' rest pose untouched, and stop the tail
// the body would otherwise let through.
#include "tools/common/body_proxy.h"

#include <gtest/gtest.h>

#include "bind/support.h"
#include "fit/surface_distance.h"
#include "sim/contact.h"
#include "sim/simulator.h"
#include "sim/surface_probes.h"

namespace sweep::sim {
namespace {

using test_probes::penetration;

constexpr int kStations = ContactSolver::kDefaultStationsPerSpan;

Scene::BodyCollider settings(double margin = 0) {
  Scene::BodyCollider b;
  b.spheres = 24;
  b.margin = margin;
  return b;
}

// The diplodocus's binding, made once (its tail and neck, the head bound as the neck's cap).
const bind::Binding& diplodocus_binding() {
  static const bind::Binding b = bind::bind_rig(test::diplodocus()->rig, test::diplodocus()->mesh);
  return b;
}

const tools::BodyProxy* diplodocus_proxy() {
  static const std::optional<tools::BodyProxy> p = []() -> std::optional<tools::BodyProxy> {
    const test::Diplodocus* d = test::diplodocus();
    if (!d) return std::nullopt;
    return tools::body_proxy(d->mesh, d->rig, diplodocus_binding(), settings(), kStations);
  }();
  return p ? &*p : nullptr;
}

TEST(BodyProxy, SpheresLieInsideTheBodyAndFillIt) {
  const test::Diplodocus* d = test::diplodocus();
  if (!d) GTEST_SKIP() << "no diplodocus mesh (tools/setup-deps.sh)";
  const tools::BodyProxy& proxy = *diplodocus_proxy();
  ASSERT_EQ(proxy.colliders.size(), 24u);
  const fit::TriangleDistance surface(d->mesh.positions, d->mesh.triangles());
  for (const Collider& c : proxy.colliders) {
    EXPECT_TRUE(c.carried) << c.name;
    EXPECT_TRUE(surface.inside(c.pose.center)) << c.name;
    EXPECT_LE(c.radius, surface.distance(c.pose.center) + 1e-9)
        << c.name << " reaches out of the body";
  }
  // Coverage, on a grid of its own (offset from and finer than the fit's): of the points inside the
  // mesh, outside the parts' rest surfaces and nearest an unbound vertex (the body, by another
  // measure than the fit's), the share within one fit spacing of a sphere.
  std::vector<char> bound(d->mesh.vertex_count(), 0);
  for (const bind::SweepBinding& s : diplodocus_binding().sweeps) {
    for (const std::uint32_t v : s.vertices) bound[v] = 1;
  }
  const auto nearest_vertex_bound = [&](const Vec3& p) {
    std::size_t best = 0;
    for (std::size_t v = 1; v < d->mesh.vertex_count(); ++v) {
      if ((d->mesh.positions[v] - p).squaredNorm() < (d->mesh.positions[best] - p).squaredNorm())
        best = v;
    }
    return bound[best] != 0;
  };
  Vec3 lo = d->mesh.positions[0], hi = lo;
  for (const Vec3& p : d->mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double h = (hi - lo).maxCoeff() / 53;
  int body = 0, covered = 0;
  for (double x = lo.x() + 0.3 * h; x < hi.x(); x += h) {
    for (double y = lo.y() + 0.3 * h; y < hi.y(); y += h) {
      for (double z = lo.z() + 0.3 * h; z < hi.z(); z += h) {
        const Vec3 p(x, y, z);
        if (!surface.inside(p) || rest_room(d->rig, p, 0, kStations) <= 0 ||
            nearest_vertex_bound(p))
          continue;
        ++body;
        for (const Collider& c : proxy.colliders) {
          if ((p - c.pose.center).norm() <= c.radius + proxy.fit.spacing) {
            ++covered;
            break;
          }
        }
      }
    }
  }
  ASSERT_GT(body, 1000);
  EXPECT_GE(covered, 0.9 * body) << covered << " of " << body << " points of the body covered";
}

TEST(BodyProxy, NoSphereCutsAPartsRestSurface) {
  const test::Diplodocus* d = test::diplodocus();
  if (!d) GTEST_SKIP() << "no diplodocus mesh (tools/setup-deps.sh)";
  // The same check sweep-sim warns with (Simulator's rest-overlap check), with and without a
  // margin.
  EXPECT_EQ(rest_pose_overlaps(d->rig, diplodocus_proxy()->colliders, Frame{}, kStations),
            std::vector<std::string>{});
  const tools::BodyProxy wide =
      tools::body_proxy(d->mesh, d->rig, diplodocus_binding(), settings(0.01), kStations);
  ASSERT_FALSE(wide.colliders.empty());
  EXPECT_EQ(rest_pose_overlaps(d->rig, wide.colliders, Frame{}, kStations),
            std::vector<std::string>{});
  // Blind to the parts (no sweeps, nothing bound), the fit fills the tail's root: the check can
  // fail.
  const tools::BodyProxy blind =
      tools::body_proxy(d->mesh, Rig{}, bind::Binding{}, settings(), kStations);
  EXPECT_FALSE(rest_pose_overlaps(d->rig, blind.colliders, Frame{}, kStations).empty());
}

// The deepest the tail's surface lies inside any body sphere over the frames of a kick forward and
// sideways, under the rump and into a hind leg.
double deepest_in_body(const Rig& rig, const std::vector<Collider>& body,
                       const std::vector<Collider>& scene_colliders, double fps) {
  Scene scene;
  scene.duration = 0.5;
  scene.fps = fps;
  scene.forces.push_back(test_probes::tip_impulse(rig.sweeps[0], Vec3(30, 0, 30)));
  scene.colliders = scene_colliders;
  Simulator sim(rig, scene);
  double deepest = 0;
  for (int k = 1; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    for (const Collider& c : body)
      deepest = std::max(deepest, penetration(sim.sweep(0).deformed(), c));
  }
  return deepest;
}

TEST(BodyProxy, ATailKickedIntoTheBodyEndsNoFrameInsideIt) {
  const test::Diplodocus* d = test::diplodocus();
  if (!d) GTEST_SKIP() << "no diplodocus mesh (tools/setup-deps.sh)";
  const std::vector<Collider>& body = diplodocus_proxy()->colliders;
  const double length = d->rig.sweeps[0].rest.length();
  const double free = deepest_in_body(d->rig, body, {}, 30);
  // (11% of the length when written: through the rump's surface and into the hind leg.)
  ASSERT_GT(free, 0.05 * length)
      << "without the body collider the tail must pass deep into the body";
  for (const double fps : {24.0, 144.0}) {
    const double held = deepest_in_body(d->rig, body, body, fps);
    EXPECT_LE(held, 1e-3 * length) << fps << " fps";
  }
}

}  // namespace
}  // namespace sweep::sim
