#pragma once
// Tracing a part's axis by successive plane slices, and rotation-minimizing frames along it.
//
// The trace starts at the root: the plane through the root point is turned until its normal
// points from its loop's area centroid to the centroid of the loop one radius ahead (oblique cuts
// of a tube are centred on its axis, so a few slices settle it); that centroid is the first axis
// point. Each step then slices a plane a
// little ahead (a fraction of the local radius), perpendicular to the current direction, picks
// the loop around the predicted point, takes its centroid as the next axis point and the chord
// to it as the new direction. It follows curls and bends, and stops when the plane passes the tip
// or the part ends (no loop around the predicted point).
#include <string>
#include <vector>

#include "core/frame.h"
#include "fit/slicer.h"

namespace sweep::fit {

struct TraceOptions {
  // Step along the axis as a fraction of the local equivalent radius (sqrt(area/π) of the loop).
  // Smaller follows tighter bends and costs more slices (~0.4 ms each for 24k vertices).
  double step_fraction = 0.5;
  // Bounds on the step, as fractions of the root-to-tip distance.
  double min_step_fraction = 1.0 / 250;
  double max_step_fraction = 1.0 / 25;
  // A step that turns the direction by more than this has jumped to another part: the trace
  // stops there. Degrees.
  double max_turn_degrees = 60;
  int max_steps = 5000;
  // The trace ends "at the tip" when it runs out of loops no farther from the tip than this many
  // local radii (plus one step): the end cap of the part. Farther away, the tip was not reached.
  double tip_reach_radii = 3;
  // The trace also ends when its next plane passes the tip while the tip lies within this many
  // local radii (plus one step) of the current axis point. Tighter than the above, because a
  // plane can pass the tip's level long before a bending part gets there.
  double tip_pass_radii = 1.5;
  // The root may lie outside every slice loop by at most this distance (mesh units) and still
  // pick the nearest loop; 0 requires it to lie inside one.
  double root_max_distance = 0;
};

struct AxisTrace {
  std::vector<Vec3> points;     // axis points from root to tip end, area centroids of slice loops
  std::vector<Vec3> tangents;   // unit axis direction at each point
  std::vector<double> radii;    // equivalent radius of each point's loop, mesh units
  double root_loop_extent = 0;  // largest distance of the root loop from points[0], mesh units
  bool reached_tip = false;     // false: the part was lost before the tip (see stop_reason)
  std::string stop_reason;      // why the trace stopped, for messages
};

// Throws Error(bad_input) when no slice loop lies around the root (the root is not inside or
// near the mesh) or root and tip coincide.
AxisTrace trace_axis(const MeshSlicer& slicer, const Vec3& root, const Vec3& tip,
                     const TraceOptions& options = {});

// An axis given as a polyline from root to tip (at least 2 distinct points): tangents by central
// chords, radii of the slice loops around each point (0 where there is none), reached_tip true.
AxisTrace axis_from_polyline(const MeshSlicer& slicer, const std::vector<Vec3>& points);

// Arc length at each point of a polyline (0 at the first).
std::vector<double> arc_lengths(const std::vector<Vec3>& points);

// Rotation-minimizing frames along a polyline with unit tangents, by the double reflection method
// (Wang, Jüttler, Zheng & Liu 2008). The frame's third column is the tangent; the first frame's x
// axis is `x0` made perpendicular to the first tangent (or a deterministic choice when x0 is 0).
std::vector<Quat> rotation_minimizing_frames(const std::vector<Vec3>& points,
                                             const std::vector<Vec3>& tangents,
                                             const Vec3& x0 = Vec3::Zero());

}  // namespace sweep::fit
