#pragma once
// How far a part bends, span by span, over a bake, and whether it folds or passes through itself:
// what the report warns about (a part that whips over itself looks broken however right its
// physics).
//  - A span's bend: the angle by which section i's axis turned away from where section i−1 holds
//    it at rest (the deformed relative frame's axis against the rest's; twist left out).
//  - A fold: a span bent past 90°.
//  - Passing through itself: two sections' discs (centre, axis, mean radius) that cross, where
//    they did not at rest — the discs' chords along their planes' common line overlap. A cheap
//    test of the sweep, not of the mesh: it sees the tube pinch or two stretches of it meet
//    section on section, not a surface that grazes another between sections.
#include <vector>

#include "sweep/core/sweep_shape.h"

namespace sweep {

class FoldMeter {
 public:
  explicit FoldMeter(const SweepShape& rest);
  // Measures one pose of the part (same K and n as the rest), seen at `frame`.
  void measure(const SweepShape& deformed, int frame);

  double largest_bend = 0;  // rad, over every span and pose measured
  int bend_span = 0;        // the span (sections bend_span − 1 .. bend_span) where it was reached
  int bend_frame = 0;       // the first frame it was reached
  int fold_frame = -1;      // the first frame a span bent past 90° (−1: never)
  int fold_span = 0;
  int cross_frame = -1;  // the first frame two discs crossed (−1: never)
  int cross_a = 0, cross_b = 0;

 private:
  std::vector<Frame> rest_relative_;
  std::vector<double> mean_radius_;
  std::vector<char> crossed_at_rest_;  // K × K
  std::vector<double> radius_now_;     // the pose's mean radii (scratch)
};

// Whether the discs (centre, unit normal, radius) a and b cross.
bool discs_cross(const Vec3& ca, const Vec3& na, double ra, const Vec3& cb, const Vec3& nb, double rb);

}  // namespace sweep
