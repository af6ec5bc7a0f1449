#pragma once
// Deformation (the paper's §III): a point is bound to a sweep by its sweep coordinates (t, θ, s, z),
// found once on the rest shape (core/locate.h), and rebuilt from them on every pose of the sweep:
// on the rest shape it comes back to where it was; on a deformed shape it follows the bending,
// twisting and radial change. deform_point is that rebuild, the exact per-vertex path in double;
// bind/deform.h applies it to every bound vertex of a mesh, and the fast path (bind/fast_deform.h)
// approximates it in float from stations.
#include "sweep/core/sweep_shape.h"

namespace sweep {

struct SweepCoords {
  double t = 0;      // arc-length parameter in [0, L]
  double theta = 0;  // angle in the cross-section plane, [0, 2π), measured from the frame's x axis
  double s = 0;      // distance from the axis over r(θ, t): 1 on the surface, < 1 inside
  double z = 0;      // offset along the end section's axis (0 unless t was clamped to an end)
};

// v' = C(t) + R(t)·(s r(θ,t) cos θ, s r(θ,t) sin θ, z).
Vec3 deform_point(const SweepShape& shape, const SweepCoords& c);

}  // namespace sweep
