#include "targets.h"

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "assets/mesh_io.h"
#include "core/error.h"
#include "core/hash.h"
#include "fit/discover.h"
#include "fit/fit.h"
#include "io/binding_file.h"
#include "io/rig_json.h"
#include "io/scene_json.h"
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

namespace {

// ---- An independent reading of the vertex lines, for the mesh targets ----
// Whatever a reader accepts must hold exactly the vertices the file's lines hold, in their order:
// counted here line by line with strtod, a way unrelated to the readers' own (a BOM
// once made the OBJ reader skip the first `v`, a lying PLY header had face lines read as vertices).

std::string_view without_bom(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return text;
}

// Lines ending at "\n", "\r\n" or a lone "\r" (what the readers accept), '#' comments removed.
std::vector<std::vector<std::string>> lines_of(std::string_view text, bool lone_cr_ends_line) {
  std::vector<std::vector<std::string>> lines;
  std::vector<std::string> words;
  std::string word;
  bool comment = false;
  auto end_word = [&] {
    if (!word.empty()) words.push_back(word);
    word.clear();
  };
  for (std::size_t i = 0; i <= text.size(); ++i) {
    const char c = i < text.size() ? text[i] : '\n';
    if (c == '\n' || (c == '\r' && lone_cr_ends_line)) {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      end_word();
      lines.push_back(std::move(words));
      words.clear();
      comment = false;
    } else if (comment || c == '#') {
      comment = true;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      end_word();
    } else {
      word += c;
    }
  }
  return lines;
}

Vec3 strtod3(const std::vector<std::string>& w, std::size_t first) {
  Vec3 p;
  for (int k = 0; k < 3; ++k) p[k] = std::strtod(w.at(first + k).c_str(), nullptr);
  return p;
}

void expect_vertices(const Mesh& m, const std::vector<Vec3>& expected, const char* target) {
  if (m.positions.size() != expected.size()) {
    throw std::logic_error(std::string(target) + ": the reader holds " +
                           std::to_string(m.positions.size()) + " vertices, the file's lines " +
                           std::to_string(expected.size()));
  }
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (!(m.positions[i] == expected[i])) {
      throw std::logic_error(std::string(target) + ": vertex " + std::to_string(i) +
                             " differs from its line");
    }
  }
}

}  // namespace

void off_mesh(std::string_view data) {
  Mesh m;
  try {
    m = io::parse_off(data, "fuzz.off");
    io::validate_mesh(m, "fuzz.off");
  } catch (const Error& e) {
    ignore(e);
    return;
  }
  // Accepted: the header word, the counts (on its line or the next), then one vertex a line.
  std::vector<std::vector<std::string>> lines;
  for (auto& l : lines_of(without_bom(data), false)) {
    if (!l.empty()) lines.push_back(std::move(l));
  }
  std::size_t at = 0;
  std::vector<std::string> counts(lines.at(0).begin() + 1, lines.at(0).end());
  if (counts.empty()) counts = lines.at(++at);
  const std::size_t nv = std::stoull(counts.at(0));
  std::vector<Vec3> expected;
  for (std::size_t i = 0; i < nv; ++i) expected.push_back(strtod3(lines.at(++at), 0));
  expect_vertices(m, expected, "off_mesh");
}

void obj_mesh(std::string_view data) {
  Mesh m;
  try {
    m = io::parse_obj(std::string(data), "fuzz.obj");
    io::validate_mesh(m, "fuzz.obj");
  } catch (const Error& e) {
    ignore(e);
    return;
  }
  std::vector<Vec3> expected;
  for (const auto& l : lines_of(without_bom(data), true)) {
    if (!l.empty() && l[0] == "v") expected.push_back(strtod3(l, 1));
  }
  expect_vertices(m, expected, "obj_mesh");
}

void ply_mesh(std::string_view data) {
  Mesh m;
  try {
    m = io::parse_ply(data, "fuzz.ply");
    io::validate_mesh(m, "fuzz.ply");
  } catch (const Error& e) {
    ignore(e);
    return;
  }
  // ASCII with "vertex" first and x y z its first properties: the vertex lines follow the header
  // one a line, as single-precision values (assimp stores floats).
  const auto lines = lines_of(without_bom(data), false);
  std::size_t at = 0;
  std::vector<std::string> props;
  bool ascii = false, vertex_first = false;
  std::size_t nv = 0, elements = 0;
  for (; at < lines.size(); ++at) {
    const auto& l = lines[at];
    if (l.empty()) continue;
    if (l[0] == "end_header") break;
    if (l[0] == "format" && l.size() > 1) ascii = l[1] == "ascii";
    if (l[0] == "element" && l.size() > 2 && elements++ == 0 && l[1] == "vertex") {
      vertex_first = true;
      nv = std::stoull(l[2]);
    }
    if (l[0] == "property" && elements == 1 && l.size() > 2) props.push_back(l.back());
  }
  if (!ascii || !vertex_first || props.size() < 3 || props[0] != "x" || props[1] != "y" ||
      props[2] != "z") {
    return;
  }
  std::vector<Vec3> expected;
  while (expected.size() < nv) {
    const auto& l = lines.at(++at);
    if (!l.empty()) expected.push_back(strtod3(l, 0).cast<float>().cast<double>());
  }
  expect_vertices(m, expected, "ply_mesh");
}

void fit_off(std::string_view data) {
  Mesh m;
  try {
    m = io::parse_off(data, "fuzz.off");
    io::validate_mesh(m, "fuzz.off");
  } catch (const Error& e) {
    ignore(e);
    return;
  }
  if (m.vertex_count() > 2000) return;  // keeps each run short; size is not what is tested
  try {
    const fit::SweepFitter fitter(m);
    fit::DiscoverOptions discover;
    discover.samples = 4;
    const std::vector<fit::FoundPart> parts = fit::find_parts(m, fitter.topology(), discover);
    fit::FitOptions o;
    o.sections = 8;
    o.radial = 8;
    o.tip_vertex = parts.empty() ? 0 : static_cast<std::int64_t>(parts.front().tip_vertex);
    const fit::FitResult r = fitter.fit(o);
    const SweepShape& shape = r.sweep.rest;
    bool finite = std::isfinite(r.mean_radius) && std::isfinite(r.length);
    for (const double x : shape.radii) finite = finite && std::isfinite(x) && x > 0;
    for (std::size_t i = 0; i < shape.frames.size(); ++i) {
      finite = finite && shape.frames[i].center.allFinite() && std::isfinite(shape.t[i]);
    }
    if (!finite) throw std::logic_error("fit_off: a fit returned a non-finite or non-positive number");
    for (const std::uint32_t v : r.part_vertices) {
      if (v >= m.vertex_count()) throw std::logic_error("fit_off: a part vertex outside the mesh");
    }
  } catch (const Error& e) {
    ignore(e);
  }
}

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {{"rig_json", rig_json},
                                          {"scene", scene},
                                          {"binding", binding},
                                          {"off_mesh", off_mesh},
                                          {"obj_mesh", obj_mesh},
                                          {"ply_mesh", ply_mesh},
                                          {"fit_off", fit_off}};
  return all;
}

}  // namespace sweep::fuzz
