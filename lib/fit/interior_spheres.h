#pragma once
// Spheres inside a closed mesh that together fill it. The body
// is approximated by spheres rather than kept as a signed-distance grid because the contact code
// already meets spheres continuously in time (sim/contact.h) and a sphere is convex and cheap to
// test; a distance grid is neither convex nor something that code can take.
//
// How: grid points over the mesh's bounding box (`cells` along its longest side); of those inside
// the mesh and with room (below), each may hold a sphere of radius min(distance to the surface,
// room). Greedily, the largest sphere over the points not yet covered is kept, until every point
// is covered (within one grid spacing) or `max_spheres` are kept. Deterministic: ties go to the
// first point in grid order.
#include <cstdint>
#include <functional>
#include <vector>

#include "sweep/core/frame.h"

namespace sweep::fit {

struct Sphere {
  Vec3 centre = Vec3::Zero();
  double radius = 0;
};

struct InteriorSpheresOptions {
  int max_spheres = 24;
  int cells = 40;  // grid cells along the bounding box's longest side
};

struct InteriorSpheres {
  std::vector<Sphere> spheres;  // largest first
  double spacing = 0;           // of the grid
  std::size_t points = 0;       // grid points inside the mesh with room: what is to be covered
  std::size_t covered = 0;      // of those, within one spacing of a kept sphere
};

// `room(p)`: how far p is from whatever else the spheres must keep clear of (the parts' rest
// surfaces), ≤ 0 where p must not be covered at all; return infinity for nothing. `points` and
// `triangles` (3 indices each) make a closed surface.
InteriorSpheres fit_interior_spheres(const std::vector<Vec3>& points, const std::vector<std::uint32_t>& triangles,
                                     const InteriorSpheresOptions& options,
                                     const std::function<double(const Vec3&)>& room);

}  // namespace sweep::fit
