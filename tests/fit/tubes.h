#pragma once
// Tubes with a known answer, built in the tests: a circular tube of radius r (optionally tapered)
// around a circular arc in the x-z plane that starts at the origin heading +z and turns towards
// +x by `bend` radians over arc length `length`. Rings of `segments` vertices, closed by fans.
#include <cmath>
#include <numbers>

#include "sweep/core/mesh.h"

namespace sweep::test {

struct Tube {
  double length = 1.0;
  double radius = 0.1;
  double tip_radius = -1;  // < 0: same as radius
  double bend = 0;         // radians
  int rings = 41;
  int segments = 24;

  double kappa() const { return bend / length; }
  Vec3 axis(double s) const {
    if (bend == 0) return {0, 0, s};
    const double a = kappa() * s;
    return {(1 - std::cos(a)) / kappa(), 0, std::sin(a) / kappa()};
  }
  Vec3 tangent(double s) const {
    const double a = kappa() * s;
    return {std::sin(a), 0, std::cos(a)};
  }
  double radius_at(double s) const {
    const double rt = tip_radius < 0 ? radius : tip_radius;
    return radius + (rt - radius) * s / length;
  }
  Mesh mesh() const {
    Mesh m;
    for (int i = 0; i < rings; ++i) {
      const double s = length * i / (rings - 1);
      const double a = kappa() * s;
      const Vec3 u(std::cos(a), 0, -std::sin(a)), v(0, 1, 0);
      for (int j = 0; j < segments; ++j) {
        const double th = 2 * std::numbers::pi * j / segments;
        m.positions.push_back(axis(s) + radius_at(s) * (std::cos(th) * u + std::sin(th) * v));
      }
    }
    const auto id = [&](int i, int j) { return static_cast<std::uint32_t>(i * segments + (j % segments)); };
    const auto root = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(axis(0));
    m.positions.push_back(axis(length));
    for (int i = 0; i + 1 < rings; ++i) {
      for (int j = 0; j < segments; ++j) m.add_face({id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)});
    }
    for (int j = 0; j < segments; ++j) {
      m.add_face({root, id(0, j + 1), id(0, j)});
      m.add_face({root + 1, id(rings - 1, j), id(rings - 1, j + 1)});
    }
    return m;
  }
};

}  // namespace sweep::test
