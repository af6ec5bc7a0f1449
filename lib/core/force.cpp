#include "sweep/core/force.h"

#include <algorithm>
#include <cmath>

namespace sweep {

void SectionLoads::resize(int sections, int radial_count) {
  force.assign(sections, Vec3::Zero());
  torque.assign(sections, Vec3::Zero());
  radial.assign(static_cast<std::size_t>(sections) * radial_count, 0.0);
}

void SectionLoads::clear() {
  std::fill(force.begin(), force.end(), Vec3::Zero());
  std::fill(torque.begin(), torque.end(), Vec3::Zero());
  std::fill(radial.begin(), radial.end(), 0.0);
}

Vec3 rotational_torque(const Vec3& p, const Vec3& center, const Vec3& f, double c_rot, MomentModel model) {
  const Vec3 moment = (p - center).cross(f);
  if (model == MomentModel::physical) return moment;
  const double norm = moment.norm();
  // a × f = 0 (force through the centre, or no force): no rotational part.
  if (norm <= 1e-300) return Vec3::Zero();
  return c_rot * f.norm() * (moment / norm);
}

double radial_force(const Vec3& p, const Vec3& o, const Vec3& normal, const Vec3& f, double c_rad) {
  const Vec3 op = p - o;
  const double op_len = op.norm();
  if (op_len <= 1e-300) return 0.0;  // p on the axis: no radial direction
  const Vec3 f_plane = f - f.dot(normal) * normal;
  const Vec3 p_hat = p + f_plane;
  return c_rad * op.dot(p - p_hat) / op_len;
}

std::array<double, 4> bilinear_weights(double u, double w) {
  return {(1 - u) * (1 - w), (1 - u) * w, u * (1 - w), u * w};
}

namespace {

// The key section nearest t that may move (section 0 is the fixed root).
int nearest_movable_section(const SweepShape& shape, double t) {
  const SpanCoord sc = locate_span(shape, t);
  const int i = sc.u < 0.5 ? sc.span : sc.span + 1;
  return std::max(i, 1);
}

}  // namespace

void accumulate_force(const SweepShape& shape, const ForceSpec& force, double t, double theta, double c_rot,
                      double c_rad, SectionLoads& loads) {
  const Frame plane = frame_at(shape, t);
  const double r = radius_at(shape, theta, t);
  const double cos_t = std::cos(theta), sin_t = std::sin(theta);
  const Vec3 p = plane.to_world(Vec3(r * cos_t, r * sin_t, 0.0));
  // A surface-frame vector turns with the surface: re-expressed in world axes every time.
  const Vec3 f = force.frame == VectorFrame::world
                     ? force.vector
                     : plane.rotation * Vec3(force.vector.x() * cos_t - force.vector.y() * sin_t,
                                             force.vector.x() * sin_t + force.vector.y() * cos_t, force.vector.z());
  const SpanCoord sc = locate_span(shape, t);
  const int k = shape.section_count();

  if (force.components & kRotational) {
    auto add_torque = [&](int i) {
      loads.torque[i] += rotational_torque(p, shape.frames[i].center, f, c_rot, force.moment);
    };
    switch (force.target) {
      case RotationTarget::nearest:
        add_torque(nearest_movable_section(shape, t));
        break;
      case RotationTarget::section:
        if (force.target_section >= 1 && force.target_section < k) add_torque(force.target_section);
        break;
      case RotationTarget::chain: {
        // Sections 1 .. the last one at or before the point; at least section 1.
        const int last = std::max(sc.u >= 1.0 ? sc.span + 1 : sc.span, 1);
        for (int i = 1; i <= last; ++i) add_torque(i);
        break;
      }
    }
  }

  if (force.components & kRadial) {
    const double f_rad = radial_force(p, plane.center, plane.axis(), f, c_rad);
    const AngleCoord ac = locate_angle(shape.radial_count, theta);
    const int n = shape.radial_count;
    const int j1 = (ac.j + 1) % n;
    const std::array<double, 4> w = bilinear_weights(sc.u, ac.w);
    const std::array<int, 4> sec = {sc.span, sc.span, sc.span + 1, sc.span + 1};
    const std::array<int, 4> ang = {ac.j, j1, ac.j, j1};
    for (int c = 0; c < 4; ++c) {
      if (sec[c] == 0 || w[c] == 0.0) continue;  // the root's handles are fixed
      // f_rad pushes inward; a handle's coordinate grows outward.
      loads.radial[static_cast<std::size_t>(sec[c]) * n + ang[c]] -= w[c] * f_rad;
    }
  }

  if (force.components & kPositional) {
    const double w0 = 1 - sc.u, w1 = sc.u;
    if (sc.span >= 1) loads.force[sc.span] += w0 * f;
    loads.force[sc.span + 1] += w1 * f;
  }
}

}  // namespace sweep
