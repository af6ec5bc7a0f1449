// The glTF index check of mesh_checks.h. The file is read here with nlohmann::json rather than
// tinygltf: the Debian tinygltf library's TinyGLTF object does not match its header's layout in
// this build (its destructor frees a wrong pointer), and only the index accessors are needed.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <optional>

#include "assets/mesh_checks.h"
#include "core/error.h"
#include "io/atomic_file.h"

namespace sweep::io::detail {
namespace {

using Json = nlohmann::json;
using Bytes = std::string;

std::uint32_t u32_at(const Bytes& b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);  // little-endian, as glTF is (and this build)
  return v;
}

std::optional<Bytes> base64(std::string_view text) {
  Bytes out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (char c : text) {
    int v = -1;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    else if (c >= '0' && c <= '9') v = c - '0' + 52;
    else if (c == '+') v = 62;
    else if (c == '/') v = 63;
    else if (c == '=') break;
    else return std::nullopt;
    acc = (acc << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((acc >> bits) & 0xffu));
    }
  }
  return out;
}

// A buffer's bytes: the .glb's binary chunk, a base64 data URI, or a file beside the glTF.
std::optional<Bytes> buffer_bytes(const Json& buffer, const Bytes& bin,
                                  const std::filesystem::path& dir) {
  if (!buffer.is_object()) return std::nullopt;
  const auto uri = buffer.find("uri");
  if (uri == buffer.end()) return bin;
  if (!uri->is_string()) return std::nullopt;
  const std::string u = uri->get<std::string>();
  if (u.rfind("data:", 0) == 0) {
    const std::size_t comma = u.find(";base64,");
    if (comma == std::string::npos) return std::nullopt;
    return base64(std::string_view(u).substr(comma + 8));
  }
  try {
    return read_file(dir / u);
  } catch (const Error&) {
    return std::nullopt;  // assimp reports a missing buffer itself
  }
}

std::uint64_t number(const Json& obj, const char* key, std::uint64_t fallback) {
  const auto it = obj.find(key);
  return it != obj.end() && it->is_number_unsigned() ? it->get<std::uint64_t>() : fallback;
}

const Json* at(const Json& doc, const char* array, const Json& index) {
  const auto it = doc.find(array);
  if (it == doc.end() || !it->is_array() || !index.is_number_unsigned()) return nullptr;
  const auto i = index.get<std::uint64_t>();
  return i < it->size() && (*it)[i].is_object() ? &(*it)[i] : nullptr;
}

}  // namespace

void check_gltf_indices(const std::filesystem::path& path) {
  const Bytes file = read_file(path);
  // glTF JSON is UTF-8 without a byte order mark (glTF 2.0, "JSON encoding"); assimp then finds
  // no reader at all, so say what is wrong.
  if (file.compare(0, 3, "\xEF\xBB\xBF") == 0) {
    fail(ErrorCategory::bad_input, path.string() +
                                       ": starts with a UTF-8 byte order mark, which glTF does not "
                                       "allow before its JSON; save it without one");
  }
  Bytes json_text = file, bin;
  if (file.size() >= 20 && file.compare(0, 4, "glTF") == 0) {
    const std::uint32_t json_length = u32_at(file, 12);
    if (json_length > file.size() - 20) return;
    json_text = file.substr(20, json_length);
    const std::size_t bin_at = 20 + std::size_t{json_length};
    if (bin_at + 8 <= file.size()) bin = file.substr(bin_at + 8, u32_at(file, bin_at));
  }
  const Json doc = Json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (!doc.is_object() || !doc.contains("meshes") || !doc["meshes"].is_array()) return;
  std::vector<std::optional<Bytes>> buffers;
  if (doc.contains("buffers") && doc["buffers"].is_array()) {
    for (const Json& b : doc["buffers"]) buffers.push_back(buffer_bytes(b, bin, path.parent_path()));
  }
  for (std::size_t mi = 0; mi < doc["meshes"].size(); ++mi) {
    const Json& mesh = doc["meshes"][mi];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (std::size_t pi = 0; pi < mesh["primitives"].size(); ++pi) {
      const Json& p = mesh["primitives"][pi];
      if (!p.is_object() || !p.contains("indices") || !p.contains("attributes")) continue;
      const Json& attributes = p["attributes"];
      if (!attributes.is_object() || !attributes.contains("POSITION")) continue;
      const Json* positions = at(doc, "accessors", attributes["POSITION"]);
      const Json* indices = at(doc, "accessors", p["indices"]);
      if (positions == nullptr || indices == nullptr || indices->contains("sparse")) continue;
      const Json* view = indices->contains("bufferView")
                             ? at(doc, "bufferViews", (*indices)["bufferView"])
                             : nullptr;
      if (view == nullptr || !view->contains("buffer")) continue;
      const Json& buffer_index = (*view)["buffer"];
      if (!buffer_index.is_number_unsigned() || buffer_index.get<std::uint64_t>() >= buffers.size())
        continue;
      const std::optional<Bytes>& data = buffers[buffer_index.get<std::uint64_t>()];
      if (!data) continue;
      const std::uint64_t type = number(*indices, "componentType", 0);
      const std::uint64_t size = type == 5121 ? 1 : type == 5123 ? 2 : type == 5125 ? 4 : 0;
      if (size == 0) continue;
      const std::uint64_t stride = number(*view, "byteStride", size);
      const std::uint64_t begin = number(*view, "byteOffset", 0) + number(*indices, "byteOffset", 0);
      const std::uint64_t view_end = number(*view, "byteOffset", 0) + number(*view, "byteLength", 0);
      const std::uint64_t vertices = number(*positions, "count", 0);
      const std::uint64_t count = number(*indices, "count", 0);
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
}

}  // namespace sweep::io::detail
