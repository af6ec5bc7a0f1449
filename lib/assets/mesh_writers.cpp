// The writers of mesh_io.h: OBJ, OFF and ASCII PLY, deterministic bytes (shortest round-trippable
// numbers, file order), written atomically.
#include <algorithm>
#include <cstdint>
#include <string>

#include "sweep/assets/mesh_io.h"
#include "sweep/assets/mesh_io_detail.h"
#include "sweep/core/error.h"
#include "sweep/core/frame.h"
#include "sweep/core/text.h"
#include "sweep/io/atomic_file.h"

using sweep::io::write_file_atomically;

namespace sweep::assets {
namespace fs = std::filesystem;
namespace {

// Writers refuse what no reader should ever see: a non-finite coordinate or a broken face table.
void check_writable(const fs::path& path, const Mesh& mesh) {
  const auto& off = mesh.face_offsets;
  if (off.empty() || off.front() != 0 || off.back() != mesh.face_vertices.size()) {
    fail(ErrorCategory::internal, path.string() + ": refusing to write a malformed face table");
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!is_finite(mesh.positions[i])) {
      fail(ErrorCategory::output, path.string() + ": refusing to write vertex " + std::to_string(i) +
                                      ": non-finite coordinate " + format_exact_point(mesh.positions[i]));
    }
  }
  for (std::uint32_t v : mesh.face_vertices) {
    if (v >= mesh.positions.size()) {
      fail(ErrorCategory::internal, path.string() + ": refusing to write a face index out of range");
    }
  }
}

// Faces as OFF and ASCII PLY both write them: "count i0 i1 ...", 0-based, one a line.
void append_counted_faces(std::string& out, const Mesh& mesh) {
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    append_number(out, std::uint64_t{mesh.face_offsets[f + 1] - mesh.face_offsets[f]});
    for (std::uint32_t k = mesh.face_offsets[f]; k < mesh.face_offsets[f + 1]; ++k) {
      out += ' ';
      append_number(out, std::uint64_t{mesh.face_vertices[k]});
    }
    out += '\n';
  }
}

}  // namespace

namespace detail {

void append_obj_faces(std::string& out, const Mesh& mesh) {
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    out += 'f';
    for (std::uint32_t k = mesh.face_offsets[f]; k < mesh.face_offsets[f + 1]; ++k) {
      out += ' ';
      append_number(out, std::uint64_t{mesh.face_vertices[k]} + 1);
    }
    out += '\n';
  }
}

}  // namespace detail

std::string obj_bytes(const Mesh& mesh) {
  std::string out = "# sweep mesh 1: " + std::to_string(mesh.vertex_count()) + " vertices, " +
                    std::to_string(mesh.face_count()) + " faces\n";
  out.reserve(out.size() + mesh.vertex_count() * 64 + mesh.face_vertices.size() * 8);
  for (const Vec3& p : mesh.positions) detail::append_vertex_line(out, "v ", p);
  detail::append_obj_faces(out, mesh);
  return out;
}

std::string off_bytes(const Mesh& mesh) {
  std::string out = "OFF\n# sweep mesh 1\n";
  append_number(out, std::uint64_t{mesh.vertex_count()});
  out += ' ';
  append_number(out, std::uint64_t{mesh.face_count()});
  out += " 0\n";
  for (const Vec3& p : mesh.positions) detail::append_vertex_line(out, "", p);
  append_counted_faces(out, mesh);
  return out;
}

std::string ply_bytes(const Mesh& mesh) {
  std::uint32_t widest = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    widest = std::max(widest, mesh.face_offsets[f + 1] - mesh.face_offsets[f]);
  }
  std::string out =
      "ply\nformat ascii 1.0\ncomment sweep mesh 1\nelement vertex " + std::to_string(mesh.vertex_count()) +
      "\nproperty double x\nproperty double y\nproperty double z\nelement face " + std::to_string(mesh.face_count()) +
      "\nproperty list " + (widest <= 255 ? "uchar" : "uint") + " uint vertex_indices\nend_header\n";
  for (const Vec3& p : mesh.positions) detail::append_vertex_line(out, "", p);
  append_counted_faces(out, mesh);
  return out;
}

void write_obj(const fs::path& path, const Mesh& mesh) {
  check_writable(path, mesh);
  write_file_atomically(path, obj_bytes(mesh));
}

void write_off(const fs::path& path, const Mesh& mesh) {
  check_writable(path, mesh);
  write_file_atomically(path, off_bytes(mesh));
}

void write_ply(const fs::path& path, const Mesh& mesh) {
  check_writable(path, mesh);
  write_file_atomically(path, ply_bytes(mesh));
}

bool is_writable_mesh_extension(const fs::path& path) {
  const std::string ext = lower_extension(path);
  return ext == "obj" || ext == "off" || ext == "ply";
}

void write_mesh(const fs::path& path, const Mesh& mesh) {
  const std::string ext = lower_extension(path);
  if (ext == "obj") return write_obj(path, mesh);
  if (ext == "off") return write_off(path, mesh);
  if (ext == "ply") return write_ply(path, mesh);
  fail(ErrorCategory::unsupported,
       path.string() + ": cannot write mesh format '" + path.extension().string() + "' (write .obj, .off or .ply)");
}

}  // namespace sweep::assets
