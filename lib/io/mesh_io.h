#pragma once
// Reading and writing meshes, always in the file's own vertex order where the format has one.
//  - OFF, PLY, glTF/glb: assimp with no post-processing (it keeps the file's vertices);
//  - OBJ: tinyobjloader (keeps the `v` array; assimp would unroll it per face corner);
//  - STL, FBX and anything else assimp reads: welded by position in first-use order (these formats
//    have no shared vertex list, so that order is the only one there is). See README.
// Bad files raise sweep::Error (bad_input) naming the file and what is wrong; unsupported formats
// raise ErrorCategory::unsupported.
#include <filesystem>

#include "core/mesh.h"

namespace sweep::io {

Mesh read_mesh(const std::filesystem::path& path);

// Checks that a mesh is usable by the tools: has vertices and faces, finite coordinates, face
// indices in range, faces of at least 3 vertices. Throws Error(bad_input) naming `source`, and the
// vertex or face index at fault.
void validate_mesh(const Mesh& mesh, const std::string& source);

// Wavefront OBJ with `v` lines in vertex order and the mesh's polygons; deterministic bytes.
void write_obj(const std::filesystem::path& path, const Mesh& mesh);

}  // namespace sweep::io
