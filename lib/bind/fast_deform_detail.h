#pragma once
// What the three parts of the fast deformation path share (not installed): the layout of a
// station row (written by fast_deform_stations.cpp, read by fast_deform_kernel.cpp) and the
// padding of the per-vertex arrays (allocated by fast_deform_layout.cpp, read past the end by the
// kernel).
#include <cstddef>

namespace sweep::bind::detail {

// Station row layout: centre, the three frame axes, then 4 cubic coefficients per angle cell.
inline constexpr int kCenter = 0, kAxisX = 3, kAxisY = 6, kAxisZ = 9, kCells = 12;

// The radii loop runs in whole vectors of kPad floats (AVX2's 8; baseline's 4 divides it), so a
// short angle-cell segment costs no scalar remainder (BENCHMARKS.md, section "Layout and
// thread thresholds"); u_ and w_ carry kPad floats of padding for the reads past the end.
inline constexpr std::ptrdiff_t kPad = 8;

}  // namespace sweep::bind::detail
