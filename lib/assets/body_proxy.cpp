#include "sweep/assets/body_proxy.h"

#include <cmath>
#include <string>

#include "sweep/fit/surface_distance.h"
#include "sweep/sim/contact.h"

namespace sweep::assets {

BodyProxy body_proxy(const Mesh& mesh, const Rig& rig, const bind::Binding& binding,
                     const io::SceneAuthoring::BodyCollider& settings, int stations_per_span) {
  BodyProxy out;
  if (settings.spheres <= 0) return out;
  // The body's faces (no vertex bound) and the parts' (any vertex bound).
  std::vector<char> bound(mesh.vertex_count(), 0);
  for (const bind::SweepBinding& s : binding.sweeps) {
    for (const std::uint32_t v : s.vertices) bound[v] = 1;
  }
  const std::vector<std::uint32_t> triangles = mesh.triangles();
  std::vector<std::uint32_t> body_triangles, part_triangles;
  for (std::size_t k = 0; k + 2 < triangles.size(); k += 3) {
    const bool part = bound[triangles[k]] || bound[triangles[k + 1]] || bound[triangles[k + 2]];
    std::vector<std::uint32_t>& to = part ? part_triangles : body_triangles;
    to.insert(to.end(), triangles.begin() + k, triangles.begin() + k + 3);
  }
  const fit::TriangleDistance body_surface(mesh.positions, body_triangles);
  const fit::TriangleDistance part_surface(mesh.positions, part_triangles);

  fit::InteriorSpheresOptions options;
  options.max_spheres = settings.spheres;
  options.cells = settings.resolution;
  const auto room = [&](const Vec3& p) {
    // Inside a part's mesh (nearer its faces), even beyond its sweep's surface: not the body's.
    if (part_surface.distance(p) < body_surface.distance(p)) return 0.0;
    // A hair under the parts' room, so that rounding cannot leave a sphere touching a rest surface.
    const double r = sim::rest_room(rig, p, settings.margin, stations_per_span);
    return std::isfinite(r) ? r - 1e-9 * std::abs(r) : r;  // infinite: a rig of no part
  };
  out.fit = fit::fit_interior_spheres(mesh.positions, triangles, options, room);
  for (const fit::Sphere& s : out.fit.spheres) {
    sim::Collider c = sim::Collider::sphere(s.centre, s.radius);
    c.name = "body sphere " + std::to_string(out.colliders.size());
    c.carried = true;
    c.margin = settings.margin;
    c.friction = settings.friction;
    out.colliders.push_back(c);
  }
  return out;
}

}  // namespace sweep::assets
