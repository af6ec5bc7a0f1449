// The project's own text readers of mesh_io.h: OFF and OBJ, read from bytes in memory with
// exact numbers (std::from_chars) and every error named by its line. (PLY goes through assimp:
// mesh_import.cpp.)
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "sweep/assets/mesh_io.h"
#include "sweep/assets/mesh_io_detail.h"
#include "sweep/core/error.h"
#include "sweep/core/frame.h"
#include "sweep/core/text.h"

namespace sweep::assets {
namespace {

using detail::bad;
using detail::skip_bom;

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

// One `f` line of an OBJ, until the vertex count is known.
struct ObjFaceLine {
  int line;                  // for messages
  std::size_t first, count;  // the face's corners in the flat list of indices
};

}  // namespace

// ---- OFF: our own strict reader ----
// assimp's OFF loader clamps out-of-range face indices to the last vertex, fills a truncated file
// with zeros and reads single precision, all without an error; so OFF is read here instead.
// Accepted: the OFF, COFF, NOFF, CNOFF and NCOFF headers (colours and normals after the three
// coordinates, and colours after a face's indices, are ignored), counts on the header line or the
// next, '#' comments anywhere. Binary OFF and the 4OFF/nOFF/STOFF variants are unsupported.
Mesh parse_off(std::string_view text, const std::string& source) {
  text = skip_bom(text);
  LineReader lines(text);
  std::vector<std::string_view> tok;
  if (!lines.next(tok)) bad(source, "no OFF header");
  const std::string_view keyword = tok[0];
  static constexpr std::array<std::string_view, 5> kKeywords = {"OFF", "COFF", "NOFF", "CNOFF", "NCOFF"};
  if (std::find(kKeywords.begin(), kKeywords.end(), keyword) == kKeywords.end()) {
    if (keyword.size() >= 3 && keyword.substr(keyword.size() - 3) == "OFF") {
      fail(ErrorCategory::unsupported, source + ": " + at_line(lines.line()) + "OFF variant '" + std::string(keyword) +
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
      bad(source, "unexpected end of file: the header announces " + std::to_string(nv) + " vertices, the file has " +
                      std::to_string(i));
    }
    Vec3 p;
    if (tok.size() < 3) {
      bad(source, at_line(lines.line()) + "vertex " + std::to_string(i) + ": expected 3 coordinates");
    }
    for (int k = 0; k < 3; ++k) {
      if (!parse_real(tok[k], p[k])) {
        bad(source, at_line(lines.line()) + "vertex " + std::to_string(i) + ": '" + std::string(tok[k].substr(0, 40)) +
                        "' is not a number");
      }
    }
    if (!is_finite(p)) {
      bad(source, at_line(lines.line()) + "vertex " + std::to_string(i) + " has a non-finite coordinate " +
                      format_exact_point(p));
    }
    mesh.positions.push_back(p);
  }
  mesh.face_offsets.reserve(std::min<std::uint64_t>(nf, text.size() / 6) + 1);
  for (std::uint64_t f = 0; f < nf; ++f) {
    if (!lines.next(tok)) {
      bad(source, "unexpected end of file: the header announces " + std::to_string(nf) + " faces, the file has " +
                      std::to_string(f));
    }
    std::uint64_t n = 0;
    if (!parse_index(tok[0], n)) {
      bad(source, at_line(lines.line()) + "face " + std::to_string(f) + ": expected its vertex count, found '" +
                      std::string(tok[0].substr(0, 40)) + "'");
    }
    if (n < 3) {
      bad(source, at_line(lines.line()) + "face " + std::to_string(f) + " has " + std::to_string(n) +
                      " vertices (a face needs at least 3)");
    }
    if (n > tok.size() - 1) {  // not tok.size() < n + 1: n may be 2^64 - 1
      bad(source, at_line(lines.line()) + "face " + std::to_string(f) + ": expected " + std::to_string(n) +
                      " vertex indices, found " + std::to_string(tok.size() - 1));
    }
    for (std::uint64_t k = 1; k <= n; ++k) {
      std::uint64_t v = 0;
      if (!parse_index(tok[k], v)) {
        bad(source, at_line(lines.line()) + "face " + std::to_string(f) + ": '" + std::string(tok[k].substr(0, 40)) +
                        "' is not a vertex index");
      }
      if (v >= nv) {
        bad(source, at_line(lines.line()) + "face " + std::to_string(f) + " uses vertex " + std::to_string(v) +
                        ", out of range (the mesh has " + std::to_string(nv) + " vertices)");
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
Mesh parse_obj(const std::string& file_text, const std::string& source) {
  const std::string_view text = skip_bom(file_text);
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
        bad(source, at_line(line_no) + "vertex " + std::to_string(index) + ": expected 3 coordinates");
      }
      Vec3 p;
      for (int k = 0; k < 3; ++k) {
        if (!parse_real(tok[k + 1], p[k])) {
          bad(source, at_line(line_no) + "vertex " + std::to_string(index) + ": '" +
                          std::string(tok[k + 1].substr(0, 40)) + "' is not a number");
        }
      }
      if (!is_finite(p)) {
        bad(source, at_line(line_no) + "vertex " + std::to_string(index) + " has a non-finite coordinate " +
                        format_exact_point(p));
      }
      mesh.positions.push_back(p);
    } else if (tok[0] == "f") {
      const std::size_t face = faces.size();
      if (tok.size() < 4) {
        bad(source, at_line(line_no) + "face " + std::to_string(face) + " has " + std::to_string(tok.size() - 1) +
                        " vertices (a face needs at least 3)");
      }
      faces.push_back({line_no, corners.size(), tok.size() - 1});
      for (std::size_t k = 1; k < tok.size(); ++k) {
        const std::string_view v = tok[k].substr(0, tok[k].find('/'));
        long long index = 0;
        const auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), index);
        if (ec != std::errc() || ptr != v.data() + v.size() || index == 0) {
          bad(source, at_line(line_no) + "face " + std::to_string(face) + ": '" + std::string(tok[k].substr(0, 40)) +
                          "' is not a vertex index (1-based, or negative for relative)");
        }
        // Relative: -1 is the last vertex read so far.
        corners.push_back(index > 0 ? index - 1 : static_cast<long long>(mesh.positions.size()) + index);
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
        bad(source, at_line(faces[f].line) + "face " + std::to_string(f) + " uses vertex " + std::to_string(v + 1) +
                        " (1-based, as in the file), out of range (the mesh has " + std::to_string(nv) + " vertices)");
      }
      mesh.face_vertices.push_back(static_cast<std::uint32_t>(v));
    }
    if (mesh.face_vertices.size() >= UINT32_MAX) bad(source, "too many face corners for this reader");
    mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_vertices.size()));
  }
  return mesh;
}

}  // namespace sweep::assets
