#pragma once
// A sweep's deformed pose as one flat list of numbers, for tests that compare two runs: section
// centres (mesh units), rotations times the part's length (so an angle counts as the distance it
// moves the tip; the quaternion's sign fixed), radii. Shared by the clock, body and live tests.
#include <algorithm>
#include <cmath>
#include <vector>

#include "sweep/core/elastic_sweep.h"

namespace sweep::sim::test_pose {

inline std::vector<double> pose(const ElasticSweep& s) {
  std::vector<double> p;
  const double len = s.rest().length();
  for (const Frame& f : s.deformed().frames) {
    for (int c = 0; c < 3; ++c) p.push_back(f.center[c]);
    for (int c = 0; c < 4; ++c) p.push_back(len * f.rotation.coeffs()[c] * (f.rotation.w() < 0 ? -1 : 1));
  }
  p.insert(p.end(), s.deformed().radii.begin(), s.deformed().radii.end());
  return p;
}

// The largest difference between two poses of the same sweep, entry by entry.
inline double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0;
  for (std::size_t m = 0; m < a.size(); ++m) d = std::max(d, std::abs(a[m] - b[m]));
  return d;
}

}  // namespace sweep::sim::test_pose
