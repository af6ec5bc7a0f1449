#pragma once
// Slice loops in their plane: picking the loop around an axis point, its area centroid, and the
// radius samples of a key section (rays from the centre). Plain geometry, no CGAL.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "sweep/core/frame.h"
#include "sweep/fit/slicer.h"

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
  int necks_cut = 0;             // how many necks loop_around cut it at (cut_at_necks)
};

// Whether loop_around cuts the loop it picks at its necks (cut_at_necks).
enum class Necks { keep, cut };

// The loop of `slice` around `point` (a plane point of the slice): among loops whose polygon
// contains it, the one of least area (the part's own section rather than a loop around it),
// with Necks::cut cut at its necks down to the piece around the point (a plane through two tubes
// fused side by side, homer's thighs, cuts one figure-8 loop around both); if none contains it,
// the loop nearest to it when no farther than `max_distance`, as it is.
// Open polylines take part closed by their gap. Empty when there is no such loop.
// The key sections cut necks (sections.cpp). The axis tracer (trace.cpp) does not: it already
// drops a slice too wide or pulled aside, and re-centring its points on the pieces of pinched
// slices as well made four fits of the fit-evidence table worse than with the sections' cuts
// alone (elephant's trunk, where the tusk lies against it: 11.1 % RMS against 3.2 %;
// refined_elephant's trunk, armadillo's leg, man's finger) and fixed none.
std::optional<Loop> loop_around(const std::vector<SlicePolyline>& slice, const Vec3& point, const Vec3& normal,
                                double max_distance, Necks necks = Necks::keep);

// A loop in its plane (`loop`, closed) that pinches between two tubes, two stretches of it close
// in space while far apart along it (a figure 8, a dumbbell), is cut across the neck, and only the
// piece containing `point` is kept; again on that piece, up to a few times. A neck is a chord
// inside the loop that splits it into two pieces, each at least a tenth of the area and each at
// least twice as thick as the chord is long (thickness 2·area/perimeter, a disc's radius), the
// narrowest such chord against the thinner piece first. An ellipse, a flat ear, a lobed tube, a
// C are not cut (loop.cpp gives the measurements). Returns the number of cuts (0: `loop` as it
// was).
int cut_at_necks(std::vector<Vec2>& loop, const Vec2& point);

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
