#include "sweep/core/fold_check.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

namespace sweep {
namespace {

// Each section's mean radius, into `out` (K entries).
void mean_radii(const SweepShape& s, std::vector<double>& out) {
  const int k = s.section_count(), n = s.radial_count;
  for (int i = 0; i < k; ++i) {
    out[i] = 0;
    for (int j = 0; j < n; ++j) out[i] += s.radius_sample(i, j);
    out[i] /= n;
  }
}

bool pair_crosses(const SweepShape& s, const std::vector<double>& r, int a, int b) {
  return discs_cross(s.frames[a].center, s.frames[a].axis(), r[a], s.frames[b].center, s.frames[b].axis(), r[b]);
}

}  // namespace

bool discs_cross(const Vec3& ca, const Vec3& na, double ra, const Vec3& cb, const Vec3& nb, double rb) {
  const Vec3 d = na.cross(nb);
  const double d2 = d.squaredNorm();
  if (d2 < 1e-18) {
    // Parallel planes: they meet only when they are one plane, then as two circles do.
    const double gap = (cb - ca).dot(na);
    return std::abs(gap) <= 1e-12 * std::max(ra, rb) && (cb - ca).norm() < ra + rb;
  }
  // The planes' common line: p0 + t u, p0 = (h_a n_b − h_b n_a) × d / |d|².
  const double ha = na.dot(ca), hb = nb.dot(cb);
  const Vec3 p0 = (ha * nb - hb * na).cross(d) / d2;
  const Vec3 u = d / std::sqrt(d2);
  // Each disc cuts the line in a chord [t − w, t + w] (none when the line passes beyond it).
  const auto chord = [&](const Vec3& c, double r, double& t, double& w) {
    t = (c - p0).dot(u);
    const double off2 = (c - p0).squaredNorm() - t * t;
    if (off2 >= r * r) return false;
    w = std::sqrt(r * r - off2);
    return true;
  };
  double ta = 0, wa = 0, tb = 0, wb = 0;
  if (!chord(ca, ra, ta, wa) || !chord(cb, rb, tb, wb)) return false;
  return std::abs(ta - tb) < wa + wb;
}

FoldMeter::FoldMeter(const SweepShape& rest) {
  const int k = rest.section_count();
  rest_relative_.assign(k, Frame{});
  for (int i = 1; i < k; ++i) rest_relative_[i] = rest.frames[i - 1].inverse() * rest.frames[i];
  mean_radius_.assign(k, 0.0);
  radius_now_.assign(k, 0.0);
  mean_radii(rest, mean_radius_);
  crossed_at_rest_.assign(static_cast<std::size_t>(k) * k, 0);
  for (int a = 0; a < k; ++a) {
    for (int b = a + 1; b < k; ++b)
      crossed_at_rest_[static_cast<std::size_t>(a) * k + b] = pair_crosses(rest, mean_radius_, a, b);
  }
}

void FoldMeter::measure(const SweepShape& deformed, int frame) {
  const int k = deformed.section_count();
  assert(k == static_cast<int>(rest_relative_.size()));
  for (int i = 1; i < k; ++i) {
    const Quat relative = deformed.frames[i - 1].rotation.conjugate() * deformed.frames[i].rotation;
    const Vec3 now = relative * Vec3::UnitZ(), was = rest_relative_[i].rotation * Vec3::UnitZ();
    const double bend = std::atan2(now.cross(was).norm(), now.dot(was));
    if (bend > largest_bend) {
      largest_bend = bend;
      bend_span = i;
      bend_frame = frame;
    }
    if (fold_frame < 0 && bend > std::numbers::pi / 2) {
      fold_frame = frame;
      fold_span = i;
    }
  }
  if (cross_frame >= 0) return;  // the first is what the warning names
  // The radii as the pose has them (a part may swell or pinch), the discs where the pose puts them.
  mean_radii(deformed, radius_now_);
  for (int a = 0; a < k && cross_frame < 0; ++a) {
    for (int b = a + 1; b < k; ++b) {
      if (crossed_at_rest_[static_cast<std::size_t>(a) * k + b]) continue;
      if (pair_crosses(deformed, radius_now_, a, b)) {
        cross_frame = frame;
        cross_a = a;
        cross_b = b;
        break;
      }
    }
  }
}

}  // namespace sweep
