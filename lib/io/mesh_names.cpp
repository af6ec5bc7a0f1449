// The list of a rig's meshes in Rig::mesh_name (mesh_names.h).
#include "sweep/io/mesh_names.h"

namespace sweep::io {

std::vector<std::string> split_mesh_names(std::string_view joined) {
  std::vector<std::string> names;
  if (joined.empty()) return names;
  for (std::size_t at = 0;;) {
    const std::size_t end = joined.find(kMeshNameSeparator, at);
    names.emplace_back(joined.substr(at, end == std::string_view::npos ? std::string_view::npos : end - at));
    if (end == std::string_view::npos) return names;
    at = end + 1;
  }
}

std::string join_mesh_names(const std::vector<std::string>& names) {
  std::string joined;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (k > 0) joined += kMeshNameSeparator;
    joined += names[k];
  }
  return joined;
}

std::string quoted_mesh_names(std::string_view joined) {
  std::string out;
  for (const std::string& name : split_mesh_names(joined)) out += (out.empty() ? "'" : ", '") + name + "'";
  return out;
}

std::string shown_mesh_names(std::string_view joined) {
  return (several_mesh_names(joined) ? "the meshes " : "") + quoted_mesh_names(joined);
}

}  // namespace sweep::io
