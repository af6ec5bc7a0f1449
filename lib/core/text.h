#pragma once
// Numbers and points in messages, the same way everywhere: 4 significant digits for a quantity,
// "x,y,z" for a point (as --tip and --root take it), 3 for a percentage.
#include <sstream>
#include <string>

#include "core/frame.h"

namespace sweep {

inline std::string format_number(double x, int digits = 4) {
  std::ostringstream s;
  s.precision(digits);
  s << x;
  return s.str();
}

inline std::string format_point(const Vec3& p) {
  std::ostringstream s;
  s.precision(6);
  s << p.x() << "," << p.y() << "," << p.z();
  return s.str();
}

inline std::string format_percent(double share) {
  return format_number(100 * share, 3) + "%";
}

}  // namespace sweep
