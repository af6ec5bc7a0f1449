#include "sweep/core/locate.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace sweep {
namespace {

// The regula falsi refinement stops when the bracket is this small, as a fraction of the sweep's
// length (1e-13·L: far below float precision of the mesh, so rebuilding a vertex is exact in
// float), or after kMaxRefineSteps steps.
constexpr double kParamTolerance = 1e-13;
constexpr int kMaxRefineSteps = 100;

}  // namespace

SweepLocator::SweepLocator(const SweepShape& shape, int stations_per_span) {
  reset(shape, stations_per_span);
}

void SweepLocator::reset(const SweepShape& shape, int stations_per_span) {
  shape_ = &shape;
  station_parameters(shape, stations_per_span, station_t_);
  station_center_.clear();
  station_axis_.clear();
  for (double t : station_t_) {
    const Frame f = frame_at(shape, t);
    station_center_.push_back(f.center);
    station_axis_.push_back(f.axis());
  }
}

SweepCoords SweepLocator::locate(const Vec3& v) const {
  const SweepShape& shape = *shape_;
  const std::size_t m = station_t_.size();
  // Signed distance of v from the cross-section plane at a station: positive when v lies ahead.
  auto g_station = [&](std::size_t q) { return station_axis_[q].dot(v - station_center_[q]); };
  auto g_exact = [&](double t) {
    const Frame f = frame_at(shape, t);
    return f.axis().dot(v - f.center);
  };

  double best_t = 0;
  double best_dist = std::numeric_limits<double>::infinity();
  auto consider = [&](double t) {
    const double d = (v - center_at(shape, t)).squaredNorm();
    if (d < best_dist) {
      best_dist = d;
      best_t = t;
    }
  };

  // Every bracket where the plane sweeps past v is a candidate: the nearest plane wins.
  double g_prev = g_station(0);
  for (std::size_t q = 1; q < m; ++q) {
    const double g_next = g_station(q);
    if ((g_prev >= 0) != (g_next >= 0) || g_next == 0) {
      // Illinois-modified regula falsi on the exact plane distance within [t_a, t_b].
      double ta = station_t_[q - 1], tb = station_t_[q];
      double ga = g_prev, gb = g_next;
      if (ga == 0) {
        tb = ta;
      } else {
        int side = 0;
        const double tol = kParamTolerance * shape.length();
        for (int it = 0; it < kMaxRefineSteps && tb - ta > tol; ++it) {
          const double tc = (ga * tb - gb * ta) / (ga - gb);
          const double gc = g_exact(tc);
          if (gc == 0) {
            ta = tb = tc;
            break;
          }
          if ((gc > 0) == (ga > 0)) {
            ta = tc;
            ga = gc;
            if (side == -1) gb *= 0.5;
            side = -1;
          } else {
            tb = tc;
            gb = gc;
            if (side == 1) ga *= 0.5;
            side = 1;
          }
        }
      }
      consider(std::abs(ga) <= std::abs(gb) ? ta : tb);
    }
    g_prev = g_next;
  }
  // Behind (or on) the root plane or beyond (or on) the tip plane: the end sections with an axial
  // offset. A point exactly on an end plane is a candidate there even when no bracket starts at it.
  if (g_station(0) <= 0) consider(0.0);
  if (g_station(m - 1) >= 0) consider(shape.length());

  const Frame f = frame_at(shape, best_t);
  const Vec3 local = f.to_local(v);
  SweepCoords c;
  c.t = best_t;
  const bool at_end = best_t == 0.0 || best_t == shape.length();
  c.z = at_end ? local.z() : 0.0;
  double theta = std::atan2(local.y(), local.x());
  if (theta < 0) theta += 2 * std::numbers::pi;
  c.theta = theta;
  const double rho = std::hypot(local.x(), local.y());
  c.s = rho / radius_at(shape, theta, best_t);
  return c;
}

}  // namespace sweep
