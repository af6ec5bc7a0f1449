#include "assets/mesh_io.h"

#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <assimp/Importer.hpp>
#include <bit>
#include <cfenv>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string_view>
#include <system_error>
#include <unordered_map>

#include "assets/mesh_checks.h"
#include "core/error.h"
#include "core/hash.h"
#include "io/atomic_file.h"

namespace sweep::io {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void bad(const std::string& source, const std::string& what) {
  fail(ErrorCategory::bad_input, source + ": " + what);
}

std::string lower_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  if (!ext.empty() && ext.front() == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// One line of text for an error message: libraries report with embedded newlines.
std::string one_line(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      out += c;
    }
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// Shortest round-trippable text for a double, independent of the locale.
void append_number(std::string& out, double value) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
  if (ec != std::errc()) fail(ErrorCategory::internal, "cannot format a number");
  out.append(buf, end);
}

void append_number(std::string& out, std::uint64_t value) {
  char buf[24];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
  if (ec != std::errc()) fail(ErrorCategory::internal, "cannot format a number");
  out.append(buf, end);
}

// Eigen's allFinite() computes x - x, which raises FE_INVALID for an infinity; test element-wise.
bool finite(const Vec3& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

std::string format_position(const Vec3& p) {
  std::string s = "(";
  for (int k = 0; k < 3; ++k) {
    if (k) s += ", ";
    append_number(s, p[k]);
  }
  return s + ")";
}

// Missing, not a regular file, unreadable or empty: each gets its own message.
void check_input_file(const fs::path& path) {
  const std::string source = path.string();
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) bad(source, "no such file");
  if (fs::is_directory(st)) bad(source, "is a directory, not a file");
  // A FIFO or a device would block the reader forever or never end: only regular files are read.
  if (!fs::is_regular_file(st)) bad(source, "is not a regular file (a FIFO, a device or a socket)");
  std::ifstream in(path, std::ios::binary);
  if (!in) bad(source, std::string("cannot open: ") + std::strerror(errno));
  if (in.peek() == std::ifstream::traits_type::eof()) bad(source, "empty file");
}

// Third-party parsers (tinyobjloader's float conversion, assimp's number parsing) raise overflow
// and invalid flags on legitimate input such as 1.7976931348623157e308 read into a float; what
// they produce is either discarded or checked afterwards (validate_mesh). This holds such
// exceptions for the call: traps a caller enabled (tests do) are paused, and the flags raised
// inside are dropped, as the C standard's feholdexcept/fesetenv pair is meant for.
class HoldFpExceptions {
 public:
  HoldFpExceptions() { std::feholdexcept(&saved_); }
  ~HoldFpExceptions() { std::fesetenv(&saved_); }
  HoldFpExceptions(const HoldFpExceptions&) = delete;
  HoldFpExceptions& operator=(const HoldFpExceptions&) = delete;

 private:
  std::fenv_t saved_;
};

// ---- Text helpers shared by the OFF and OBJ readers ----

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

// Splits on blanks. Returns the tokens of one line (comments already removed).
std::vector<std::string_view> split_tokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

// A real number in C syntax (a leading '+' allowed); "nan" and "inf" parse, as non-finite values,
// so that the caller can name the vertex. Returns false when the token is not a number at all.
bool parse_real(std::string_view token, double& value) {
  // from_chars takes no '+': drop one, unless another sign follows ("+-5" is not a number).
  if (token.size() > 1 && token.front() == '+') {
    if (token[1] == '-' || token[1] == '+') return false;
    token.remove_prefix(1);
  }
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ec == std::errc::result_out_of_range) {
    // from_chars leaves value untouched on overflow; report it as the non-finite value it is.
    value = (token.front() == '-') ? -HUGE_VAL : HUGE_VAL;
    return ptr == end;
  }
  return ec == std::errc() && ptr == end;
}

bool parse_index(std::string_view token, std::uint64_t& value) {
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end;
}

// Reads lines one at a time, dropping '#' comments and blank lines, counting line numbers.
class LineReader {
 public:
  explicit LineReader(std::string_view text) : text_(text) {}

  // The next non-blank line's tokens; false at end of text.
  bool next(std::vector<std::string_view>& tokens) {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view line = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_;
      if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) {
        line = line.substr(0, hash);
      }
      tokens = split_tokens(line);
      if (!tokens.empty()) return true;
    }
    return false;
  }
  int line() const { return line_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  int line_ = 0;
};

std::string at_line(int line) {
  return "line " + std::to_string(line) + ": ";
}

// A UTF-8 byte order mark is an encoding marker, not content: editors on Windows put one before
// the first line, and a reader that took it for part of the first token would shift the data.
std::string_view skip_bom(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return text;
}

// ---- OFF: our own strict reader ----
// assimp's OFF loader clamps out-of-range face indices to the last vertex, fills a truncated file
// with zeros and reads single precision, all without an error; so OFF is read here instead.
// Accepted: the OFF, COFF, NOFF, CNOFF and NCOFF headers (colours and normals after the three
// coordinates, and colours after a face's indices, are ignored), counts on the header line or the
// next, '#' comments anywhere. Binary OFF and the 4OFF/nOFF/STOFF variants are unsupported.
Mesh read_off(const std::string& source, std::string_view text) {
  text = skip_bom(text);
  LineReader lines(text);
  std::vector<std::string_view> tok;
  if (!lines.next(tok)) bad(source, "no OFF header");
  const std::string_view keyword = tok[0];
  static constexpr std::array<std::string_view, 5> kKeywords = {"OFF", "COFF", "NOFF", "CNOFF",
                                                                "NCOFF"};
  if (std::find(kKeywords.begin(), kKeywords.end(), keyword) == kKeywords.end()) {
    if (keyword.size() >= 3 && keyword.substr(keyword.size() - 3) == "OFF") {
      fail(ErrorCategory::unsupported,
           source + ": " + at_line(lines.line()) + "OFF variant '" + std::string(keyword) +
               "' is not supported (only OFF, COFF, NOFF, CNOFF, NCOFF)");
    }
    bad(source, at_line(lines.line()) + "not an OFF file: expected the keyword OFF, found '" +
                    std::string(keyword.substr(0, 40)) + "'");
  }
  if (tok.size() > 1 && tok[1] == "BINARY") {
    fail(ErrorCategory::unsupported, source + ": binary OFF is not supported");
  }
  tok.erase(tok.begin());
  if (tok.empty() && !lines.next(tok)) bad(source, "missing the vertex and face counts");
  std::uint64_t counts[2] = {0, 0};
  if (tok.size() < 2 || !parse_index(tok[0], counts[0]) || !parse_index(tok[1], counts[1])) {
    bad(source, at_line(lines.line()) + "expected the vertex and face counts");
  }
  const std::uint64_t nv = counts[0], nf = counts[1];
  if (nv >= UINT32_MAX || nf >= UINT32_MAX) {
    bad(source, at_line(lines.line()) + "counts too large for this reader");
  }

  Mesh mesh;
  // Reserve no more than the text could hold, so a lying header cannot exhaust memory.
  mesh.positions.reserve(std::min<std::uint64_t>(nv, text.size() / 6));
  for (std::uint64_t i = 0; i < nv; ++i) {
    if (!lines.next(tok)) {
      bad(source, "unexpected end of file: the header announces " + std::to_string(nv) +
                      " vertices, the file has " + std::to_string(i));
    }
    Vec3 p;
    if (tok.size() < 3) {
      bad(source,
          at_line(lines.line()) + "vertex " + std::to_string(i) + ": expected 3 coordinates");
    }
    for (int k = 0; k < 3; ++k) {
      if (!parse_real(tok[k], p[k])) {
        bad(source, at_line(lines.line()) + "vertex " + std::to_string(i) + ": '" +
                        std::string(tok[k].substr(0, 40)) + "' is not a number");
      }
    }
    if (!finite(p)) {
      bad(source, at_line(lines.line()) + "vertex " + std::to_string(i) +
                      " has a non-finite coordinate " + format_position(p));
    }
    mesh.positions.push_back(p);
  }
  mesh.face_offsets.reserve(std::min<std::uint64_t>(nf, text.size() / 6) + 1);
  for (std::uint64_t f = 0; f < nf; ++f) {
    if (!lines.next(tok)) {
      bad(source, "unexpected end of file: the header announces " + std::to_string(nf) +
                      " faces, the file has " + std::to_string(f));
    }
    std::uint64_t n = 0;
    if (!parse_index(tok[0], n)) {
      bad(source, at_line(lines.line()) + "face " + std::to_string(f) +
                      ": expected its vertex count, found '" + std::string(tok[0].substr(0, 40)) +
                      "'");
    }
    if (n < 3) {
      bad(source, at_line(lines.line()) + "face " + std::to_string(f) + " has " +
                      std::to_string(n) + " vertices (a face needs at least 3)");
    }
    if (n > tok.size() - 1) {  // not tok.size() < n + 1: n may be 2^64 - 1
      bad(source, at_line(lines.line()) + "face " + std::to_string(f) + ": expected " +
                      std::to_string(n) + " vertex indices, found " +
                      std::to_string(tok.size() - 1));
    }
    for (std::uint64_t k = 1; k <= n; ++k) {
      std::uint64_t v = 0;
      if (!parse_index(tok[k], v)) {
        bad(source, at_line(lines.line()) + "face " + std::to_string(f) + ": '" +
                        std::string(tok[k].substr(0, 40)) + "' is not a vertex index");
      }
      if (v >= nv) {
        bad(source, at_line(lines.line()) + "face " + std::to_string(f) + " uses vertex " +
                        std::to_string(v) + ", out of range (the mesh has " + std::to_string(nv) +
                        " vertices)");
      }
      mesh.face_vertices.push_back(static_cast<std::uint32_t>(v));
    }
    mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_vertices.size()));
  }
  return mesh;
}

// ---- OBJ: our own reader of the `v` and `f` lines ----
// tinyobjloader (used before) read indices into a 32-bit int, so "f 1 2 4294967298" wrapped to a
// valid vertex; it dropped faces of fewer than 3 vertices without a word, rounded coordinates
// incorrectly and turned "nan" into 0. The two statements that matter for a mesh are simple, so
// they are read here: `v x y z [w]` (exact, std::from_chars) and `f i[/vt[/vn]] ...` (64-bit
// indices, negative ones relative to the vertices read so far). Everything else (vt, vn, g, o, s,
// l, p, usemtl, mtllib, ...) is ignored. Lines end at "\n", "\r\n" or a lone "\r".
struct ObjFaceLine {
  int line;                  // for messages
  std::size_t first, count;  // the face's corners in the flat list of indices
};

Mesh read_obj(const std::string& source, std::string_view text) {
  text = skip_bom(text);
  Mesh mesh;
  std::vector<long long> corners;  // 0-based; checked against the vertex count at the end
  std::vector<ObjFaceLine> faces;
  std::size_t pos = 0;
  int line_no = 0;
  while (pos < text.size()) {
    std::size_t end = text.find_first_of("\r\n", pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + (end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n' ? 2 : 1);
    ++line_no;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) {
      line = line.substr(0, hash);
    }
    const auto tok = split_tokens(line);
    if (tok.empty()) continue;
    if (tok[0] == "v") {
      const std::size_t index = mesh.positions.size();
      if (tok.size() < 4) {
        bad(source,
            at_line(line_no) + "vertex " + std::to_string(index) + ": expected 3 coordinates");
      }
      Vec3 p;
      for (int k = 0; k < 3; ++k) {
        if (!parse_real(tok[k + 1], p[k])) {
          bad(source, at_line(line_no) + "vertex " + std::to_string(index) + ": '" +
                          std::string(tok[k + 1].substr(0, 40)) + "' is not a number");
        }
      }
      if (!finite(p)) {
        bad(source, at_line(line_no) + "vertex " + std::to_string(index) +
                        " has a non-finite coordinate " + format_position(p));
      }
      mesh.positions.push_back(p);
    } else if (tok[0] == "f") {
      const std::size_t face = faces.size();
      if (tok.size() < 4) {
        bad(source, at_line(line_no) + "face " + std::to_string(face) + " has " +
                        std::to_string(tok.size() - 1) + " vertices (a face needs at least 3)");
      }
      faces.push_back({line_no, corners.size(), tok.size() - 1});
      for (std::size_t k = 1; k < tok.size(); ++k) {
        const std::string_view v = tok[k].substr(0, tok[k].find('/'));
        long long index = 0;
        const auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), index);
        if (ec != std::errc() || ptr != v.data() + v.size() || index == 0) {
          bad(source, at_line(line_no) + "face " + std::to_string(face) + ": '" +
                          std::string(tok[k].substr(0, 40)) +
                          "' is not a vertex index (1-based, or negative for relative)");
        }
        // Relative: -1 is the last vertex read so far.
        corners.push_back(index > 0 ? index - 1
                                    : static_cast<long long>(mesh.positions.size()) + index);
      }
    }
  }
  const auto nv = static_cast<long long>(mesh.positions.size());
  if (nv >= static_cast<long long>(UINT32_MAX)) bad(source, "too many vertices for this reader");
  mesh.face_offsets.reserve(faces.size() + 1);
  mesh.face_vertices.reserve(corners.size());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (std::size_t k = 0; k < faces[f].count; ++k) {
      const long long v = corners[faces[f].first + k];
      if (v < 0 || v >= nv) {
        bad(source, at_line(faces[f].line) + "face " + std::to_string(f) + " uses vertex " +
                        std::to_string(v + 1) +
                        " (1-based, as in the file), out of range (the mesh has " +
                        std::to_string(nv) + " vertices)");
      }
      mesh.face_vertices.push_back(static_cast<std::uint32_t>(v));
    }
    if (mesh.face_vertices.size() >= UINT32_MAX) bad(source, "too many face corners for this reader");
    mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_vertices.size()));
  }
  return mesh;
}

// ---- assimp: PLY, glTF/glb (kept as stored) and everything else (welded) ----

using Transform = Eigen::Matrix4d;

Transform to_transform(const aiMatrix4x4& m) {
  Transform t;
  t << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3,
      m.d4;
  return t;
}

// World transform of each mesh: that of the first node referring to it in depth-first order
// (identity when no node does). Instances (one mesh under several nodes) are not duplicated.
void collect_transforms(const aiNode* node, const Transform& parent,
                        std::vector<Transform>& transforms, std::vector<bool>& seen) {
  const Transform world = parent * to_transform(node->mTransformation);
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    const unsigned m = node->mMeshes[i];
    if (m < transforms.size() && !seen[m]) {
      transforms[m] = world;
      seen[m] = true;
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) {
    collect_transforms(node->mChildren[c], world, transforms, seen);
  }
}

Vec3 apply(const Transform& t, const aiVector3D& v) {
  if (t.isIdentity(0.0)) return Vec3(v.x, v.y, v.z);  // exact: no arithmetic at all
  const Eigen::Vector4d h = t * Eigen::Vector4d(v.x, v.y, v.z, 1.0);
  return h.head<3>();
}

// Key for welding by exact position: the bit patterns, with -0 and +0 counted as one.
struct PositionKey {
  std::array<std::uint64_t, 3> bits;
  bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
  std::size_t operator()(const PositionKey& k) const {
    std::uint64_t h = kFnvOffset;  // FNV-1a's constants, a 64-bit word at a time: a table key, not a file's hash
    for (std::uint64_t b : k.bits) h = (h ^ b) * kFnvPrime;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
PositionKey key_of(const Vec3& p) {
  PositionKey key;
  for (int k = 0; k < 3; ++k) key.bits[k] = std::bit_cast<std::uint64_t>(p[k] == 0.0 ? 0.0 : p[k]);
  return key;
}

// `bytes` given: the file's content already in memory (PLY, read from there so that a byte order
// mark can be skipped and the body checked first), with `hint` its extension; else the file
// `source` is read by assimp itself (glTF may refer to other files beside it).
Mesh read_with_assimp(const std::string& source, bool weld, std::string_view bytes = {},
                      const char* hint = "") {
  Assimp::Importer importer;
  // No post-processing: it keeps the stored vertices, their order and count, and the polygons.
  const aiScene* scene = nullptr;
  {
    const HoldFpExceptions hold;
    scene = bytes.empty() ? importer.ReadFile(source, 0)
                          : importer.ReadFileFromMemory(bytes.data(), bytes.size(), 0, hint);
  }
  if (scene == nullptr) bad(source, "cannot parse: " + one_line(importer.GetErrorString()));
  if (scene->mNumMeshes == 0 || scene->mMeshes == nullptr) bad(source, "no vertices");

  std::vector<Transform> transforms(scene->mNumMeshes, Transform::Identity());
  std::vector<bool> seen(scene->mNumMeshes, false);
  if (scene->mRootNode != nullptr) {
    collect_transforms(scene->mRootNode, Transform::Identity(), transforms, seen);
  }

  Mesh mesh;
  std::size_t face = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    const Transform& t = transforms[m];
    const std::size_t base = mesh.positions.size();
    if (!weld) {
      for (unsigned i = 0; i < am->mNumVertices; ++i)
        mesh.positions.push_back(apply(t, am->mVertices[i]));
    }
    std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> welded;
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& af = am->mFaces[f];
      if (af.mNumIndices < 3) continue;  // points and lines are not surface
      for (unsigned k = 0; k < af.mNumIndices; ++k) {
        const unsigned v = af.mIndices[k];
        if (v >= am->mNumVertices) {
          bad(source, "face " + std::to_string(face) + " uses vertex " + std::to_string(v) +
                          " of mesh " + std::to_string(m) + ", out of range (that mesh has " +
                          std::to_string(am->mNumVertices) + " vertices)");
        }
        if (!weld) {
          mesh.face_vertices.push_back(static_cast<std::uint32_t>(base + v));
          continue;
        }
        const Vec3 p = apply(t, am->mVertices[v]);
        const auto [it, inserted] =
            welded.try_emplace(key_of(p), static_cast<std::uint32_t>(mesh.positions.size()));
        if (inserted) mesh.positions.push_back(p);
        mesh.face_vertices.push_back(it->second);
      }
      mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_vertices.size()));
      ++face;
    }
  }
  return mesh;
}

}  // namespace

Mesh parse_off(std::string_view text, const std::string& source) {
  return read_off(source, text);
}
Mesh parse_obj(const std::string& text, const std::string& source) {
  return read_obj(source, text);
}
Mesh parse_ply(std::string_view bytes, const std::string& source) {
  bytes = skip_bom(bytes);
  if (bytes.empty()) bad(source, "empty file");
  detail::check_ascii_ply(bytes, source);
  return read_with_assimp(source, /*weld=*/false, bytes, "ply");
}

Mesh read_mesh(const fs::path& path) {
  const std::string source = path.string();
  check_input_file(path);
  const std::string ext = lower_extension(path);
  Mesh mesh;
  if (ext == "off") {
    mesh = read_off(source, read_file(path));
  } else if (ext == "obj") {
    mesh = read_obj(source, read_file(path));
  } else if (ext == "ply") {
    mesh = parse_ply(read_file(path), source);
  } else if (ext == "gltf" || ext == "glb") {
    detail::check_gltf_indices(path);
    mesh = read_with_assimp(source, /*weld=*/false);
  } else {
    if (ext.empty()) {
      fail(ErrorCategory::unsupported, source + ": no file extension, so the format is unknown");
    }
    const Assimp::Importer probe;
    if (!probe.IsExtensionSupported("." + ext)) {
      fail(ErrorCategory::unsupported, source + ": unsupported mesh format '." + ext + "'");
    }
    mesh = read_with_assimp(source, /*weld=*/true);
  }
  validate_mesh(mesh, source);
  return mesh;
}

void validate_mesh(const Mesh& mesh, const std::string& source) {
  if (const std::string why = check_mesh(mesh); !why.empty()) bad(source, why);
}

namespace {

// Writers refuse what no reader should ever see: a non-finite coordinate or a broken face table.
void check_writable(const fs::path& path, const Mesh& mesh) {
  const auto& off = mesh.face_offsets;
  if (off.empty() || off.front() != 0 || off.back() != mesh.face_vertices.size()) {
    fail(ErrorCategory::internal, path.string() + ": refusing to write a malformed face table");
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!finite(mesh.positions[i])) {
      fail(ErrorCategory::output, path.string() + ": refusing to write vertex " +
                                      std::to_string(i) + ": non-finite coordinate " +
                                      format_position(mesh.positions[i]));
    }
  }
  for (std::uint32_t v : mesh.face_vertices) {
    if (v >= mesh.positions.size()) {
      fail(ErrorCategory::internal,
           path.string() + ": refusing to write a face index out of range");
    }
  }
}

void append_vertex_line(std::string& out, const char* prefix, const Vec3& p) {
  out += prefix;
  for (int k = 0; k < 3; ++k) {
    if (k) out += ' ';
    append_number(out, p[k]);
  }
  out += '\n';
}

}  // namespace

std::string obj_bytes(const Mesh& mesh) {
  std::string out = "# sweep mesh 1: " + std::to_string(mesh.vertex_count()) + " vertices, " +
                    std::to_string(mesh.face_count()) + " faces\n";
  out.reserve(out.size() + mesh.vertex_count() * 64 + mesh.face_vertices.size() * 8);
  for (const Vec3& p : mesh.positions) append_vertex_line(out, "v ", p);
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    out += 'f';
    for (std::uint32_t k = mesh.face_offsets[f]; k < mesh.face_offsets[f + 1]; ++k) {
      out += ' ';
      append_number(out, std::uint64_t{mesh.face_vertices[k]} + 1);
    }
    out += '\n';
  }
  return out;
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

std::string off_bytes(const Mesh& mesh) {
  std::string out = "OFF\n# sweep mesh 1\n";
  append_number(out, std::uint64_t{mesh.vertex_count()});
  out += ' ';
  append_number(out, std::uint64_t{mesh.face_count()});
  out += " 0\n";
  for (const Vec3& p : mesh.positions) append_vertex_line(out, "", p);
  append_counted_faces(out, mesh);
  return out;
}

std::string ply_bytes(const Mesh& mesh) {
  std::uint32_t widest = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    widest = std::max(widest, mesh.face_offsets[f + 1] - mesh.face_offsets[f]);
  }
  std::string out = "ply\nformat ascii 1.0\ncomment sweep mesh 1\nelement vertex " +
                    std::to_string(mesh.vertex_count()) +
                    "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
                    std::to_string(mesh.face_count()) + "\nproperty list " +
                    (widest <= 255 ? "uchar" : "uint") + " uint vertex_indices\nend_header\n";
  for (const Vec3& p : mesh.positions) append_vertex_line(out, "", p);
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
  fail(ErrorCategory::unsupported, path.string() + ": cannot write mesh format '" +
                                       path.extension().string() + "' (write .obj, .off or .ply)");
}

}  // namespace sweep::io
