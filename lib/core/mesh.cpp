#include "sweep/core/mesh.h"

#include <algorithm>
#include <sstream>

#include "sweep/core/frame.h"

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

std::string check_mesh(const Mesh& mesh) {
  const auto& off = mesh.face_offsets;
  if (off.empty() || off.front() != 0 || off.back() != mesh.face_vertices.size() ||
      !std::is_sorted(off.begin(), off.end())) {
    return "malformed face table";
  }
  if (mesh.positions.empty()) return "no vertices";
  if (mesh.face_count() == 0) return "no faces";
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec3& p = mesh.positions[i];
    if (!is_finite(p)) {
      std::ostringstream s;
      s << "vertex " << i << " has a non-finite coordinate (" << p.x() << ", " << p.y() << ", " << p.z() << ")";
      return s.str();
    }
  }
  const std::size_t nv = mesh.positions.size();
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t begin = off[f], end = off[f + 1];
    if (end - begin < 3) {
      return "face " + std::to_string(f) + " has " + std::to_string(end - begin) +
             " vertices (a face needs at least 3)";
    }
    for (std::uint32_t k = begin; k < end; ++k) {
      if (mesh.face_vertices[k] >= nv) {
        return "face " + std::to_string(f) + " uses vertex " + std::to_string(mesh.face_vertices[k]) +
               ", out of range (the mesh has " + std::to_string(nv) + " vertices)";
      }
    }
  }
  return "";
}

}  // namespace sweep
