#pragma once
// A glTF 2.0 file (.gltf or .glb) as its JSON and its buffers' bytes, read with nlohmann::json: the
// Debian tinygltf library's loader does not match its header's layout in this build (its
// destructor frees a wrong pointer), so the project reads what it needs itself — the index check
// of mesh_checks.h and a node's animation (gltf_motion.h). assimp still reads the meshes.
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sweep::assets::detail {

struct GltfDocument {
  nlohmann::json json;  // discarded (not an object) when the text is not JSON
  // Each buffer's bytes: the .glb's binary chunk, a base64 data URI or a file beside the glTF;
  // empty where it cannot be had (assimp reports that itself when it reads the mesh).
  std::vector<std::optional<std::string>> buffers;
};

// Throws Error(bad_input) for a UTF-8 byte order mark before the JSON (which glTF does not allow;
// assimp then finds no reader and says nothing useful); anything else malformed is left to the
// caller (a document that is not an object, accessors that do not fit).
GltfDocument read_gltf_document(const std::filesystem::path& path);

// The bytes a base64 text stands for (a data URI's payload), or nullopt at a character outside the
// alphabet; decoding stops at the first '='.
std::optional<std::string> decode_base64(std::string_view text);

// The element `index` of the top-level array `array` ("accessors", "nodes", ...), or nullptr.
const nlohmann::json* gltf_element(const nlohmann::json& doc, const char* array, const nlohmann::json& index);
// An unsigned member, or `fallback` when absent or not unsigned.
std::uint64_t gltf_unsigned(const nlohmann::json& obj, const char* key, std::uint64_t fallback);
// A string member (a name, an interpolation, a type), or `fallback` when absent or `obj` is not an
// object. Throws Error(bad_input) when it is there but not a string, naming `where` (the file and
// the JSON pointer of `obj`) and the member.
std::string gltf_string(const nlohmann::json& obj, const char* key, const std::string& fallback,
                        const std::string& where);

// Whether `count` elements of `element` bytes, `stride` apart, from byte `offset` of a bufferView
// of `view_length` bytes at byte `view_offset` of a buffer of `buffer_size` bytes, lie within both
// (without overflow: the numbers are the file's, up to 2^64 - 1).
bool gltf_fits(std::uint64_t view_offset, std::uint64_t view_length, std::uint64_t offset, std::uint64_t count,
               std::uint64_t element, std::uint64_t stride, std::uint64_t buffer_size);

// A FLOAT accessor of `components` numbers an element (1 SCALAR, 3 VEC3, 4 VEC4), read whole, in
// element order; nullopt when it is not such an accessor or its bytes do not fit its buffer.
std::optional<std::vector<float>> read_float_accessor(const GltfDocument& file, const nlohmann::json& index,
                                                      int components);

}  // namespace sweep::assets::detail
