#include "targets.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "bind/binding_file.h"
#include "core/error.h"
#include "io/mesh_io.h"
#include "io/rig_json.h"
#include "sim/scene.h"

namespace sweep::fuzz {
namespace {

// The rig the scene target resolves forces against: one sweep "tube" with named sections.
constexpr const char* kRig = R"({"format": "sweep-rig", "version": 1, "mesh": "tube.obj",
  "sweeps": [{"name": "tube", "radial_samples": 4,
    "sections": [
      {"name": "root", "t": 0, "center": [0, 0, 0], "rotation": [0, 0, 0, 1], "radii": [0.1, 0.1, 0.1, 0.1]},
      {"name": "mid", "t": 0.5, "center": [0, 0, 0.5], "rotation": [0, 0, 0, 1], "radii": [0.1, 0.1, 0.1, 0.1]},
      {"name": "tip", "t": 1, "center": [0, 0, 1], "rotation": [0, 0, 0, 1], "radii": [0.05, 0.05, 0.05, 0.05]}]}]})";

const Rig& fixed_rig() {
  static const Rig rig = io::parse_rig(kRig, "fixed-rig");
  return rig;
}

// A mesh for check_binding: a triangle (the binding's own checks come first anyway).
const Mesh& fixed_mesh() {
  static const Mesh mesh = [] {
    Mesh m;
    m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    m.face_vertices = {0, 1, 2};
    m.face_offsets = {0, 3};
    return m;
  }();
  return mesh;
}

// A parser's answer to bad bytes: any category but internal, which means a bug (core/error.h).
void ignore(const Error& e) {
  if (e.category() == ErrorCategory::internal) {
    throw std::logic_error(std::string("internal error on input: ") + e.what());
  }
}

std::uint64_t fnv1a(std::string_view bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

void put_u64(std::string& s, std::size_t at, std::uint64_t v) {
  for (int b = 0; b < 8; ++b) s[at + b] = static_cast<char>((v >> (8 * b)) & 0xffu);
}

void parse_and_check_binding(std::string_view data) {
  try {
    const bind::Binding b = bind::parse_binding(data, "fuzz.bind");
    bind::check_binding(b, fixed_mesh(), fixed_rig(), "fuzz.bind");
  } catch (const Error& e) {
    ignore(e);
  }
}

}  // namespace

void rig_json(std::string_view data) {
  Rig rig;
  try {
    rig = io::parse_rig(std::string(data), "fuzz.json", [](const std::string&) {});
  } catch (const Error& e) {
    ignore(e);
    return;
  }
  // Whatever was accepted must write, and read back to the same bytes (bindings hash the values):
  // an Error here is a bug, so it is not caught.
  const std::string text = io::format_rig(rig);
  if (io::format_rig(io::parse_rig(text, "fuzz-again.json")) != text) {
    throw std::logic_error("rig_json: a rig read back from its own text writes other bytes");
  }
}

void scene(std::string_view data) {
  // read_scene takes a path (it tells a scene file from a rig file carrying one), so the input is
  // written to a file of this process's own.
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("sweep_fuzz_scene_" + std::to_string(::getpid()) + ".json");
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data.data(), 1, data.size(), f);
    std::fclose(f);
  }
  try {
    const sim::Scene s = sim::read_scene(path, fixed_rig(), [](const std::string&) {});
    (void)s.frame_count();
  } catch (const Error& e) {
    ignore(e);
  }
  std::filesystem::remove(path);
}

void binding(std::string_view data) {
  parse_and_check_binding(data);
  // A checksum guards everything behind it, so random bytes rarely get past it: the same input
  // again with the payload size and the checksum made to agree with the bytes.
  constexpr std::size_t kHeader = 48, kTrailer = 8;
  if (data.size() < kHeader + kTrailer) return;
  std::string fixed(data);
  put_u64(fixed, 40, fixed.size() - kHeader - kTrailer);
  const std::size_t end = fixed.size() - kTrailer;
  put_u64(fixed, end, fnv1a(std::string_view(fixed).substr(0, end)));
  parse_and_check_binding(fixed);
}

void off_mesh(std::string_view data) {
  try {
    const Mesh m = io::parse_off(data, "fuzz.off");
    io::validate_mesh(m, "fuzz.off");
  } catch (const Error& e) {
    ignore(e);
  }
}

void obj_mesh(std::string_view data) {
  try {
    const Mesh m = io::parse_obj(std::string(data), "fuzz.obj");
    io::validate_mesh(m, "fuzz.obj");
  } catch (const Error& e) {
    ignore(e);
  }
}

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {{"rig_json", rig_json},
                                          {"scene", scene},
                                          {"binding", binding},
                                          {"off_mesh", off_mesh},
                                          {"obj_mesh", obj_mesh}};
  return all;
}

}  // namespace sweep::fuzz
