#pragma once
// A picture of a fit, to look at before baking: the mesh from three sides (front, side, top), each
// fitted part tinted, its axis drawn through it and its key sections drawn around it. A small
// software renderer (orthographic, flat shading, a depth buffer): no window, no GPU, the same
// pixels on every machine.
#include <cstdint>
#include <vector>

#include "sweep/core/mesh.h"
#include "sweep/core/sweep_shape.h"

namespace sweep::preview {

// Pixels, row by row from the top, three bytes (R, G, B) each.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
};

// One fitted part to draw over the mesh.
struct Overlay {
  std::vector<std::uint32_t> vertices;   // the part's vertices (tinted)
  std::vector<Vec3> axis;                // the axis, root to tip (a line drawn on top)
  std::vector<std::vector<Vec3>> rings;  // each key section's outline (closed loops)
};

// Each key section's outline on the sweep surface, `samples` points a loop.
std::vector<std::vector<Vec3>> section_outlines(const SweepShape& shape, int samples = 48);

// The views, left to right: front (looking along -Z), side (along -X), top (along -Y); +Y is up
// in the first two. All three share one scale. `view_size` is each view's width and height in
// pixels (32 to 4096).
Image render_views(const Mesh& mesh, const std::vector<Overlay>& parts, int view_size = 400);

}  // namespace sweep::preview
