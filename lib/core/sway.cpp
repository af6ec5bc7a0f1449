#include "sweep/core/sway.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace sweep {

bool is_bending_mode(const ChainModel& model, int mode) {
  double bend = 0, twist = 0;
  for (int j = 0; j < model.joints; ++j) {
    for (int c = 0; c < 3; ++c) {
      const double a = model.modes(3 * j + c, mode);
      (c == 2 ? twist : bend) += a * a;
    }
  }
  return bend > twist;
}

SwayFigures sway_figures(const ChainModel& model, const SweepShape& rest, const Vec3& gravity) {
  SwayFigures out;
  out.feels_gravity = true;
  const int dim = 3 * model.joints;
  for (int c = 0; c < dim && out.frequencies_hz.size() < 2; ++c) {
    if (!is_bending_mode(model, c)) continue;
    out.frequencies_hz.push_back(std::sqrt(std::max(model.omega2[c], 0.0)) / (2 * std::numbers::pi));
  }
  if (gravity == Vec3::Zero()) return out;
  // Joint j carries the weight beyond it: τ_j = Σ_{i ≥ j} (c_i − c_j) × m_i g (metres, world axes).
  const int k = rest.section_count();
  const double s = model.metres_per_unit;
  Vec3 force = Vec3::Zero(), moment = Vec3::Zero();  // Σ m_i g and Σ c_i × m_i g beyond joint j
  const Vec3 tip = s * rest.frames[k - 1].center;
  Vec3 tip_shift = Vec3::Zero();
  for (int j = k - 1; j >= 1; --j) {
    const Vec3 c = s * rest.frames[j].center;
    force += model.node_mass[j] * gravity;
    moment += c.cross(model.node_mass[j] * gravity);
    const Vec3 torque = moment - c.cross(force);
    // The joint's turn in its own axes (its stiffness is diagonal there), then the tip's shift.
    const Quat& r = rest.frames[j].rotation;
    const Vec3 local = r.conjugate() * torque;
    Vec3 turn = Vec3::Zero();
    for (int a = 0; a < 3; ++a) {
      const double kk = model.stiffness(3 * (j - 1) + a, 3 * (j - 1) + a);
      turn[a] = kk > 0 ? local[a] / kk : 0.0;
    }
    tip_shift += (r * turn).cross(tip - c);
  }
  out.droop = tip_shift.norm() / (s * rest.length());
  return out;
}

SwayFigures sway_figures(const SweepDef& def, const Vec3& gravity) {
  if (def.material) return sway_figures(build_chain_model(def.rest, def.section_materials), def.rest, gravity);
  SwayFigures out;
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < def.springs.size(); ++i) lowest = std::min(lowest, def.springs[i].bend.frequency_hz);
  if (std::isfinite(lowest)) out.frequencies_hz.push_back(lowest);
  return out;
}

}  // namespace sweep
