// The body as a collider: spheres fitted in a body outside its parts (a small body with
// a tail, and CGAL's diplodocus outside its tail and neck). They must lie inside the body, fill
// it, leave the parts' rest pose untouched, and stop the tail the body would otherwise let through.
#include "sweep/assets/body_proxy.h"

#include <gtest/gtest.h>

#include "bind/support.h"
#include "fit/curve_tubes.h"
#include "sim/surface_probes.h"
#include "sweep/fit/fit.h"
#include "sweep/fit/surface_distance.h"
#include "sweep/sim/contact.h"
#include "sweep/sim/simulator.h"

namespace sweep::sim {
namespace {

using test_probes::penetration;

constexpr int kStations = ContactSolver::kDefaultStationsPerSpan;

io::SceneAuthoring::BodyCollider settings(double margin = 0) {
  io::SceneAuthoring::BodyCollider b;
  b.spheres = 24;
  b.margin = margin;
  return b;
}

// The diplodocus's binding, made once (its tail and neck, the head bound as the neck's cap).
const bind::Binding& diplodocus_binding() {
  static const bind::Binding b = bind::bind_rig(test::diplodocus()->rig, test::diplodocus()->mesh);
  return b;
}

const assets::BodyProxy* diplodocus_proxy() {
  static const std::optional<assets::BodyProxy> p = []() -> std::optional<assets::BodyProxy> {
    const test::Diplodocus* d = test::diplodocus();
    if (!d) return std::nullopt;
    return assets::body_proxy(d->mesh, d->rig, diplodocus_binding(), settings(), kStations);
  }();
  return p ? &*p : nullptr;
}

// A body (an ellipsoid 4r wide over 10r) with a tail (a tube of radius r, 12r long) leaving it
// along +Z: the diplodocus's case on a mesh small enough for the sanitizer build (the diplodocus
// tests take ten minutes there and are left out of it).
struct BodyWithTail {
  Mesh mesh;
  Rig rig;
  bind::Binding binding;
};

const BodyWithTail& body_with_tail() {
  static const BodyWithTail b = [] {
    constexpr double r = 0.1, body_length = 10 * r, tube_length = 12 * r;
    test::CurveTube t;
    t.curve = [=](double u) { return Vec3(0, 0, u * (body_length + tube_length)); };
    t.radius = test::with_body(4 * r, body_length, [](double) { return r; });
    t.segments = 24;
    BodyWithTail out;
    out.mesh = t.mesh();
    fit::FitOptions o;
    o.name = "tail";
    o.root = Vec3(0, 0, body_length + r);
    o.tip = Vec3(0, 0, body_length + tube_length + r);
    out.rig.sweeps.push_back(fit::fit_sweep(out.mesh, o).sweep);
    out.binding = bind::bind_rig(out.rig, out.mesh);
    return out;
  }();
  return b;
}

// Every sphere lies inside the body (its centre inside the mesh, its radius within the distance
// to the surface), and together they fill it: of the points of a grid of its own (offset from and
// finer than the fit's) inside the mesh, outside the parts' rest surfaces and nearest an unbound
// vertex (the body, by another measure than the fit's), at least 90% lie within one fit spacing
// of a sphere.
void expect_inside_and_filling(const Mesh& mesh, const Rig& rig, const bind::Binding& binding,
                               const assets::BodyProxy& proxy, int min_points) {
  const fit::TriangleDistance surface(mesh.positions, mesh.triangles());
  for (const Collider& c : proxy.colliders) {
    EXPECT_TRUE(c.carried) << c.name;
    EXPECT_TRUE(surface.inside(c.pose.center)) << c.name;
    EXPECT_LE(c.radius, surface.distance(c.pose.center) + 1e-9) << c.name << " reaches out of the body";
  }
  std::vector<char> bound(mesh.vertex_count(), 0);
  for (const bind::SweepBinding& s : binding.sweeps) {
    for (const std::uint32_t v : s.vertices) bound[v] = 1;
  }
  const auto nearest_vertex_bound = [&](const Vec3& p) {
    std::size_t best = 0;
    for (std::size_t v = 1; v < mesh.vertex_count(); ++v) {
      if ((mesh.positions[v] - p).squaredNorm() < (mesh.positions[best] - p).squaredNorm()) best = v;
    }
    return bound[best] != 0;
  };
  Vec3 lo = mesh.positions[0], hi = lo;
  for (const Vec3& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double h = (hi - lo).maxCoeff() / 53;
  int body = 0, covered = 0;
  for (double x = lo.x() + 0.3 * h; x < hi.x(); x += h) {
    for (double y = lo.y() + 0.3 * h; y < hi.y(); y += h) {
      for (double z = lo.z() + 0.3 * h; z < hi.z(); z += h) {
        const Vec3 p(x, y, z);
        if (!surface.inside(p) || rest_room(rig, p, 0, kStations) <= 0 || nearest_vertex_bound(p)) continue;
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
  ASSERT_GT(body, min_points);
  EXPECT_GE(covered, 0.9 * body) << covered << " of " << body << " points of the body covered";
}

// No sphere cuts a part's rest surface (the check sweep-sim warns with: Simulator's rest-overlap
// check), with and without a margin; blind to the parts (no sweeps, nothing bound) the fit fills
// the part's root, and the check can fail.
void expect_clear_of_the_parts(const Mesh& mesh, const Rig& rig, const bind::Binding& binding,
                               const assets::BodyProxy& proxy, double margin) {
  EXPECT_EQ(rest_pose_overlaps(rig, proxy.colliders, Frame{}, kStations), std::vector<std::string>{});
  const assets::BodyProxy wide = assets::body_proxy(mesh, rig, binding, settings(margin), kStations);
  ASSERT_FALSE(wide.colliders.empty());
  EXPECT_EQ(rest_pose_overlaps(rig, wide.colliders, Frame{}, kStations), std::vector<std::string>{});
  const assets::BodyProxy blind = assets::body_proxy(mesh, Rig{}, bind::Binding{}, settings(), kStations);
  EXPECT_FALSE(rest_pose_overlaps(rig, blind.colliders, Frame{}, kStations).empty());
}

TEST(BodyProxy, SpheresLieInsideABodyAndFillIt) {
  const BodyWithTail& b = body_with_tail();
  const assets::BodyProxy proxy = assets::body_proxy(b.mesh, b.rig, b.binding, settings(), kStations);
  ASSERT_EQ(proxy.colliders.size(), 24u);
  expect_inside_and_filling(b.mesh, b.rig, b.binding, proxy, 1000);
}

TEST(BodyProxy, NoSphereCutsATailsRestSurface) {
  const BodyWithTail& b = body_with_tail();
  const assets::BodyProxy proxy = assets::body_proxy(b.mesh, b.rig, b.binding, settings(), kStations);
  expect_clear_of_the_parts(b.mesh, b.rig, b.binding, proxy, 0.01);
}

TEST(BodyProxy, DiplodocusSpheresLieInsideTheBodyAndFillIt) {
  const test::Diplodocus* d = test::diplodocus();
  if (!d) GTEST_SKIP() << "no diplodocus mesh (tools/setup-deps.sh)";
  const assets::BodyProxy& proxy = *diplodocus_proxy();
  ASSERT_EQ(proxy.colliders.size(), 24u);
  expect_inside_and_filling(d->mesh, d->rig, diplodocus_binding(), proxy, 1000);
}

TEST(BodyProxy, DiplodocusNoSphereCutsAPartsRestSurface) {
  const test::Diplodocus* d = test::diplodocus();
  if (!d) GTEST_SKIP() << "no diplodocus mesh (tools/setup-deps.sh)";
  expect_clear_of_the_parts(d->mesh, d->rig, diplodocus_binding(), *diplodocus_proxy(), 0.01);
}

// The deepest the tail's surface lies inside any body sphere over the frames of a kick forward and
// sideways, under the rump and into a hind leg.
double deepest_in_body(const Rig& rig, const std::vector<Collider>& body, const std::vector<Collider>& scene_colliders,
                       double fps) {
  Scene scene;
  scene.duration = 0.5;
  scene.fps = fps;
  scene.forces.push_back(test_probes::tip_impulse(rig.sweeps[0], Vec3(30, 0, 30)));
  scene.colliders = scene_colliders;
  Simulator sim(rig, scene);
  double deepest = 0;
  for (int k = 1; k < scene.frame_count(); ++k) {
    sim.advance_frame();
    for (const Collider& c : body) deepest = std::max(deepest, penetration(sim.sweep(0).deformed(), c));
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
  ASSERT_GT(free, 0.05 * length) << "without the body collider the tail must pass deep into the body";
  for (const double fps : {24.0, 144.0}) {
    const double held = deepest_in_body(d->rig, body, body, fps);
    EXPECT_LE(held, 1e-3 * length) << fps << " fps";
  }
}

}  // namespace
}  // namespace sweep::sim
