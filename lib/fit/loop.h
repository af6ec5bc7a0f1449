#pragma once
// Slice loops in their plane: picking the loop around an axis point, its area centroid, and the
// radius samples of a key section (rays from the centre). Plain geometry, no CGAL.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/frame.h"
#include "fit/slicer.h"

namespace sweep::fit {

using Vec2 = Eigen::Vector2d;

// An orthonormal basis (u, v) of the plane through `origin` with unit normal n = u × v.
struct PlaneBasis {
  Vec3 origin = Vec3::Zero();
  Vec3 u = Vec3::UnitX(), v = Vec3::UnitY(), n = Vec3::UnitZ();
  Vec2 to_plane(const Vec3& p) const {
    const Vec3 d = p - origin;
    return {d.dot(u), d.dot(v)};
  }
  Vec3 to_world(const Vec2& q) const { return origin + q.x() * u + q.y() * v; }
};
PlaneBasis plane_basis(const Vec3& origin, const Vec3& normal);  // normal need not be unit

// A closed loop of a slice, with what the axis tracer needs to know about it.
struct Loop {
  std::vector<Vec3> points;      // closed: the last point joins the first
  Vec3 centroid = Vec3::Zero();  // area centroid (vertex mean for a degenerate loop)
  double area = 0;               // unsigned area, mesh units²
  double radius = 0;             // equivalent radius sqrt(area/π), mesh units
  bool was_open = false;         // the slice was an open polyline (a hole in the mesh) closed here
  bool around = true;            // its polygon contains the point it was picked for (loop_around)
};

// The loop of `slice` around `point` (a plane point of the slice): among loops whose polygon
// contains it, the one of least area (the part's own section rather than a loop around it);
// if none contains it, the loop nearest to it when no farther than `max_distance`.
// Open polylines take part closed by their gap. Empty when there is no such loop.
std::optional<Loop> loop_around(const std::vector<SlicePolyline>& slice, const Vec3& point,
                                const Vec3& normal, double max_distance);

// Area centroid, area and equivalent radius of a polygon in the plane of `basis`.
void measure_loop(const PlaneBasis& basis, Loop& loop);

// Radius samples of a key section: rays in the section plane from frame.center at
// θ_j = 2πj/n from the frame's x axis, each hitting the loop at its outermost crossing.
struct RaySamples {
  std::vector<double> radii;    // n radii, mesh units (> 0)
  int multi_crossing_rays = 0;  // rays crossing the loop more than once (not star-shaped)
  int missed_rays = 0;          // rays that found no crossing (centre outside the loop)
};
RaySamples sample_radii(const Frame& frame, const std::vector<Vec3>& loop, int n);

}  // namespace sweep::fit
