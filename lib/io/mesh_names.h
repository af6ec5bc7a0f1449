#pragma once
// The meshes of one file a rig belongs to. A rig over several meshes of a scene file (sweep-fit
// --mesh A --mesh B ...: a body and its legs modelled as separate objects) names them all, in the
// order their vertices are concatenated. The rig file holds them as a JSON array ("mesh_name":
// ["Body", "LegL", "LegR"], rig format version 4); in memory Rig::mesh_name (one string, as one mesh
// is named) holds them joined by NUL characters, which no mesh name holds (assimp's names are C
// strings, and the rig reader refuses a name with one). One name is held as it is; none is "" (the
// whole file).
#include <string>
#include <string_view>
#include <vector>

namespace sweep::io {

// The rig format version that holds a list of meshes (a single name is version 3).
inline constexpr int kMeshListFormatVersion = 4;
inline constexpr char kMeshNameSeparator = '\0';

// "" → none; "Tail" → {"Tail"}; "Body\0LegL" → {"Body", "LegL"}.
std::vector<std::string> split_mesh_names(std::string_view joined);
// The inverse: the names as Rig::mesh_name holds them.
std::string join_mesh_names(const std::vector<std::string>& names);
// For messages: "'Tail'", or "'Body', 'LegL', 'LegR'".
std::string quoted_mesh_names(std::string_view joined);
// For messages: "'Tail'", or "the meshes 'Body', 'LegL', 'LegR'".
std::string shown_mesh_names(std::string_view joined);
// Whether `joined` names more than one mesh.
inline bool several_mesh_names(std::string_view joined) {
  return joined.find(kMeshNameSeparator) != std::string_view::npos;
}

}  // namespace sweep::io
