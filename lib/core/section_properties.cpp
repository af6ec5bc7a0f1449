#include "sweep/core/section_properties.h"

#include <cassert>
#include <cmath>
#include <numbers>

namespace sweep {

SectionProperties section_properties(std::span<const double> radii) {
  const std::size_t n = radii.size();
  assert(n >= 3);
  // Shoelace sums about the section centre, then the parallel-axis shift.
  double a2 = 0, sx = 0, sy = 0, ixx = 0, iyy = 0, ixy = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t k = (j + 1) % n;
    const double tj = 2 * std::numbers::pi * static_cast<double>(j) / static_cast<double>(n);
    const double tk = 2 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(n);
    const double xj = radii[j] * std::cos(tj), yj = radii[j] * std::sin(tj);
    const double xk = radii[k] * std::cos(tk), yk = radii[k] * std::sin(tk);
    const double c = xj * yk - xk * yj;
    a2 += c;
    sx += c * (xj + xk);
    sy += c * (yj + yk);
    ixx += c * (yj * yj + yj * yk + yk * yk);
    iyy += c * (xj * xj + xj * xk + xk * xk);
    ixy += c * (xj * yk + 2 * xj * yj + 2 * xk * yk + xk * yj);
  }
  SectionProperties p;
  p.area = 0.5 * a2;
  p.centroid_x = sx / (3 * a2);
  p.centroid_y = sy / (3 * a2);
  p.i_xx = ixx / 12 - p.area * p.centroid_y * p.centroid_y;
  p.i_yy = iyy / 12 - p.area * p.centroid_x * p.centroid_x;
  p.i_xy = ixy / 24 - p.area * p.centroid_x * p.centroid_y;
  p.polar = p.i_xx + p.i_yy;
  // Saint-Venant's approximation is exact for a circle (A⁴/(4π² I_p) = π r⁴/2 = I_p); a polygon
  // of equal radii gets J = I_p so that a sampled circle twists like the circle it samples.
  bool round = true;
  for (std::size_t j = 1; j < n; ++j) round = round && radii[j] == radii[0];
  p.torsion = round ? p.polar : p.area * p.area * p.area * p.area / (4 * std::numbers::pi * std::numbers::pi * p.polar);
  return p;
}

}  // namespace sweep
