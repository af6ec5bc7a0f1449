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
//    and count, and the polygons (checked by tests/io). Single precision (assimp stores floats).
//    Checked first (assets/mesh_checks.h), since assimp silently shifts or drops data otherwise: an
//    ASCII PLY must hold exactly the elements its header announces, one a line; a glTF index
//    past its primitive's vertices is refused.
//  - Text formats (OFF, OBJ, PLY) may start with a UTF-8 byte order mark, which is skipped.
//  - Only regular files are read (a FIFO or a device is refused, not waited on).
//  - STL, FBX and anything else assimp reads: welded by exact position in first-use order (faces
//    in file order, corners in face order; -0 and +0 are one position; vertices no face uses are
//    dropped). These formats have no shared vertex list, so that order is the only one there is.
// For every assimp format: the scene's meshes are concatenated in the scene's mesh order (welding
// is per mesh, so separate meshes stay separate), each placed by the world transform of the first
// node that refers to it (FBX stores local positions under unit-scale and axis nodes), and point
// and line primitives are dropped. An identity transform is applied without arithmetic.
// Bad files raise sweep::Error (bad_input) naming the file and what is wrong, as one line
// "<path>: <what>"; unsupported formats raise ErrorCategory::unsupported.
// Three files, one job each: mesh_text_readers.cpp (OFF, OBJ), mesh_import.cpp (read_mesh, and
// assimp for PLY, glTF and the rest: the only file that sees assimp), mesh_writers.cpp.
#include <filesystem>
#include <string>
#include <string_view>

#include "core/mesh.h"

namespace sweep::io {

Mesh read_mesh(const std::filesystem::path& path);

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

}  // namespace sweep::io
