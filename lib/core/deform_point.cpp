#include "sweep/core/deform_point.h"

#include <cmath>

namespace sweep {

Vec3 deform_point(const SweepShape& shape, const SweepCoords& c) {
  const Frame f = frame_at(shape, c.t);
  const double r = c.s * radius_at(shape, c.theta, c.t);
  return f.to_world(Vec3(r * std::cos(c.theta), r * std::sin(c.theta), c.z));
}

}  // namespace sweep
