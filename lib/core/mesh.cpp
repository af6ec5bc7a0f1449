#include "core/mesh.h"

namespace sweep {

std::vector<std::uint32_t> Mesh::triangles() const {
  std::vector<std::uint32_t> out;
  out.reserve(face_vertices.size() * 3);
  for (std::size_t f = 0; f < face_count(); ++f) {
    const std::uint32_t begin = face_offsets[f], end = face_offsets[f + 1];
    for (std::uint32_t k = begin + 1; k + 1 < end; ++k) {
      out.insert(out.end(), {face_vertices[begin], face_vertices[k], face_vertices[k + 1]});
    }
  }
  return out;
}

}  // namespace sweep
