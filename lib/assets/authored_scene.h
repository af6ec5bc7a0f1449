#pragma once
// A scene as authored, resolved into one the runtime runs as it is. Two keys of a scene file need
// the mesh file, which the runtime never reads: a body that follows a node of a glTF mesh (or plays
// a skinned mesh's clip), and the body itself as a collider, spheres fitted in the mesh. The
// runtime's reader (io/scene_json.h) refuses them; read_authored_scene reads them beside the rest,
// and resolve_scene turns them into what the runtime runs: a body path or a skinned clip, and
// sphere colliders carried by the body. What sweep-sim runs before its bake (bake_run.h).
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "sweep/assets/mesh_io.h"
#include "sweep/assets/skinned_clip.h"
#include "sweep/bind/bind.h"
#include "sweep/core/rig.h"
#include "sweep/io/json_reader.h"
#include "sweep/io/scene_authoring_detail.h"
#include "sweep/sim/scene.h"

namespace sweep::assets {

struct AuthoredScene {
  sim::Scene scene;  // the keys the runtime runs
  io::SceneAuthoring authoring;
};

// A scene file (or a rig file's "scene"), validated as io::read_scene validates it, with the
// authoring keys read too.
AuthoredScene read_authored_scene(const std::filesystem::path& path, const Rig& rig, const io::WarningSink& warn = {});

struct ResolvedScene {
  sim::Scene scene;  // runnable: the body's path filled in, the body's spheres among the colliders
  // A skinned mesh's clip drives the body (BakeOptions::skinned): each part follows its root joint.
  std::optional<SkinnedClip> skinned;
};

// Resolves `authored` on the mesh read from `mesh_path` (`read`: as read_scene_mesh read it), bound
// by `binding`: a body node plays the mesh's skinned clip where the mesh is skinned, else follows
// the node's animation (gltf_motion.h); "body_collider" is fitted (body_proxy.h) and its spheres
// added to the colliders. Notes (io::note) say what was found; `warn` is told what a person should
// know (a body collider of no sphere, colliders cutting a part's rest surface). Throws Error
// (bad_input) for what the mesh does not hold: an unknown node or clip, "loop" or "preroll" on a
// mesh that is not skinned.
ResolvedScene resolve_scene(AuthoredScene authored, const std::filesystem::path& mesh_path, const SceneMesh& read,
                            const Rig& rig, const bind::Binding& binding,
                            const std::function<void(const std::string&)>& warn);

}  // namespace sweep::assets
