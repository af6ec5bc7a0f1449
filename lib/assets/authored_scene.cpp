#include "sweep/assets/authored_scene.h"

#include <utility>

#include "sweep/assets/assimp_skin.h"
#include "sweep/assets/body_proxy.h"
#include "sweep/assets/gltf_motion.h"
#include "sweep/core/error.h"
#include "sweep/core/text.h"
#include "sweep/io/interrupt.h"
#include "sweep/io/scene_json.h"
#include "sweep/sim/contact.h"

namespace sweep::assets {

AuthoredScene read_authored_scene(const std::filesystem::path& path, const Rig& rig, const io::WarningSink& warn) {
  AuthoredScene out;
  out.scene = io::read_scene(path, rig, warn, out.authoring);
  return out;
}

namespace {

// The body node: a skinned mesh plays its clip (skinned_clip.h); any other follows the node rigidly.
void resolve_body(const io::SceneAuthoring& a, const std::filesystem::path& mesh_path, const SceneMesh& read,
                  const Rig& rig, const bind::Binding& binding, const std::function<void(const std::string&)>& warn,
                  ResolvedScene& out) {
  if (a.body_node.empty()) return;
  if (auto model = read_skin(mesh_path, read.mesh.positions, read.to_world)) {
    if (warn)
      for (const std::string& w : model->warnings) warn(w);
    out.skinned.emplace(mesh_path, std::move(*model), read.to_world, rig, binding, a.body_node, a.body_animation,
                        a.body_loop, a.body_preroll, out.scene.fps);
    for (std::size_t i = 0; i < rig.sweeps.size(); ++i) {
      io::note("clip '" + out.skinned->clip_name() + "': part \"" + rig.sweeps[i].name + "\" hangs from joint '" +
               out.skinned->model().nodes[out.skinned->root_joint_node(static_cast<int>(i))].name + "'");
    }
    return;
  }
  if (a.body_loop || a.body_preroll > 0)
    fail(ErrorCategory::bad_input,
         mesh_path.string() +
             ": the scene's body \"loop\" and \"preroll\" play a skinned mesh's clip, and this mesh is not skinned");
  out.scene.body = read_gltf_body_path(mesh_path, a.body_node, a.body_animation);
}

// "body_collider": spheres fitted in the body, carried by it, added to the scene's colliders.
void resolve_body_collider(const io::SceneAuthoring& a, const SceneMesh& read, const Rig& rig,
                           const bind::Binding& binding, const std::function<void(const std::string&)>& warn,
                           sim::Scene& scene) {
  if (a.body_collider.spheres <= 0) return;
  const BodyProxy proxy = body_proxy(read.mesh, rig, binding, a.body_collider, scene.contact_stations);
  if (proxy.colliders.empty()) {
    if (warn) warn("body_collider: no sphere fits in the body (is the mesh closed, and not all parts?): none is used");
    return;
  }
  scene.colliders.insert(scene.colliders.end(), proxy.colliders.begin(), proxy.colliders.end());
  io::note("body collider: " + std::to_string(proxy.colliders.size()) + " spheres, covering " +
           format_percent(static_cast<double>(proxy.fit.covered) / proxy.fit.points) +
           " of the body's grid points (spacing " + format_number(proxy.fit.spacing, 3) + ")");
}

}  // namespace

ResolvedScene resolve_scene(AuthoredScene authored, const std::filesystem::path& mesh_path, const SceneMesh& read,
                            const Rig& rig, const bind::Binding& binding,
                            const std::function<void(const std::string&)>& warn) {
  ResolvedScene out;
  out.scene = std::move(authored.scene);
  resolve_body(authored.authoring, mesh_path, read, rig, binding, warn, out);
  resolve_body_collider(authored.authoring, read, rig, binding, warn, out.scene);
  // Colliders that cut a part's rest surface where the body starts.
  const sim::BodyState b = out.scene.body.at(0);
  for (const std::string& m :
       sim::rest_pose_overlaps(rig, out.scene.colliders, {b.rotation, b.translation}, out.scene.contact_stations))
    if (warn) warn(m);
  return out;
}

}  // namespace sweep::assets
