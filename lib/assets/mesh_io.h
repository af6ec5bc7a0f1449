#pragma once
// Reading and writing meshes, always in the file's own vertex order where the format has one.
//  - OFF: our own strict reader (assimp's OFF loader silently clamps out-of-range face indices and
//    zero-fills truncated files); double precision, '#' comments, OFF/COFF/NOFF/CNOFF/NCOFF
//    headers.
//  - OBJ: our own reader of `v` and `f` lines (the `v` array as stored, coordinates exact with
//    std::from_chars, so NaN is caught by index and a written file reads back bit for bit; 64-bit
//    face indices, negative ones relative). Faces stay polygons; a face of fewer than 3 vertices
//    or an index out of range is refused with its line; `l`, `p`, `vt`, `vn`, groups are ignored.
//  - PLY, glTF/glb: assimp with no post-processing, which keeps the stored vertices, their order
//    and count, and the polygons (checked by tests/assets). Single precision (assimp stores floats).
//    Checked first (assets/mesh_checks.h), since assimp silently shifts or drops data otherwise: an
//    ASCII PLY must hold exactly the elements its header announces, one a line; a glTF index
//    past its primitive's vertices is refused.
//  - Text formats (OFF, OBJ, PLY) may start with a UTF-8 byte order mark, which is skipped.
//  - Only regular files are read (a FIFO or a device is refused, not waited on).
//  - STL, FBX and anything else assimp reads: welded by exact position in first-use order (faces
//    in file order, corners in face order; -0 and +0 are one position; vertices no face uses are
//    dropped). These formats have no shared vertex list, so that order is the only one there is.
// For every assimp format: point and line primitives are dropped, and each mesh is placed in world
// space by its node's world transform (FBX stores local positions under axis nodes); an identity
// transform is applied without arithmetic. No unit scale is applied: an FBX's coordinates stay in
// its unit, which SceneMesh::unit reports (its UnitScaleFactor, centimetres a unit).
// Several meshes in one file: a scene file (glTF, FBX and the other assimp formats but
// PLY and STL) holds meshes by name. One mesh of it is a node that shows one (Blender's object):
// all that node's importer meshes (a glTF mesh's primitives, an FBX model's parts by material),
// in the node's order, welded per importer mesh, placed by that node's world transform. Its name
// is the node's, as assimp gives it (a glTF node without a name is "nodes[N]"); the name of its
// mesh (a glTF mesh's, its primitives' "-0", "-1" suffixes dropped) names it too. read_scene_mesh
// takes one by name, or the only or largest one; read_mesh (and a rig with no mesh name) reads
// the whole file as before: every importer mesh in the scene's mesh order, each placed by the
// first node showing it, depth first. OFF, OBJ, PLY and STL hold one mesh with no name (an OBJ's
// o/g groups share one vertex list, so they are not meshes of their own).
// Bad files raise sweep::Error (bad_input) naming the file and what is wrong, as one line
// "<path>: <what>"; unsupported formats raise ErrorCategory::unsupported.
// Three files, one job each: mesh_text_readers.cpp (OFF, OBJ), mesh_import.cpp (read_mesh, and
// assimp for PLY, glTF and the rest: the only file that sees assimp), mesh_writers.cpp.
#include <Eigen/Geometry>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "sweep/core/mesh.h"

namespace sweep::assets {

// Every mesh of the file, in world space, concatenated (see above).
Mesh read_mesh(const std::filesystem::path& path);

// One mesh a scene file holds (see above), for choosing and for messages.
struct SceneMeshEntry {
  std::string name;         // its node's name: what --mesh and a rig's mesh_name give
  std::string mesh_name;    // its mesh's name ("" when its parts are named unlike each other)
  std::size_t vertex_count = 0;  // as read (welded where the format welds)
};

// How the file's length unit was taken (assimp's scene metadata): FBX states one.
struct MeshUnit {
  double unit_scale_factor = 0;  // FBX UnitScaleFactor: centimetres per file unit; 0 = none stated
  double original_unit_scale_factor = 0;  // FBX OriginalUnitScaleFactor (0 = none stated)
};

// Which mesh of a file read_scene_mesh takes.
enum class MeshPick {
  whole_file,       // `name` empty: the whole file, as read_mesh (a rig without a mesh name)
  only_or_largest,  // `name` empty: the only mesh, or the one with the most vertices (the first
                    // of those that tie)
};

struct SceneMesh {
  Mesh mesh;                 // in world space: its node's world transform applied
  std::string name;          // the mesh taken ("" = the whole file, or a format of one nameless mesh)
  // Its local space → world: the node's world transform (identity for the whole file and for
  // formats without nodes). A bake writes .pc2 and .obj in local space, by its inverse.
  Eigen::Affine3d to_world = Eigen::Affine3d::Identity();
  std::vector<SceneMeshEntry> meshes;  // the file's meshes, depth first; empty: no names
  bool largest = false;      // taken as the largest of several (no name given)
  // The importer meshes it is made of, in order; for a glTF, by the file's numbers (its primitives
  // counted over its meshes in the file's order, whatever order assimp reads them in: the .glb
  // passthrough's key to which primitives it deforms); empty = all of them, in order.
  std::vector<unsigned> parts;
  MeshUnit unit;
};

// Reads one mesh of `path` by its node's or its mesh's name, or as `pick` says when `name` is
// empty. Error(bad_input) naming the file: a name no mesh has, or several have (the message lists
// the file's meshes and their vertex counts), or any name for a format of one nameless mesh.
SceneMesh read_scene_mesh(const std::filesystem::path& path, const std::string& name, MeshPick pick);

// The file's meshes as "Tail (875 vertices), Ground (4 vertices)", for messages.
std::string list_scene_meshes(const std::vector<SceneMeshEntry>& meshes);

// The project's own text readers on bytes in memory (what read_mesh uses for .off and .obj; the
// fuzz targets drive them directly). `source` names the input in messages. Like read_mesh they
// throw Error(bad_input or unsupported); unlike it they do not call validate_mesh.
Mesh parse_off(std::string_view text, const std::string& source);
Mesh parse_obj(const std::string& text, const std::string& source);
Mesh parse_ply(std::string_view bytes, const std::string& source);  // via assimp, from memory

// check_mesh (core/mesh.h) as a reader's error: throws Error(bad_input) "source: what is wrong",
// naming the vertex or face index at fault.
void validate_mesh(const Mesh& mesh, const std::string& source);

// Wavefront OBJ with `v` lines in vertex order and the mesh's polygons; deterministic bytes.
void write_obj(const std::filesystem::path& path, const Mesh& mesh);

// ASCII OFF ("OFF", a comment with the sweep format version, counts, vertices, polygons) and ASCII
// PLY (double x y z, uint index lists), both with shortest round-trippable numbers.
void write_off(const std::filesystem::path& path, const Mesh& mesh);
void write_ply(const std::filesystem::path& path, const Mesh& mesh);

// Chooses the writer by extension (.obj, .off, .ply, case-insensitive); anything else raises
// Error(unsupported). All writers go through write_file_atomically and refuse a non-finite vertex
// (Error(output), naming the vertex).
void write_mesh(const std::filesystem::path& path, const Mesh& mesh);
bool is_writable_mesh_extension(const std::filesystem::path& path);

// The exact bytes the writers produce (deterministic: C locale, std::to_chars, file order).
std::string obj_bytes(const Mesh& mesh);
std::string off_bytes(const Mesh& mesh);
std::string ply_bytes(const Mesh& mesh);

}  // namespace sweep::assets
