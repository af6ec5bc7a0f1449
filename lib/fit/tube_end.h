#pragma once
// An end that is not a tube: a foot spreading sideways from a leg, a hoof, a tuft. A
// sweep fitted through it is far off there alone; the fitter (fit.cpp, step 4b) ends the sweep
// where the tube does and carries the vertices past it rigidly, as a head is carried.
#include <cstddef>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "sweep/core/sweep_shape.h"

namespace sweep::fit {

// A traced fit is cut where the run of spans at its tip end whose RMS distance exceeds this share
// of the error limit (FitOptions::max_error) begins, when that run is at most this share of the
// sweep's length and the vertices before it are within the limit. The cut fit is kept only if it meets every
// limit, fits better than the uncut one, and its part, now carried past the last section, gains at
// most FitOptions::max_leak_share of the vertices it had (an end that is closed off: not a hand
// fused to the hip, whose walk past the wrist would go on into the body). Measured per vertex on
// camel.off's hind leg (refused at 9.2 % RMS): 98 % of the squared error lay in the last fifth of
// t, the foot (spans 5-15 % RMS each), every span before it 0-2 %.
inline constexpr double kEndCutSpanShare = 0.5;
inline constexpr double kMaxEndCutShare = 1.0 / 3;
// ... and only where the key sections are at most this many mean radii apart: farther, a span's
// error is the sections' spacing, not the shape (diplodocus's tail at K = 4 has ends 5 % off).
inline constexpr double kMaxEndCutSpacingRadii = 2;
// The run goes on over fitting stretches no longer than this many mean radii (a toe's gap; as
// long as the longest span the cut is tried with, so that one fitting span never ends it), and
// must begin within it of the tip.
inline constexpr double kMaxEndGapRadii = kMaxEndCutSpacingRadii;

struct TubeEnd {
  int first_section = 0;  // the first key section of the end's run of spans off the tube
  double t = 0;           // its axis parameter: the sweep ends there
  double share = 0;       // the share of the sweep's length past it
  double end_rms = 0;     // the measured vertices' RMS distance past it, and before it
  double before_rms = 0;
  std::size_t end_count = 0;  // vertices measured past it
};

// Where the tube ends, from each measured part vertex's (t, distance to the sweep): the run of
// spans at the tip end whose RMS exceeds kEndCutSpanShare × `limit` (going on over spans with no
// vertex and over fitting stretches shorter than kMaxEndGapRadii mean radii), when it begins past
// (1 − kMaxEndCutShare) of the length, the sections are at most kMaxEndCutSpacingRadii ×
// `mean_radius` apart, and the vertices before it are within `limit` at the 90th percentile. None
// when the end is a tube or cannot be told.
std::optional<TubeEnd> find_tube_end(const SweepShape& shape, std::span<const std::pair<double, double>> along,
                                     double limit, double mean_radius);

// An end find_tube_end does not take (longer than kMaxEndCutShare, sections farther apart: a
// head turned across the neck, a hand clicked at a fingertip), for a fit that breaks the error
// limit `limit`: cuts at the first span, from the root on, whose RMS exceeds kEndCutSpanShare ×
// `limit`, then at each of up to kMaxWideEndSteps sections before it (none before section 1),
// to be tried in that order. Empty when no span is off the tube.
inline constexpr int kMaxWideEndSteps = 3;
std::vector<TubeEnd> wide_end_cuts(const SweepShape& shape, std::span<const std::pair<double, double>> along,
                                   double limit);

// The value a tenth of the distances exceed (nth_element: linear, reorders the copy it is given).
double percentile_90(std::vector<double> distances);

}  // namespace sweep::fit
