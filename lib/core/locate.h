#pragma once
// Sweep coordinates of a point (the paper's §III; SweepCoords in core/deform_point.h): the parameter
// t whose cross-section plane passes through it (the nearest such plane where several do), its
// angle θ in that plane, the ratio s of its distance from the axis to the surface radius there,
// and an axial offset z for points beyond the end sections (t is then clamped to 0 or L).
// Rebuilding with deform_point on the same shape gives the point back.
#include <vector>

#include "sweep/core/deform_point.h"
#include "sweep/core/sweep_shape.h"

namespace sweep {

// Finds sweep coordinates for many points against one shape: builds a table of stations once
// (centre and axis at `stations_per_span` points per span), scans it for sign changes of the
// signed plane distance, and refines each bracket by the Illinois variant of regula falsi on the
// exact sweep's plane distance (the bracket always keeps the sign change), until the bracket is
// 1e-13 of the sweep's length (at most 100 steps).
class SweepLocator {
 public:
  explicit SweepLocator(const SweepShape& shape, int stations_per_span = 16);
  // None yet: reset() it before locating.
  SweepLocator() = default;
  // Against `shape` (kept by reference, as by the constructor), the table rebuilt in place: a
  // locator kept for a shape that changes allocates nothing once its table has grown.
  void reset(const SweepShape& shape, int stations_per_span = 16);
  SweepCoords locate(const Vec3& point) const;
  const SweepShape& shape() const { return *shape_; }

 private:
  const SweepShape* shape_ = nullptr;
  std::vector<double> station_t_;
  std::vector<Vec3> station_center_;
  std::vector<Vec3> station_axis_;
};

}  // namespace sweep
