#pragma once
// What each libFuzzer target does with one input, shared by the fuzz executables (fuzz_*.cpp, built
// with SWEEP_FUZZ=ON under clang) and by the replay tests (tests/tools/fuzz_replay_test.cpp), which
// run every committed seed and every input that once crashed in the regular suite.
//
// The contract each target checks: a parser meets any bytes with a result or a sweep::Error (the
// tools turn that into a message and an exit code). Anything else escaping — another exception
// type, an Error of category internal, a crash, a sanitizer report, a hang — is a bug.
#include <string>
#include <string_view>
#include <vector>

namespace sweep::fuzz {

void rig_json(std::string_view data);  // io::parse_rig
void scene(std::string_view data);     // io::read_scene (a file) against a fixed small rig
void binding(std::string_view data);   // io::parse_binding + check_binding, raw and re-summed
// The mesh readers, each + validate_mesh; what they accept must hold the vertices of the file's
// lines, in their order, as an independent line-by-line count reads them.
void off_mesh(std::string_view data);  // assets::parse_off
void obj_mesh(std::string_view data);  // assets::parse_obj
void ply_mesh(std::string_view data);  // assets::parse_ply (the ASCII body check, then assimp)
// sweep-fit's work on any mesh the OFF reader accepts (up to 2,000 vertices): find_parts, then a
// fit from its first part's tip (or vertex 0) with the root found; a fit that returns holds only
// finite numbers and part vertices of the mesh.
void fit_off(std::string_view data);
// What a .gltf/.glb (chosen by its first bytes) meets on the project's own JSON side, before and
// besides assimp: check_gltf_indices (accessors, skins, index ranges), read_gltf_skin (with the
// skinned node's POSITION read independently, so the fuzzer gets past the mesh match) and its
// skinning at each clip's start, middle and end, and read_gltf_body_path for the file's first node
// names. What is accepted must hold: weights that sum to 1 on joints of the skin, one inverse bind
// matrix a joint, finite keys; a body path of finite translations and unit rotations.
void gltf(std::string_view data);
// The material members and the scene members that depend on them: io::parse_material (an accepted
// material's constants are finite and positive, its shear modulus too), then io::read_scene on the
// same bytes against a fixed rig of two material sweeps, "neck" and "tail".
void material(std::string_view data);

struct Target {
  const char* name;  // also the folder name under tests/fuzz/corpus/ and tests/fuzz/regressions/
  void (*run)(std::string_view);
};

// Every target, in a fixed order.
const std::vector<Target>& targets();

}  // namespace sweep::fuzz
