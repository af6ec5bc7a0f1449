#pragma once
// Checks the mesh readers make on the file itself, for what the third-party parsers behind them
// (assimp) would otherwise drop or shift without a word. Each throws Error(bad_input) naming
// `source` and the place (line, mesh/primitive, index).
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace sweep::assets::detail {

// A PLY header must be well formed ("ply", one format line, element and property lines of known
// types, end_header: assimp hangs on some malformed headers). An ASCII PLY's body must hold exactly the element
// instances its header announces, one a line, each with the values its properties call for: a header announcing more
// vertices than there are would have assimp read face lines as vertices. Any PLY's vertex element must have x, y and z.
// The body of a binary PLY, and text that is not PLY, pass unchecked.
void check_ascii_ply(std::string_view text, const std::string& source);

// Every index of every indexed primitive of a glTF/glb must be below its POSITION count: assimp
// 5.2 drops a triangle with an index past the end silently. What this check cannot read (malformed
// JSON, a missing buffer) is left to assimp to report. Returns the document's JSON (discarded, not
// an object, when the text is not JSON) for the reader's further use.
nlohmann::json check_gltf_indices(const std::filesystem::path& path);

}  // namespace sweep::assets::detail
