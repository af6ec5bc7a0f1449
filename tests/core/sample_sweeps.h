#pragma once
// Small sweeps for tests, with every number visible.
#include <cmath>
#include <numbers>

#include "sweep/core/rig.h"

namespace sweep::test {

// K sections along +z at t = 0, 1, 2, ... (unit spacing), identity frames, all radii `radius`.
inline SweepShape straight_shape(int k, int n, double radius = 0.5) {
  SweepShape s;
  s.radial_count = n;
  for (int i = 0; i < k; ++i) {
    s.t.push_back(i);
    s.frames.push_back({Quat::Identity(), Vec3(0, 0, i)});
    for (int j = 0; j < n; ++j) s.radii.push_back(radius);
  }
  return s;
}

// A sweep whose sections are all different: bent about y, twisted about the axis, with uneven
// spacing and radii that vary with section and angle. Frames are exact rotations.
inline SweepShape irregular_shape(int k, int n) {
  SweepShape s;
  s.radial_count = n;
  double t = 0;
  Frame f;
  for (int i = 0; i < k; ++i) {
    if (i > 0) {
      const double h = 0.7 + 0.3 * std::sin(1.7 * i);
      t += h;
      const Quat turn(Eigen::AngleAxisd(0.2 + 0.05 * i, Vec3::UnitY()) * Eigen::AngleAxisd(0.1 * i, Vec3::UnitZ()));
      f = f * Frame{turn, Vec3(0.05 * i, 0.0, h)};
    }
    s.t.push_back(t);
    s.frames.push_back(f);
    for (int j = 0; j < n; ++j) s.radii.push_back(0.4 + 0.1 * std::cos(2.0 * j + i) + 0.02 * i);
  }
  return s;
}

inline SweepDef sweep_def(SweepShape shape) {
  return make_sweep("test", std::move(shape));
}

// A rig of one bent, irregular part named "part" (7 sections of 8 radii).
inline Rig bent_part() {
  Rig rig;
  rig.sweeps.push_back(sweep_def(irregular_shape(7, 8)));
  rig.sweeps.back().name = "part";
  return rig;
}

}  // namespace sweep::test
