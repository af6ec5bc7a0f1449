// The glTF checks of mesh_checks.h, on the document as gltf_document.h reads it: what assimp would
// crash on, drop silently or blame on something else is refused first, with the JSON pointer.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <optional>

#include "sweep/assets/gltf_document.h"
#include "sweep/assets/mesh_checks.h"
#include "sweep/core/error.h"

namespace sweep::assets::detail {

using Json = nlohmann::json;
using Bytes = std::string;

namespace {

std::size_t array_size(const Json& doc, const char* key) {
  const auto it = doc.find(key);
  return it != doc.end() && it->is_array() ? it->size() : 0;
}

// Bytes of one element of an accessor (0: a type or component this check does not know).
std::uint64_t element_bytes(const Json& accessor) {
  const std::uint64_t type = gltf_unsigned(accessor, "componentType", 0);
  const std::uint64_t component = type == 5120 || type == 5121   ? 1
                                  : type == 5122 || type == 5123 ? 2
                                  : type == 5125 || type == 5126 ? 4
                                                                 : 0;
  const auto t = accessor.find("type");
  if (t == accessor.end() || !t->is_string()) return 0;
  const std::string name = t->get<std::string>();
  const std::uint64_t n = name == "SCALAR" ? 1
                          : name == "VEC2" ? 2
                          : name == "VEC3" ? 3
                          : name == "VEC4" ? 4
                          : name == "MAT2" ? 4
                          : name == "MAT3" ? 9
                          : name == "MAT4" ? 16
                                           : 0;
  return component * n;
}

// Every accessor's elements within its bufferView, and the view within its buffer: a view too
// short for its accessor, or a stride shorter than an element, is the file's fault, said so.
void check_accessors(const std::string& where, const Json& doc, const std::vector<std::optional<Bytes>>& buffers) {
  for (std::size_t a = 0; a < array_size(doc, "accessors"); ++a) {
    const Json& accessor = doc["accessors"][a];
    if (!accessor.is_object() || !accessor.contains("bufferView")) continue;
    const Json* view = gltf_element(doc, "bufferViews", accessor["bufferView"]);
    const std::uint64_t element = element_bytes(accessor);
    if (view == nullptr || element == 0) continue;
    const std::string at = where + "/accessors/" + std::to_string(a) + ": ";
    const std::uint64_t v = accessor["bufferView"].get<std::uint64_t>();
    const std::uint64_t stride = gltf_unsigned(*view, "byteStride", element);
    if (stride < element) {
      fail(ErrorCategory::bad_input, at + "its elements are " + std::to_string(element) +
                                         " bytes, but its bufferView " + std::to_string(v) + " has a byteStride of " +
                                         std::to_string(stride) + " (/bufferViews/" + std::to_string(v) +
                                         "/byteStride)");
    }
    const std::uint64_t count = gltf_unsigned(accessor, "count", 0);
    const std::uint64_t offset = gltf_unsigned(accessor, "byteOffset", 0);
    const std::uint64_t length = gltf_unsigned(*view, "byteLength", 0);
    if (count > 0 &&
        (offset > length || element > length - offset || count - 1 > (length - offset - element) / stride)) {
      fail(ErrorCategory::bad_input, at + std::to_string(count) + " elements of " + std::to_string(element) +
                                         " bytes (stride " + std::to_string(stride) + ") from byte " +
                                         std::to_string(offset) + " do not fit in bufferView " + std::to_string(v) +
                                         "'s " + std::to_string(length) + " bytes");
    }
    const std::uint64_t b = gltf_unsigned(*view, "buffer", buffers.size());
    const std::uint64_t view_offset = gltf_unsigned(*view, "byteOffset", 0);
    // Compared without adding: the file's offset and length may each be up to 2^64 - 1.
    if (b < buffers.size() && buffers[b] && !gltf_fits(view_offset, length, 0, 0, 0, 0, buffers[b]->size())) {
      fail(ErrorCategory::bad_input, where + "/bufferViews/" + std::to_string(v) + ": its " + std::to_string(length) +
                                         " bytes from byte " + std::to_string(view_offset) +
                                         " are past the end of buffer " + std::to_string(b) + " (" +
                                         std::to_string(buffers[b]->size()) + " bytes)");
    }
  }
}

// Nodes' skins: within the skins list, their joints within the nodes, and a skinned node's mesh
// with the JOINTS_0 and WEIGHTS_0 a skin needs (assimp reads past the end without them).
void check_skins(const std::string& where, const Json& doc) {
  const std::size_t nodes = array_size(doc, "nodes"), skins = array_size(doc, "skins");
  for (std::size_t s = 0; s < skins; ++s) {
    const Json& skin = doc["skins"][s];
    if (!skin.is_object() || !skin.contains("joints") || !skin["joints"].is_array()) continue;
    for (std::size_t j = 0; j < skin["joints"].size(); ++j) {
      const Json& joint = skin["joints"][j];
      if (!joint.is_number_unsigned() || joint.get<std::uint64_t>() >= nodes) {
        fail(ErrorCategory::bad_input, where + "/skins/" + std::to_string(s) + "/joints/" + std::to_string(j) + ": " +
                                           joint.dump() + " is not a node (the file has " + std::to_string(nodes) +
                                           ")");
      }
    }
  }
  for (std::size_t n = 0; n < nodes; ++n) {
    const Json& node = doc["nodes"][n];
    if (!node.is_object() || !node.contains("skin")) continue;
    const Json& skin = node["skin"];
    const std::string at = where + "/nodes/" + std::to_string(n) + "/skin: ";
    if (!skin.is_number_unsigned() || skin.get<std::uint64_t>() >= skins) {
      fail(ErrorCategory::bad_input, at + skin.dump() + " is not a skin (the file has " + std::to_string(skins) +
                                         (skins == 1 ? " skin)" : " skins)"));
    }
    const Json* mesh = node.contains("mesh") ? gltf_element(doc, "meshes", node["mesh"]) : nullptr;
    if (mesh == nullptr || !mesh->contains("primitives") || !(*mesh)["primitives"].is_array()) continue;
    for (std::size_t p = 0; p < (*mesh)["primitives"].size(); ++p) {
      const Json& prim = (*mesh)["primitives"][p];
      if (!prim.is_object() || !prim.contains("attributes") || !prim["attributes"].is_object()) continue;
      for (const char* needed : {"JOINTS_0", "WEIGHTS_0"}) {
        if (prim["attributes"].contains(needed)) continue;
        fail(ErrorCategory::bad_input, at + "node " + std::to_string(n) + " is skinned by skin " + skin.dump() +
                                           ", but its mesh " + node["mesh"].dump() + " primitive " + std::to_string(p) +
                                           " has no " + needed + " (/meshes/" + node["mesh"].dump() + "/primitives/" +
                                           std::to_string(p) +
                                           "/attributes): a skinned mesh needs JOINTS_0 and WEIGHTS_0");
      }
    }
  }
}

}  // namespace

Json check_gltf_indices(const std::filesystem::path& path) {
  GltfDocument file = read_gltf_document(path);
  const Json& doc = file.json;
  if (!doc.is_object()) return std::move(file.json);
  check_accessors(path.string() + ": ", doc, file.buffers);
  check_skins(path.string() + ": ", doc);
  if (!doc.contains("meshes") || !doc["meshes"].is_array()) return std::move(file.json);
  const std::vector<std::optional<Bytes>>& buffers = file.buffers;
  for (std::size_t mi = 0; mi < doc["meshes"].size(); ++mi) {
    const Json& mesh = doc["meshes"][mi];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (std::size_t pi = 0; pi < mesh["primitives"].size(); ++pi) {
      const Json& p = mesh["primitives"][pi];
      if (!p.is_object() || !p.contains("attributes")) continue;
      const Json& attributes = p["attributes"];
      if (!attributes.is_object() || !attributes.contains("POSITION")) continue;
      const Json* positions = gltf_element(doc, "accessors", attributes["POSITION"]);
      // Triangles (mode 4, the default) come three indices (or vertices) a face: a remainder is a
      // face cut short, which the importer would drop without a word.
      const Json* counted = p.contains("indices") ? gltf_element(doc, "accessors", p["indices"]) : positions;
      if (gltf_unsigned(p, "mode", 4) == 4 && counted != nullptr && gltf_unsigned(*counted, "count", 0) % 3 != 0) {
        fail(ErrorCategory::bad_input,
             path.string() + ": mesh " + std::to_string(mi) + " primitive " + std::to_string(pi) + ": " +
                 std::to_string(gltf_unsigned(*counted, "count", 0)) +
                 (p.contains("indices") ? " indices" : " vertices") + " (/meshes/" + std::to_string(mi) +
                 "/primitives/" + std::to_string(pi) + (p.contains("indices") ? "/indices" : "/attributes/POSITION") +
                 "), not a multiple of 3: its triangles would end with a face cut short");
      }
      if (!p.contains("indices")) continue;
      const Json* indices = gltf_element(doc, "accessors", p["indices"]);
      if (positions == nullptr || indices == nullptr || indices->contains("sparse")) continue;
      const Json* view =
          indices->contains("bufferView") ? gltf_element(doc, "bufferViews", (*indices)["bufferView"]) : nullptr;
      if (view == nullptr || !view->contains("buffer")) continue;
      const Json& buffer_index = (*view)["buffer"];
      if (!buffer_index.is_number_unsigned() || buffer_index.get<std::uint64_t>() >= buffers.size()) continue;
      const std::optional<Bytes>& data = buffers[buffer_index.get<std::uint64_t>()];
      if (!data) continue;
      const std::uint64_t type = gltf_unsigned(*indices, "componentType", 0);
      const std::uint64_t size = type == 5121 ? 1 : type == 5123 ? 2 : type == 5125 ? 4 : 0;
      if (size == 0) continue;
      const std::uint64_t stride = gltf_unsigned(*view, "byteStride", size);
      const std::uint64_t view_offset = gltf_unsigned(*view, "byteOffset", 0);
      const std::uint64_t view_length = gltf_unsigned(*view, "byteLength", 0);
      const std::uint64_t offset = gltf_unsigned(*indices, "byteOffset", 0);
      const std::uint64_t vertices = gltf_unsigned(*positions, "count", 0);
      const std::uint64_t count = gltf_unsigned(*indices, "count", 0);
      // Indices outside the view or the buffer are assimp's to report; only those within are read.
      if (!gltf_fits(view_offset, view_length, offset, 1, size, stride, data->size())) continue;
      const std::uint64_t fit = 1 + (view_length - offset - size) / stride;
      for (std::uint64_t i = 0; i < std::min(count, fit); ++i) {
        const std::uint64_t a = view_offset + offset + i * stride;
        std::uint32_t v = 0;
        std::memcpy(&v, data->data() + a, size);
        if (size == 1) v &= 0xffu;
        if (size == 2) v &= 0xffffu;
        if (v >= vertices) {
          fail(ErrorCategory::bad_input, path.string() + ": mesh " + std::to_string(mi) + " primitive " +
                                             std::to_string(pi) + ": index " + std::to_string(i) + " is " +
                                             std::to_string(v) + ", past its " + std::to_string(vertices) +
                                             " vertices");
        }
      }
    }
  }
  return std::move(file.json);
}

}  // namespace sweep::assets::detail
