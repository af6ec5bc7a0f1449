#pragma once
// The body as a collider: spheres filling the mesh where it is the body — nearer a face
// of unbound vertices than one that a sweep binds (so not a part, nor a part's cap such as the
// diplodocus's head) — and clear of every part's rest surface by the margin (sim::rest_room, the
// measure of sim::rest_pose_overlaps, so the rest pose touches none). Fitted once at load
// (fit/interior_spheres.h, which reads the mesh through CGAL: the authoring side's) and handed to
// the runtime as plain sphere colliders carried by the body (authored_scene.h).
#include <vector>

#include "sweep/bind/bind.h"
#include "sweep/core/mesh.h"
#include "sweep/core/rig.h"
#include "sweep/fit/interior_spheres.h"
#include "sweep/io/scene_authoring_detail.h"
#include "sweep/sim/collider.h"

namespace sweep::assets {

struct BodyProxy {
  std::vector<sim::Collider> colliders;  // "body sphere N", carried by the body, largest first
  fit::InteriorSpheres fit;              // what the fit saw: its grid and how much it covered
};

BodyProxy body_proxy(const Mesh& mesh, const Rig& rig, const bind::Binding& binding,
                     const io::SceneAuthoring::BodyCollider& settings, int stations_per_span);

}  // namespace sweep::assets
