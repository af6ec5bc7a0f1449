#pragma once
// The binding file: compact, little-endian, versioned binary. Layout (offsets in bytes):
//
//   header (48 bytes)
//     0  char[8]  magic "SWPBIND\0"
//     8  u32      format version (kBindingFormatVersion)
//    12  u32      sweep count S
//    16  u64      vertex count of the mesh it was made for
//    24  u64      mesh hash (hash_positions: FNV-1a 64 of the positions' bytes as doubles)
//    32  u64      rig hash (hash_sweeps: FNV-1a 64 of the sweeps' names, rest shapes, part seeds)
//    40  u64      payload size P in bytes
//   payload (P bytes): S sweep tables, in rig order, each
//          u32      name length N, then N bytes of UTF-8 name
//          u64      bound vertex count M
//          u32[M]   vertex indices, strictly increasing
//          f32[M]   t, then f32[M] θ, f32[M] s, f32[M] z, f32[M] blend weight
//   trailer (8 bytes)
//          u64      checksum: FNV-1a 64 of every byte before it (header and payload)
//
// Reading checks, in order: size, magic, version, payload size against the file size (truncated or
// trailing bytes), checksum (corrupt), the tables' own consistency; then, against a mesh and rig,
// the vertex count, the mesh hash and the rig hash. Every failure is Error(bad_input) naming the
// file and what is wrong (a version newer than this program's is Error(unsupported)).
// Writing is deterministic (same binding, same bytes) and atomic.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "sweep/bind/bind.h"

namespace sweep::io {

// 2: the rig hash is of the sweeps' numbers (bind.h, hash_sweeps); format 1 hashed the rig's JSON
// text and is refused with a message to bind again.
inline constexpr std::uint32_t kBindingFormatVersion = 2;

std::string binding_bytes(const bind::Binding& binding);

// Where sweep-bind writes a rig's binding, and sweep-sim looks for it, when no path is given: the
// rig's path with ".bind" ("dino.rig.json" → "dino.rig.bind").
inline std::filesystem::path default_binding_path(const std::filesystem::path& rig_path) {
  return std::filesystem::path(rig_path).replace_extension(".bind");
}
void write_binding(const std::filesystem::path& path, const bind::Binding& binding);

// Parses and checks the file's own integrity (not whether it matches a mesh or rig). `source`
// names the file in messages.
bind::Binding parse_binding(std::string_view bytes, const std::string& source);
bind::Binding read_binding(const std::filesystem::path& path);

// Refuses (Error(bad_input), "source: what is wrong; run sweep-bind again") a binding made for
// another mesh (vertex count, positions) or another version of the rig's sweeps.
void check_binding(const bind::Binding& binding, const Mesh& mesh, const Rig& rig, const std::string& source);

// read_binding followed by check_binding.
bind::Binding load_binding(const std::filesystem::path& path, const Mesh& mesh, const Rig& rig);

}  // namespace sweep::io
