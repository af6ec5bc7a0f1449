#pragma once
// Measures of a part's true surface against colliders, shared by the contact tests, and the kick
// they give a part.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "sweep/core/sweep_shape.h"
#include "sweep/sim/collider.h"
#include "sweep/sim/scene.h"

namespace sweep::sim::test_probes {

// Every point of a fine grid on the surface, far finer than the solver's stations: 400 rings
// along the part, 48 points round each, S(θ,t) as surface_point gives it (the ring's frame found
// once rather than 48 times: per point, it was most of the contact tests' time under the
// sanitizers).
template <class Visit>
void for_each_surface_sample(const SweepShape& shape, Visit&& visit) {
  for (int a = 0; a <= 400; ++a) {
    const double t = shape.length() * a / 400;
    const Frame ring = frame_at(shape, t);
    for (int b = 0; b < 48; ++b) {
      const double theta = 2 * std::numbers::pi * b / 48;
      const double r = radius_at(shape, theta, t);
      visit(ring.to_world(Vec3(r * std::cos(theta), r * std::sin(theta), 0.0)));
    }
  }
}

// The deepest any point of the surface lies inside the collider (0 if none does), over that grid.
inline double penetration(const SweepShape& shape, const Collider& c) {
  double deepest = 0;
  Vec3 out;
  for_each_surface_sample(
      shape, [&](const Vec3& p) { deepest = std::max(deepest, -c.local_distance(c.pose.to_local(p), &out)); });
  return deepest;
}

// An impulse at the tip at t = 0, turning the chain (the physical moment for a material part).
inline SceneForce tip_impulse(const SweepDef& def, const Vec3& impulse) {
  SceneForce f;
  f.sweep = def.name;
  f.sweep_index = 0;
  f.spec.t = def.rest.length();
  f.spec.vector = impulse;
  f.spec.target = RotationTarget::chain;
  if (def.material) f.spec.moment = MomentModel::physical;
  f.start = f.end = 0;  // an impulse at t = 0
  return f;
}

}  // namespace sweep::sim::test_probes
