#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "sweep/assets/mesh_checks.h"
#include "sweep/core/error.h"

namespace sweep::assets::detail {
namespace {

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<bool> is_list;             // per property, in order
  std::vector<std::string> value_types;  // per property: its type (a list's: its items' type)
  std::vector<std::string> scalar_names;
  std::vector<std::string> list_names;
  std::uint64_t line = 0;  // of its "element" line
};

[[noreturn]] void bad_ply(const std::string& source, std::uint64_t line, const std::string& what) {
  fail(ErrorCategory::bad_input, source + ": line " + std::to_string(line) + ": " + what);
}

// Splits one line into blank-separated tokens ("\r" counts as a blank).
std::vector<std::string_view> tokens_of(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (i < line.size()) {
    while (i < line.size() && blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !blank(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// Element and property names as real files use them. assimp takes a name such as "4444vertex"
// partly for a count and allocates gigabytes (ply_mesh fuzz find, kept).
bool plain_name(std::string_view t) {
  const auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
  if (t.empty() || !letter(t[0])) return false;
  return std::all_of(t.begin(), t.end(),
                     [&](char c) { return letter(c) || (c >= '0' && c <= '9') || c == '-' || c == '.'; });
}

bool whole_number(std::string_view t, std::uint64_t& v) {
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  return ec == std::errc() && p == t.data() + t.size();
}

// A value of an ASCII body: a number (assimp leaks on other tokens, found by the fuzz target)
// within the range of a 32-bit float, which is what assimp stores: beyond it, assimp's own
// parsing returns some finite wrong value rather than failing (a 43-digit coordinate, found by
// the ply_mesh fuzz target's vertex check).
// assimp reads a number's integer digits into 64 bits and its exponent's into an int, and gets
// longer ones wrong without a word ("020000000000000000000000": a ply_mesh fuzz find, kept).
bool digits_assimp_reads(std::string_view t) {
  std::size_t i = (!t.empty() && (t[0] == '+' || t[0] == '-')) ? 1 : 0;
  const auto run = [&] {
    const std::size_t start = i;
    while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i;
    return i - start;
  };
  if (run() > 18) return false;
  if (i < t.size() && t[i] == '.') {
    ++i;
    run();
  }
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    ++i;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    if (run() > 4) return false;
  }
  return true;
}

bool is_number(std::string_view t) {
  if (!digits_assimp_reads(t)) return false;
  if (t.size() > 1 && t[0] == '+') t.remove_prefix(1);
  double v = 0;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  // (nan and inf pass: the mesh check names the vertex that holds them)
  return ec == std::errc() && p == t.data() + t.size() &&
         (!std::isfinite(v) || std::abs(v) <= static_cast<double>(std::numeric_limits<float>::max()));
}

// The PLY scalar types. assimp reads a property of another type as nothing at all, so the values
// of a line shift (found by the ply_mesh fuzz target: "property doub\x17e y").
bool known_type(std::string_view t) {
  for (const char* k : {"char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint8", "int16",
                        "uint16", "int32", "uint32", "float32", "float64"}) {
    if (t == k) return true;
  }
  return false;
}

// The range of an integer type; false for float and double.
bool integer_range(std::string_view type, std::int64_t& lo, std::int64_t& hi) {
  struct Range {
    const char* names[2];
    std::int64_t lo, hi;
  };
  static constexpr Range ranges[] = {{{"char", "int8"}, -128, 127},
                                     {{"uchar", "uint8"}, 0, 255},
                                     {{"short", "int16"}, -32768, 32767},
                                     {{"ushort", "uint16"}, 0, 65535},
                                     {{"int", "int32"}, -2147483648LL, 2147483647LL},
                                     {{"uint", "uint32"}, 0, 4294967295LL}};
  for (const Range& r : ranges) {
    if (type == r.names[0] || type == r.names[1]) {
      lo = r.lo;
      hi = r.hi;
      return true;
    }
  }
  return false;
}

// A value of an integer property must be a whole number in its type's range: assimp reads
// "0.5" as 0 and wraps 300 in a uchar (found by the ply_mesh fuzz target's vertex check).
bool fits_integer_type(std::string_view t, std::string_view type) {
  std::int64_t lo = 0, hi = 0;
  if (!integer_range(type, lo, hi)) return true;
  if (t.size() > 1 && t[0] == '+') t.remove_prefix(1);
  std::int64_t v = 0;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  return ec == std::errc() && p == t.data() + t.size() && v >= lo && v <= hi;
}

}  // namespace

void check_ascii_ply(std::string_view text, const std::string& source) {
  std::size_t pos = 0;
  std::uint64_t line_no = 0;
  auto next_line = [&](std::string_view& line) {
    if (pos >= text.size()) return false;
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    return true;
  };
  std::string_view line;
  // The header is checked whole before assimp sees it: assimp hangs on some malformed headers
  // ("plyply", found by the ply_mesh fuzz target) and misreads others.
  if (!next_line(line) || tokens_of(line).size() != 1 || tokens_of(line)[0] != "ply") {
    bad_ply(source, 1, "not a PLY file: the first line must be 'ply'");
  }
  bool has_format = false;
  bool ascii = false;
  std::vector<PlyElement> elements;
  std::uint64_t unknown_line = 0;  // the first header line that is none of PLY's keywords
  std::string unknown_word;
  for (;;) {
    if (!next_line(line)) bad_ply(source, line_no, "the header has no end_header");
    // Printable text only (assimp hangs on "end_header\v\0": a ply_mesh fuzz timeout).
    for (std::size_t k = 0; k < line.size(); ++k) {
      const auto c = static_cast<unsigned char>(line[k]);
      const bool cr_at_end = c == '\r' && k + 1 == line.size();
      if (!cr_at_end && c != '\t' && (c < 0x20 || c > 0x7e)) {
        bad_ply(source, line_no, "the header holds a byte that is not printable text");
      }
    }
    const auto tok = tokens_of(line);
    // assimp loses the property after a blank header line and reads the values shifted
    // (ply_mesh fuzz find, kept).
    if (tok.empty()) bad_ply(source, line_no, "a blank line in the header");
    if (tok[0] == "end_header") break;
    if (tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "format") {
      if (has_format || tok.size() != 3 || tok[2] != "1.0" ||
          (tok[1] != "ascii" && tok[1] != "binary_little_endian" && tok[1] != "binary_big_endian")) {
        bad_ply(source, line_no, "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      }
      has_format = true;
      ascii = tok[1] == "ascii";
    } else if (tok[0] == "element") {
      PlyElement e;
      if (tok.size() != 3 || !whole_number(tok[2], e.count)) {
        bad_ply(source, line_no, "expected 'element NAME COUNT'");
      }
      if (!plain_name(tok[1])) {
        bad_ply(source, line_no,
                "element name '" + std::string(tok[1].substr(0, 40)) +
                    "' is not a plain name (a letter or '_', then letters, digits, '_', '-' or '.')");
      }
      e.name = std::string(tok[1]);
      e.line = line_no;
      // assimp reads the values of a second element of one name (a second 'vertex' of 4 after one
      // of 0 gave 4 vertices that no line-by-line reading finds: a ply_mesh fuzz find from CI, kept).
      for (const PlyElement& earlier : elements) {
        if (earlier.name == e.name) {
          bad_ply(source, line_no,
                  "a second element '" + e.name + "' (the first is on line " + std::to_string(earlier.line) + ")");
        }
      }
      elements.push_back(std::move(e));
    } else if (tok[0] == "property") {
      if (elements.empty()) bad_ply(source, line_no, "a property before any element");
      const bool list = tok.size() > 1 && tok[1] == "list";
      // "property TYPE NAME" or "property list COUNT_TYPE ITEM_TYPE NAME".
      for (std::size_t k = list ? 2 : 1; k < (list ? 4 : 2); ++k) {
        if (k >= tok.size() || !known_type(tok[k])) {
          bad_ply(source, line_no,
                  "property: unknown type '" + std::string(k < tok.size() ? tok[k].substr(0, 40) : "") + "'");
        }
      }
      elements.back().is_list.push_back(list);
      elements.back().value_types.emplace_back(tok[list ? 3 : 1]);
      if (tok.size() != (list ? 5u : 3u)) bad_ply(source, line_no, "expected 'property TYPE NAME'");
      if (!plain_name(tok.back())) {
        bad_ply(source, line_no,
                "property name '" + std::string(tok.back().substr(0, 40)) +
                    "' is not a plain name (a letter or '_', then letters, digits, '_', '-' or '.')");
      }
      // Likewise a property named twice: which of the two a reader keeps is its own choice.
      for (const auto* names : {&elements.back().scalar_names, &elements.back().list_names}) {
        if (std::find(names->begin(), names->end(), tok.back()) != names->end()) {
          bad_ply(source, line_no,
                  "a second property '" + std::string(tok.back()) + "' in element '" + elements.back().name + "'");
        }
      }
      (list ? elements.back().list_names : elements.back().scalar_names).emplace_back(tok.back());
    } else if (unknown_line == 0) {
      unknown_line = line_no;
      unknown_word = std::string(tok[0].substr(0, 40));
    }
  }
  if (!has_format) bad_ply(source, line_no, "the header has no format line");
  // Exporters write free text in the header (Blender 2.4's "Created by Blender3D ..."); assimp skips
  // such a line as it skips a comment. In an ASCII file that is safe to follow: the body is checked
  // below against the elements announced, so a misspelt element or property line cannot shift
  // what is read. A binary body is not checked, so there an unknown line is refused.
  if (unknown_line != 0 && !ascii) {
    bad_ply(source, unknown_line,
            "unknown header line '" + unknown_word +
                "' (a binary PLY's header may hold only format, element, property, comment and obj_info lines)");
  }
  // Positions are what a mesh is read for; assimp also leaks memory on a vertex element without
  // them (found by the ply_mesh fuzz target), so such a header is refused here.
  // Likewise a face element without its index list (assimp leaks on that too).
  for (const PlyElement& e : elements) {
    if (e.name == "face" &&
        std::find(e.list_names.begin(), e.list_names.end(), "vertex_indices") == e.list_names.end() &&
        std::find(e.list_names.begin(), e.list_names.end(), "vertex_index") == e.list_names.end()) {
      bad_ply(source, e.line, "the face element has no 'vertex_indices' list");
    }
    if (e.name != "vertex") continue;
    for (const char* axis : {"x", "y", "z"}) {
      if (std::find(e.scalar_names.begin(), e.scalar_names.end(), axis) == e.scalar_names.end()) {
        bad_ply(source, e.line, std::string("the vertex element has no '") + axis + "' property");
      }
    }
  }
  if (std::none_of(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "vertex"; })) {
    bad_ply(source, line_no, "the header has no vertex element");
  }
  if (!ascii) return;
  for (const PlyElement& e : elements) {
    for (std::uint64_t i = 0; i < e.count; ++i) {
      std::vector<std::string_view> tok;
      do {
        if (!next_line(line)) {
          bad_ply(source, line_no,
                  "unexpected end of file: the header announces " + std::to_string(e.count) + " " + e.name +
                      " elements, the file holds " + std::to_string(i));
        }
        // A lone CR: assimp ends a line there, a line-based reading does not, so the values
        // would shift (found by the ply_mesh fuzz target's vertex check).
        if (const std::size_t cr = line.find('\r'); cr != std::string_view::npos && cr + 1 < line.size()) {
          bad_ply(source, line_no, "a carriage return inside a line");
        }
        // Other control bytes (vertical tab, form feed, ...) are blanks to some readers and
        // part of a number to assimp, which then fails and leaks (ply_mesh fuzz find, kept).
        for (const char c : line) {
          const auto byte = static_cast<unsigned char>(c);
          if ((byte < 0x20 && c != '\t' && c != '\r') || byte == 0x7f) {
            bad_ply(
                source, line_no,
                "a control character (byte " + std::to_string(byte) + ") where only numbers, spaces and tabs belong");
          }
        }
        tok = tokens_of(line);
      } while (tok.empty());
      std::size_t used = 0;
      // Which property each value belongs to, for its type.
      std::vector<std::size_t> property_of;
      for (std::size_t p = 0; p < e.is_list.size(); ++p) {
        const bool list = e.is_list[p];
        if (!list) {
          ++used;
          property_of.push_back(p);
          continue;
        }
        std::uint64_t n = 0;
        if (used >= tok.size() || !whole_number(tok[used], n) || n > tok.size()) {
          bad_ply(source, line_no,
                  e.name + " " + std::to_string(i) + ": expected a list length, got '" +
                      std::string(used < tok.size() ? tok[used].substr(0, 40) : "") + "'");
        }
        used += 1 + n;
        property_of.push_back(e.is_list.size());  // the list length: checked above
        property_of.insert(property_of.end(), n, p);
      }
      for (std::size_t k = 0; k < tok.size(); ++k) {
        if (!is_number(tok[k])) {
          bad_ply(source, line_no,
                  e.name + " " + std::to_string(i) + ": '" + std::string(tok[k].substr(0, 40)) +
                      "' is not a number within the range of a 32-bit float (with at most 18 digits before the point)");
        }
        if (k < property_of.size() && property_of[k] < e.is_list.size() &&
            !fits_integer_type(tok[k], e.value_types[property_of[k]])) {
          bad_ply(source, line_no,
                  e.name + " " + std::to_string(i) + ": '" + std::string(tok[k].substr(0, 40)) +
                      "' is not a whole number in the range of its type " + e.value_types[property_of[k]]);
        }
      }
      if (used != tok.size()) {
        bad_ply(source, line_no,
                e.name + " " + std::to_string(i) + ": expected " + std::to_string(used) + " values, found " +
                    std::to_string(tok.size()) +
                    " (does the header announce more or fewer elements than the file holds?)");
      }
    }
  }
  while (next_line(line)) {
    if (!tokens_of(line).empty()) {
      bad_ply(source, line_no, "data after the last element the header announces (does it announce too few?)");
    }
  }
}

}  // namespace sweep::assets::detail
