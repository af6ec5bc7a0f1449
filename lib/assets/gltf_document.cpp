#include "sweep/assets/gltf_document.h"

#include <cstring>
#include <string_view>

#include "sweep/core/error.h"
#include "sweep/io/json_reader.h"
#include "sweep/io/read_file.h"

using sweep::io::describe;
using sweep::io::read_file;

namespace sweep::assets::detail {
namespace {

using Json = nlohmann::json;
using Bytes = std::string;

std::uint32_t u32_at(const Bytes& b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);  // little-endian, as glTF is (and this build)
  return v;
}

// A buffer's bytes: the .glb's binary chunk, a base64 data URI, or a file beside the glTF.
std::optional<Bytes> buffer_bytes(const Json& buffer, const Bytes& bin, const std::filesystem::path& gltf,
                                  std::size_t index) {
  const std::filesystem::path dir = gltf.parent_path();
  if (!buffer.is_object()) return std::nullopt;
  const auto uri = buffer.find("uri");
  if (uri == buffer.end()) return bin;
  if (!uri->is_string()) return std::nullopt;
  const std::string u = uri->get<std::string>();
  if (u.rfind("data:", 0) == 0) {
    const std::size_t comma = u.find(";base64,");
    if (comma == std::string::npos) return std::nullopt;
    return decode_base64(std::string_view(u).substr(comma + 8));
  }
  const std::filesystem::path file = dir / u;
  std::error_code ec;
  // A FIFO or a device would block the importer forever (or never end): said here, by name.
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec)) {
    fail(ErrorCategory::bad_input,
         gltf.string() + ": /buffers/" + std::to_string(index) + "/uri: '" + u +
             "' is not a regular file (a FIFO, a device or a folder); a buffer must be a file");
  }
  try {
    return read_file(file);
  } catch (const Error&) {
    return std::nullopt;  // assimp reports a missing buffer itself
  }
}

}  // namespace

std::optional<std::string> decode_base64(std::string_view text) {
  std::string out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (char c : text) {
    int v = -1;
    if (c >= 'A' && c <= 'Z')
      v = c - 'A';
    else if (c >= 'a' && c <= 'z')
      v = c - 'a' + 26;
    else if (c >= '0' && c <= '9')
      v = c - '0' + 52;
    else if (c == '+')
      v = 62;
    else if (c == '/')
      v = 63;
    else if (c == '=')
      break;
    else
      return std::nullopt;
    acc = (acc << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((acc >> bits) & 0xffu));
    }
  }
  return out;
}

std::uint64_t gltf_unsigned(const Json& obj, const char* key, std::uint64_t fallback) {
  const auto it = obj.find(key);
  return it != obj.end() && it->is_number_unsigned() ? it->get<std::uint64_t>() : fallback;
}

std::string gltf_string(const Json& obj, const char* key, const std::string& fallback, const std::string& where) {
  const auto it = obj.is_object() ? obj.find(key) : obj.end();
  if (!obj.is_object() || it == obj.end()) return fallback;
  if (!it->is_string()) fail(ErrorCategory::bad_input, where + "/" + key + ": must be a string, got " + describe(*it));
  return it->get<std::string>();
}

bool gltf_fits(std::uint64_t view_offset, std::uint64_t view_length, std::uint64_t offset, std::uint64_t count,
               std::uint64_t element, std::uint64_t stride, std::uint64_t buffer_size) {
  if (view_offset > buffer_size || view_length > buffer_size - view_offset) return false;
  if (count == 0) return offset <= view_length;
  return stride >= element && element > 0 && offset <= view_length && element <= view_length - offset &&
         count - 1 <= (view_length - offset - element) / stride;
}

const Json* gltf_element(const Json& doc, const char* array, const Json& index) {
  const auto it = doc.find(array);
  if (it == doc.end() || !it->is_array() || !index.is_number_unsigned()) return nullptr;
  const auto i = index.get<std::uint64_t>();
  return i < it->size() && (*it)[i].is_object() ? &(*it)[i] : nullptr;
}

GltfDocument read_gltf_document(const std::filesystem::path& path) {
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
    if (json_length > file.size() - 20) return {};
    json_text = file.substr(20, json_length);
    const std::size_t bin_at = 20 + std::size_t{json_length};
    if (bin_at + 8 <= file.size()) bin = file.substr(bin_at + 8, u32_at(file, bin_at));
  }
  GltfDocument out;
  out.json = Json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (out.json.is_object() && out.json.contains("buffers") && out.json["buffers"].is_array()) {
    for (const Json& b : out.json["buffers"]) out.buffers.push_back(buffer_bytes(b, bin, path, out.buffers.size()));
  }
  return out;
}

std::optional<std::vector<float>> read_float_accessor(const GltfDocument& file, const Json& index, int components) {
  const Json* accessor = gltf_element(file.json, "accessors", index);
  if (accessor == nullptr || accessor->contains("sparse")) return std::nullopt;
  const char* type = components == 1 ? "SCALAR" : components == 3 ? "VEC3" : components == 4 ? "VEC4" : "";
  const auto t = accessor->find("type");
  if (gltf_unsigned(*accessor, "componentType", 0) != 5126 || t == accessor->end() || *t != type) return std::nullopt;
  const Json* view =
      accessor->contains("bufferView") ? gltf_element(file.json, "bufferViews", (*accessor)["bufferView"]) : nullptr;
  if (view == nullptr || !view->contains("buffer")) return std::nullopt;
  const std::uint64_t b = gltf_unsigned(*view, "buffer", file.buffers.size());
  if (b >= file.buffers.size() || !file.buffers[b]) return std::nullopt;
  const Bytes& data = *file.buffers[b];
  const std::uint64_t element = 4u * static_cast<std::uint64_t>(components);
  const std::uint64_t stride = gltf_unsigned(*view, "byteStride", element);
  const std::uint64_t view_begin = gltf_unsigned(*view, "byteOffset", 0);
  const std::uint64_t offset = gltf_unsigned(*accessor, "byteOffset", 0);
  const std::uint64_t count = gltf_unsigned(*accessor, "count", 0);
  if (!gltf_fits(view_begin, gltf_unsigned(*view, "byteLength", 0), offset, count, element, stride, data.size())) {
    return std::nullopt;
  }
  const std::uint64_t begin = view_begin + offset;
  std::vector<float> out(count * static_cast<std::uint64_t>(components));
  for (std::uint64_t i = 0; i < count; ++i) {
    std::memcpy(out.data() + i * components, data.data() + begin + i * stride, element);  // little-endian
  }
  return out;
}

}  // namespace sweep::assets::detail
