#include <tiny_gltf.h>

#include <cstring>

#include "core/error.h"
#include "io/mesh_checks.h"

namespace sweep::io::detail {
namespace {

// Images play no part in a mesh: a loader that accepts them unread keeps tinygltf from decoding.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;
}

// The value of index `i` of an index accessor; false when the accessor does not fit its buffer
// (assimp then reports the file, or reads what it can: that is not this check's business).
bool read_index(const tinygltf::Model& m, const tinygltf::Accessor& a, std::size_t i,
                std::uint64_t& value) {
  if (a.bufferView < 0 || a.bufferView >= static_cast<int>(m.bufferViews.size())) return false;
  const tinygltf::BufferView& view = m.bufferViews[a.bufferView];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(m.buffers.size())) return false;
  const std::vector<unsigned char>& data = m.buffers[view.buffer].data;
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  if (size != 1 && size != 2 && size != 4) return false;
  const int stride = a.ByteStride(view);
  if (stride <= 0) return false;
  const std::size_t at = view.byteOffset + a.byteOffset + i * static_cast<std::size_t>(stride);
  if (at + size > data.size() || at + size > view.byteOffset + view.byteLength) return false;
  std::uint32_t v = 0;
  std::memcpy(&v, data.data() + at, size);  // little-endian, as glTF is
  value = size == 1 ? (v & 0xffu) : size == 2 ? (v & 0xffffu) : v;
  return true;
}

}  // namespace

void check_gltf_indices(const std::filesystem::path& path) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool binary = path.extension() == ".glb" || path.extension() == ".GLB";
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                         : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
  if (!ok) return;
  for (std::size_t mi = 0; mi < model.meshes.size(); ++mi) {
    const auto& prims = model.meshes[mi].primitives;
    for (std::size_t pi = 0; pi < prims.size(); ++pi) {
      const tinygltf::Primitive& p = prims[pi];
      const auto pos = p.attributes.find("POSITION");
      if (p.indices < 0 || pos == p.attributes.end()) continue;
      if (p.indices >= static_cast<int>(model.accessors.size()) || pos->second < 0 ||
          pos->second >= static_cast<int>(model.accessors.size())) {
        continue;
      }
      const std::size_t vertices = model.accessors[pos->second].count;
      const tinygltf::Accessor& idx = model.accessors[p.indices];
      if (idx.sparse.isSparse) continue;
      for (std::size_t i = 0; i < idx.count; ++i) {
        std::uint64_t v = 0;
        if (!read_index(model, idx, i, v)) break;
        if (v >= vertices) {
          fail(ErrorCategory::bad_input,
               path.string() + ": mesh " + std::to_string(mi) + " primitive " +
                   std::to_string(pi) + ": index " + std::to_string(i) + " is " +
                   std::to_string(v) + ", past its " + std::to_string(vertices) + " vertices");
        }
      }
    }
  }
}

}  // namespace sweep::io::detail
