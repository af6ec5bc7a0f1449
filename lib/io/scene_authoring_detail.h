#pragma once
// The scene keys only the authoring side can run, for they need the mesh file: a body that follows
// a node of a glTF mesh (or plays a skinned mesh's clip), and the body itself as a collider fitted
// in the mesh. The runtime's reader (scene_json.h) refuses them; assets/authored_scene.h reads
// them through this and resolves them into a scene the runtime runs. Not installed.
#include <filesystem>
#include <string>

#include "sweep/core/rig.h"
#include "sweep/io/json_reader.h"
#include "sweep/sim/scene.h"

namespace sweep::io {

struct SceneAuthoring {
  // The body follows this node's animation (scene "body": {"node", "animation", "loop", "preroll"});
  // "" = none.
  std::string body_node;
  std::string body_animation;  // the animation's name; "" = the first one that moves the node
  // A skinned mesh's clip (assets/skinned_clip.h): repeat it over the duration, and simulate this
  // many seconds before frame 0 (rounded to whole frames).
  bool body_loop = false;
  double body_preroll = 0;
  // The body itself as a collider (scene "body_collider"): at most `spheres` spheres filling the
  // mesh outside the parts, carried by the body (assets/body_proxy.h fits them).
  struct BodyCollider {
    int spheres = 0;      // at most this many; 0 = no body collider
    int resolution = 40;  // grid cells along the mesh's longest side the fit samples the body on
    double margin = 0;    // as a collider's
    double friction = 0.5;
  };
  BodyCollider body_collider;
};

// parse_scene and read_scene (scene_json.h) with the authoring keys read into `authoring`.
sim::Scene parse_scene(const Json& json, const std::string& pointer, const JsonReader& reader, const Rig& rig,
                       SceneAuthoring& authoring);
sim::Scene read_scene(const std::filesystem::path& path, const Rig& rig, const WarningSink& warn,
                      SceneAuthoring& authoring);

}  // namespace sweep::io
