#pragma once
// Private to the mesh files of lib/assets: what the text readers (mesh_text_readers.cpp), the
// import (mesh_import.cpp), the writers (mesh_writers.cpp) and the OBJ bake (bake_obj.cpp) share.
#include <string>
#include <string_view>

#include "sweep/core/error.h"
#include "sweep/core/mesh.h"
#include "sweep/core/text.h"

namespace sweep::assets::detail {

// A reader's error: Error(bad_input) "<source>: <what>".
[[noreturn]] inline void bad(const std::string& source, const std::string& what) {
  fail(ErrorCategory::bad_input, source + ": " + what);
}

// A UTF-8 byte order mark is an encoding marker, not content: editors on Windows put one before
// the first line, and a reader that took it for part of the first token would shift the data.
inline std::string_view skip_bom(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return text;
}

// One vertex line: `prefix`, then the coordinates blank-separated, shortest round-trippable
// ("v 1 2.5 -0\n" in OBJ; no prefix in OFF and PLY).
template <typename Scalar>
void append_vertex_line(std::string& out, std::string_view prefix, const Eigen::Matrix<Scalar, 3, 1>& p) {
  out += prefix;
  append_numbers(out, p, " ");
  out += '\n';
}

// The mesh's polygons as OBJ `f` lines, "f i0 i1 ...", 1-based, one a face, in face order.
void append_obj_faces(std::string& out, const Mesh& mesh);

}  // namespace sweep::assets::detail
