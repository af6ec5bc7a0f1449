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
// Several meshes as one (a body and its legs modelled as separate objects): a list of names
// (io/mesh_names.h: joined by NUL, as a rig holds it), or kAllMeshes, takes those nodes' meshes
// as one mesh in world space, their vertices concatenated node after node (in the list's order, or
// with `file_order` in the file's: the nodes depth first, as read_scene_mesh lists them), each
// node's importer meshes in its order, each placed by its own node's world transform. No node may
// be named twice; each name must find its node alone (the rig records the nodes' names).
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
  std::string name;              // its node's name: what --mesh and a rig's mesh_name give
  std::string mesh_name;         // its mesh's name ("" when its parts are named unlike each other)
  std::size_t vertex_count = 0;  // as read (welded where the format welds)
};

// How the file's length unit was taken (assimp's scene metadata): FBX states one.
struct MeshUnit {
  double unit_scale_factor = 0;           // FBX UnitScaleFactor: centimetres per file unit; 0 = none stated
  double original_unit_scale_factor = 0;  // FBX OriginalUnitScaleFactor (0 = none stated)
};

// Which way is up in the mesh's world space, as the file says it (names of parts go by it: a leg
// points down). glTF is +Y up by its specification; an FBX states it in its GlobalSettings (UpAxis,
// UpAxisSign: assimp's scene metadata "UpAxis", "UpAxisSign"), a Collada file in <asset><up_axis>
// (which assimp's reader applies, turning the scene so that it is +Y up; the direction is taken
// through the scene's root transform either way). A format that is Z up by its own convention
// (Blender's .blend, Source's .smd, trueSpace's .cob, the Quake family's .md2, .md3, .mdc, .mdl,
// .md5mesh, .iqm, 3ds Max's .3ds and .ase) gives +Z through the same root transform: +Z where the
// reader keeps the coordinates, +Y where it turned the scene. OFF, OBJ, PLY, STL and the rest
// state none: +Y.
struct FileUp {
  Vec3 direction = Vec3::UnitY();                            // unit, in the mesh's world space
  bool stated = false;                                       // the file (or its format) says it
  std::string why = "the file states no up axis: +Y taken";  // for a person: where it comes from
};

// "+Z" for (0, 0, 1), "-Y" for (0, -1, 0); any other direction as its numbers.
std::string direction_name(const Vec3& direction);

// Which mesh of a file read_scene_mesh takes.
enum class MeshPick {
  whole_file,       // `name` empty: the whole file, as read_mesh (a rig without a mesh name)
  only_or_largest,  // `name` empty: the only mesh, or the one with the most vertices (the first
                    // of those that tie)
  every_mesh,       // `name` empty: the only mesh, or of several all of them as one, as kAllMeshes
                    // takes them (sweep-fit --list and --all: a creature whose legs are meshes of
                    // their own is searched whole); the largest when two nodes share a name
};

// A name that takes every mesh of the file as one (its nodes in the file's order), unless a mesh
// of the file has that name.
inline constexpr const char* kAllMeshes = "all";

struct SceneMesh {
  Mesh mesh;         // in world space: its node's world transform applied
  std::string name;  // the mesh taken ("" = the whole file, or a format of one nameless mesh);
                     // several: their nodes' names, in order, joined (io/mesh_names.h)
  // Its local space → world: the node's world transform (identity for the whole file, several
  // meshes and formats without nodes). A bake writes .pc2 and .obj in local space, by its inverse.
  Eigen::Affine3d to_world = Eigen::Affine3d::Identity();
  std::vector<SceneMeshEntry> meshes;  // the file's meshes, depth first; empty: no names
  bool largest = false;                // taken as the largest of several (no name given)
  bool every = false;                  // every mesh of several taken as one (MeshPick::every_mesh)
  // The importer meshes it is made of, in order; for a glTF, by the file's numbers (its primitives
  // counted over its meshes in the file's order, whatever order assimp reads them in: the .glb
  // passthrough's key to which primitives it deforms); empty = all of them, in order.
  std::vector<unsigned> parts;
  MeshUnit unit;
  FileUp up;
};

// Reads one mesh of `path` by its node's or its mesh's name, or as `pick` says when `name` is
// empty; several as one for a list of names or kAllMeshes (above). Error(bad_input) naming the
// file: a name no mesh has, or several have (the message lists the file's meshes and their vertex
// counts), a mesh named twice in a list, or any name for a format of one nameless mesh.
SceneMesh read_scene_mesh(const std::filesystem::path& path, const std::string& name, MeshPick pick,
                          bool file_order = false);

// "mesh 'Tail'", or "meshes 'Body', 'LegL'" for a list: what a name asks for, for messages.
std::string asked_meshes(const std::string& name);

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
