#pragma once
// The rig file: JSON, versioned ("format": "sweep-rig", "version": 1), schema in rigs/rig.schema.json.
// Reading validates everything and throws Error(bad_input) with the file, the JSON pointer and what
// is wrong ("rig.json: /sweeps/0/sections/2/radii/5: must be a positive number, got -1"), or the
// line and column for malformed JSON. Unknown fields are reported as warnings, not errors.
// Writing is deterministic (stable key order, round-trippable numbers) and atomic.
#include <filesystem>
#include <functional>
#include <string>

#include "sweep/core/presets.h"
#include "sweep/core/rig.h"

namespace sweep::io {

using WarningSink = std::function<void(const std::string&)>;

Rig parse_rig(const std::string& text, const std::string& source, const WarningSink& warn = {});
Rig read_rig(const std::filesystem::path& path, const WarningSink& warn = {});

std::string format_rig(const Rig& rig);

// A material on its own (sweep-fit --material): a JSON object with the members of a rig sweep's
// "material" (youngs_modulus_pa, poisson_ratio or shear_modulus_pa, density_kg_m3,
// metres_per_unit, damping_ratio), checked by the same rules, errors naming the file and pointer.
Material parse_material(const std::string& text, const std::string& source, const WarningSink& warn = {});
Material read_material_file(const std::filesystem::path& path, const WarningSink& warn = {});
// The same, where a preset may be named ("preset": "tail", or `preset` from sweep-fit --preset;
// not both): its members first, the file's over them; resolved per part (resolve_material).
MaterialRequest parse_material_request(const std::string& text, const std::string& source, const Preset* preset,
                                       const WarningSink& warn = {});
MaterialRequest read_material_request(const std::filesystem::path& path, const Preset* preset,
                                      const WarningSink& warn = {});

// The rig's mesh path is stored relative to the rig file's folder (or absolute).
std::filesystem::path resolve_mesh_path(const std::filesystem::path& rig_path, const Rig& rig);
std::string mesh_path_for_rig(const std::filesystem::path& rig_path, const std::filesystem::path& mesh_path);
void write_rig(const std::filesystem::path& path, const Rig& rig);

}  // namespace sweep::io
