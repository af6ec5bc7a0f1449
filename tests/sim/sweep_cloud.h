#pragma once
// Points on and inside a sweep, with the sweep coordinates the locator gives them (what a binding
// would hold): the shared fixture of the fast-path and stress tests.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "sweep/bind/bind.h"
#include "sweep/bind/fast_deform.h"
#include "sweep/core/locate.h"

namespace sweep::test {

struct SweepCloud {
  bind::SweepBinding bound;       // vertex v is point v; weight 1
  std::vector<bind::Vec3f> rest;  // the points in float, as a mesh would hold them
  std::vector<Vec3> points;       // the points in double
};

// `count` points spread deterministically over t (caps 5 % beyond both ends included), θ and
// depth s ∈ [s_min, s_min + s_span] (1 = on the surface).
inline SweepCloud sweep_cloud(const SweepShape& shape, int count, double s_min, double s_span) {
  SweepCloud c;
  const SweepLocator locator(shape);
  for (int v = 0; v < count; ++v) {
    const long long w = v;
    const double t = -0.05 * shape.length() + 1.1 * shape.length() * static_cast<double>((w * 7919) % count) / count;
    const double theta = 2 * std::numbers::pi * static_cast<double>((w * 104729) % 997) / 997.0;
    const double s = s_min + s_span * static_cast<double>((w * 31) % 101) / 100.0;
    const double tc = std::clamp(t, 0.0, shape.length());
    const double r = s * radius_at(shape, theta, tc);
    const Vec3 p = frame_at(shape, tc).to_world(Vec3(r * std::cos(theta), r * std::sin(theta), t - tc));
    const SweepCoords sc = locator.locate(p);
    c.bound.vertices.push_back(static_cast<std::uint32_t>(v));
    c.bound.t.push_back(static_cast<float>(sc.t));
    c.bound.theta.push_back(static_cast<float>(sc.theta));
    c.bound.s.push_back(static_cast<float>(sc.s));
    c.bound.z.push_back(static_cast<float>(sc.z));
    c.bound.weight.push_back(1.0f);
    c.rest.push_back(p.cast<float>());
    c.points.push_back(p);
  }
  return c;
}

}  // namespace sweep::test
