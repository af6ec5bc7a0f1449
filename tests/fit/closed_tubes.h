#pragma once
// Tubes without an end: a torus, the simplest closed tube, whose stretches from a root to
// a tip given mid-tube go on past the tip and back round to the root.
#include <cmath>
#include <numbers>

#include "sweep/core/mesh.h"

namespace sweep::test {

// A torus of centre-line radius `major` around the z axis and tube radius `minor`: `rings` rings
// of `segments` vertices (ring i at angle 2πi/rings from +x, counter-clockwise), quads.
inline Mesh make_torus(double major, double minor, int rings, int segments) {
  Mesh m;
  for (int i = 0; i < rings; ++i) {
    const double u = 2 * std::numbers::pi * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double v = 2 * std::numbers::pi * j / segments;
      const double rho = major + minor * std::cos(v);
      m.positions.emplace_back(rho * std::cos(u), rho * std::sin(u), minor * std::sin(v));
    }
  }
  const auto id = [&](int i, int j) { return static_cast<std::uint32_t>((i % rings) * segments + j % segments); };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  }
  return m;
}

}  // namespace sweep::test
