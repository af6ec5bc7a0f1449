#pragma once
// A polygon mesh as plain arrays, in the input file's vertex order (a point cache and a binding
// depend on that order, so nothing here ever reorders vertices).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace sweep {

using Vec3 = Eigen::Vector3d;

struct Mesh {
  std::vector<Vec3> positions;
  // Faces in compressed rows: face f uses face_vertices[face_offsets[f] .. face_offsets[f+1]).
  // face_offsets has face_count()+1 entries (a lone 0 for a mesh with no faces).
  std::vector<std::uint32_t> face_offsets{0};
  std::vector<std::uint32_t> face_vertices;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t face_count() const { return face_offsets.size() - 1; }
  void add_face(std::initializer_list<std::uint32_t> vertices) {
    face_vertices.insert(face_vertices.end(), vertices);
    face_offsets.push_back(static_cast<std::uint32_t>(face_vertices.size()));
  }
  // Triangles by fanning each polygon from its first vertex (3 indices a triangle).
  std::vector<std::uint32_t> triangles() const;
};

// What is wrong with a mesh that the algorithms cannot take (a malformed face table, no vertices
// or faces, a non-finite coordinate, a face of fewer than 3 vertices or one that names a vertex
// out of range), or "" when nothing is. Readers turn it into a message naming the file.
std::string check_mesh(const Mesh& mesh);

}  // namespace sweep
