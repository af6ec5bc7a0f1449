#include "sweep/core/frame.h"

#include <cmath>

namespace sweep {

Quat rotation_from_vector(const Vec3& phi) {
  const double angle = phi.norm();
  if (angle < 1e-300) return Quat::Identity();
  return Quat(Eigen::AngleAxisd(angle, phi / angle));
}

}  // namespace sweep
