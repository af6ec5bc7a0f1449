#pragma once
// Text the same way everywhere.
//  - In messages: 4 significant digits for a quantity, "x,y,z" for a point (as --tip and --root
//    take it; 6 digits unless told), 3 for a percentage.
//  - In files (the mesh writers, the OBJ bake) and where a message must name a value exactly:
//    the shortest text that reads back to the same number (std::to_chars: independent of the
//    locale, "-0", "nan" and "inf" as such).
//  - A file name's extension in lower case, for choosing a format.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <concepts>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>

#include "sweep/core/error.h"
#include "sweep/core/frame.h"

namespace sweep {

inline std::string format_number(double x, int digits = 4) {
  std::ostringstream s;
  s.precision(digits);
  s << x;
  return s.str();
}

inline std::string format_point(const Vec3& p, int digits = 6) {
  std::ostringstream s;
  s.precision(digits);
  s << p.x() << "," << p.y() << "," << p.z();
  return s.str();
}

inline std::string format_percent(double share) {
  return format_number(100 * share, 3) + "%";
}

// The shortest round-trippable text of `value` appended to `out`: "1.5", "-0", "nan", "42"; a
// float's own shortest text ("0.1", not the double's "0.10000000149011612"). Only these three
// types, so that no argument is converted on the way.
template <typename T>
requires std::same_as<T, double> || std::same_as<T, float> || std::same_as<T, std::uint64_t>
void append_number(std::string& out, T value) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
  if (ec != std::errc()) fail(ErrorCategory::internal, "cannot format a number");
  out.append(buf, end);
}

// A number exactly, for a message that must name it: append_number's text.
inline std::string format_exact(double x) {
  std::string s;
  append_number(s, x);
  return s;
}

// The three coordinates of `p` by append_number, with `separator` between them: "1 2.5 -0".
template <typename Scalar>
void append_numbers(std::string& out, const Eigen::Matrix<Scalar, 3, 1>& p, std::string_view separator) {
  for (int k = 0; k < 3; ++k) {
    if (k) out += separator;
    append_number(out, p[k]);
  }
}

// A position exactly, for a message that must name it: "(1, 2.5, nan)".
template <typename Scalar>
std::string format_exact_point(const Eigen::Matrix<Scalar, 3, 1>& p) {
  std::string s = "(";
  append_numbers(s, p, ", ");
  return s + ")";
}

// The extension without its dot, in lower case: "glb" for "scene.GLB", "" for "mesh" or "mesh.".
inline std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  if (!ext.empty() && ext.front() == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace sweep
