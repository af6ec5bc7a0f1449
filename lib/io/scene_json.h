#pragma once
// Reading a scene (sim/scene.h; schema: rigs/scene.schema.json) from JSON. Validated like the rig:
// every error names the file and the JSON pointer, unknown members are warnings. The keys that need
// the mesh file — a body that follows a glTF node ("body": {"node"}) and "body_collider" — are
// refused (ErrorCategory::unsupported): the tools resolve them (assets/authored_scene.h).
#include <filesystem>
#include <string>

#include "sweep/core/rig.h"
#include "sweep/io/json_reader.h"
#include "sweep/sim/scene.h"

namespace sweep::io {

// `json` is the scene object; `pointer` where it sits in its file ("" or "/scene"). Forces are
// resolved against `rig` (sweep and section names, t fraction to arc length).
sim::Scene parse_scene(const io::Json& json, const std::string& pointer, const io::JsonReader& reader, const Rig& rig);

// A scene file (format "sweep-scene"), or a rig file that holds one under "scene".
sim::Scene read_scene(const std::filesystem::path& path, const Rig& rig, const io::WarningSink& warn = {});

}  // namespace sweep::io
