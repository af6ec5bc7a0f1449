// The glTF index check of mesh_checks.h, on the document as gltf_document.h reads it.
#include <cstdint>
#include <cstring>
#include <optional>

#include "assets/gltf_document.h"
#include "assets/mesh_checks.h"
#include "core/error.h"

namespace sweep::io::detail {

using Json = nlohmann::json;
using Bytes = std::string;

Json check_gltf_indices(const std::filesystem::path& path) {
  GltfDocument file = read_gltf_document(path);
  const Json& doc = file.json;
  if (!doc.is_object() || !doc.contains("meshes") || !doc["meshes"].is_array()) return std::move(file.json);
  const std::vector<std::optional<Bytes>>& buffers = file.buffers;
  for (std::size_t mi = 0; mi < doc["meshes"].size(); ++mi) {
    const Json& mesh = doc["meshes"][mi];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (std::size_t pi = 0; pi < mesh["primitives"].size(); ++pi) {
      const Json& p = mesh["primitives"][pi];
      if (!p.is_object() || !p.contains("indices") || !p.contains("attributes")) continue;
      const Json& attributes = p["attributes"];
      if (!attributes.is_object() || !attributes.contains("POSITION")) continue;
      const Json* positions = gltf_element(doc, "accessors", attributes["POSITION"]);
      const Json* indices = gltf_element(doc, "accessors", p["indices"]);
      if (positions == nullptr || indices == nullptr || indices->contains("sparse")) continue;
      const Json* view = indices->contains("bufferView")
                             ? gltf_element(doc, "bufferViews", (*indices)["bufferView"])
                             : nullptr;
      if (view == nullptr || !view->contains("buffer")) continue;
      const Json& buffer_index = (*view)["buffer"];
      if (!buffer_index.is_number_unsigned() || buffer_index.get<std::uint64_t>() >= buffers.size())
        continue;
      const std::optional<Bytes>& data = buffers[buffer_index.get<std::uint64_t>()];
      if (!data) continue;
      const std::uint64_t type = gltf_unsigned(*indices, "componentType", 0);
      const std::uint64_t size = type == 5121 ? 1 : type == 5123 ? 2 : type == 5125 ? 4 : 0;
      if (size == 0) continue;
      const std::uint64_t stride = gltf_unsigned(*view, "byteStride", size);
      const std::uint64_t begin = gltf_unsigned(*view, "byteOffset", 0) + gltf_unsigned(*indices, "byteOffset", 0);
      const std::uint64_t view_end = gltf_unsigned(*view, "byteOffset", 0) + gltf_unsigned(*view, "byteLength", 0);
      const std::uint64_t vertices = gltf_unsigned(*positions, "count", 0);
      const std::uint64_t count = gltf_unsigned(*indices, "count", 0);
      for (std::uint64_t i = 0; i < count; ++i) {
        const std::uint64_t a = begin + i * stride;
        if (stride == 0 || a + size > data->size() || a + size > view_end) break;  // assimp's call
        std::uint32_t v = 0;
        std::memcpy(&v, data->data() + a, size);
        if (size == 1) v &= 0xffu;
        if (size == 2) v &= 0xffffu;
        if (v >= vertices) {
          fail(ErrorCategory::bad_input,
               path.string() + ": mesh " + std::to_string(mi) + " primitive " + std::to_string(pi) +
                   ": index " + std::to_string(i) + " is " + std::to_string(v) + ", past its " +
                   std::to_string(vertices) + " vertices");
        }
      }
    }
  }
  return std::move(file.json);
}

}  // namespace sweep::io::detail
