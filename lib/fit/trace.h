#pragma once
// The axis of a part as a polyline with tangents and local radii, and rotation-minimizing frames
// along it. The axis starts as the centroids of rings of equal surface distance from the tip
// (fit/rings.h), which run around the part whatever its curl; refine_axis then smooths it and
// moves each point to the area centroid of the plane slice normal to it, the centre that the key
// sections are cut around.
#include <string>
#include <vector>

#include "sweep/core/frame.h"
#include "sweep/fit/slicer.h"
#include "sweep/fit/surface_distance.h"

namespace sweep::fit {

struct AxisTrace {
  std::vector<Vec3> points;    // axis points from root to tip end
  std::vector<Vec3> tangents;  // unit axis direction at each point
  std::vector<double> radii;   // equivalent radius √(area/π) of each point's slice, 0 where none
  // Why the axis ends where it does at its tip end (extend_axis), for messages and the report:
  // "the slices reached the cap's end", "the slice ahead shrank to ...", "... then straight on
  // ... to the surface". Empty for an axis given as a polyline.
  std::string end_reason;
};

// Smooths `points` (root first; `radii` the local radius at each, mesh units) over about half a
// local radius, resamples it every quarter of the median radius, and moves each sample to the
// centroid of its slice loop normal to the axis (when that loop lies around it and is no larger
// than 1.5 local radii: elsewhere the plane also cuts the body or another part), twice: the second
// pass slices along the tangents of the first. Ends whose slice fails are dropped (a ring over a
// cap is not on the axis). Smoothing is by local parabolas, which keep bends where they are.
AxisTrace refine_axis(const MeshSlicer& slicer, const std::vector<Vec3>& points, const std::vector<double>& radii);

// Continues the axis into the tip's cap until it has gone `length` (mesh units) along its last
// tangent: first by slices as closely spaced as its own last points, centred in their loops,
// while each loop keeps most of the last one's size and the axis turns gently; then straight on,
// stopping short of the surface (`surface`) if the cap ends sooner. Each point carries its slice
// loop's radius; the last point, the part's end, radius 0. Sets axis.end_reason.
void extend_axis(const MeshSlicer& slicer, const TriangleDistance& surface, AxisTrace& axis, double length);

// Makes the axis start where `point` projects onto it: cut there (the nearest point of the
// polyline; tangent and radius interpolated), or, when the point lies before the start (within
// `max_extension` mesh units), extended straight back to its projection. The last point is never
// cut away.
void trim_axis_start(AxisTrace& axis, const Vec3& point, double max_extension);

// An axis given as a polyline from root to tip (at least 2 distinct points): tangents by central
// chords, radii of the slice loops around each point (0 where there is none).
AxisTrace axis_from_polyline(const MeshSlicer& slicer, const std::vector<Vec3>& points);

// Smooths the axis where it bends tighter than `max_curvature_radii` over its local radius (the
// turn at a point over the mean of its two segments, times its radius: the slices' where measured,
// the nearest measured one elsewhere): each such point moves halfway to the midpoint of its
// neighbours, repeated until none is left (at most 50 rounds); tangents follow. The ends stay.
// Returns the number of moves. A tube cannot bend tighter than its radius; an axis that seems
// to (slice centroids pulled aside by a neighbour fused to the part) is off centre there.
int limit_axis_curvature(AxisTrace& axis, double max_curvature_radii);

// Arc length at each point of a polyline (0 at the first).
std::vector<double> arc_lengths(const std::vector<Vec3>& points);

// Rotation-minimizing frames along a polyline with unit tangents, by the double reflection method
// (Wang, Jüttler, Zheng & Liu 2008). The frame's third column is the tangent; the first frame's x
// axis is `x0` made perpendicular to the first tangent (or a deterministic choice when x0 is 0).
std::vector<Quat> rotation_minimizing_frames(const std::vector<Vec3>& points, const std::vector<Vec3>& tangents,
                                             const Vec3& x0 = Vec3::Zero());

}  // namespace sweep::fit
