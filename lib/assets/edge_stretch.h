#pragma once
// The bake's quality figure: the largest edge stretch, deformed length / rest length,
// over the mesh's edges and the bake's frames, and where it is. A part torn from the surface beside
// it (a tube bound past its end) shows here first: its edges across the seam stretch many times.
//
//   EdgeStretchMeter meter(mesh, animated, rest);   // once: the edges that can change length
//   const EdgeStretch now = meter.measure(positions);  // each frame the shape changed
//
// Cheap enough for every bake: only edges with an animated end are kept (the others never change),
// and a frame is one pass over them (on the diplodocus' Fig. 4 bake: BENCHMARKS.md).
#include <cstdint>
#include <span>
#include <vector>

#include "sweep/bind/fast_deform.h"
#include "sweep/core/mesh.h"

namespace sweep::assets {

struct EdgeStretch {
  double ratio = 1;     // deformed length / rest length of the worst edge; 1 when none changed
  std::uint32_t a = 0;  // that edge's vertices (file indices, a < b); meaningful when found
  std::uint32_t b = 0;
  bool found = false;  // some edge stretched (ratio > 1)
};

class EdgeStretchMeter {
 public:
  // The mesh's polygon edges (each once, a < b, ascending) with an end among `animated` and a
  // rest length > 0 in `rest` (the positions frames are measured against).
  EdgeStretchMeter(const Mesh& mesh, std::span<const std::uint32_t> animated, std::span<const bind::Vec3f> rest);
  // The edge that stretched most in `positions` (the first in edge order among equals).
  EdgeStretch measure(std::span<const bind::Vec3f> positions) const;
  std::size_t edge_count() const { return a_.size(); }

 private:
  std::vector<std::uint32_t> a_, b_;
  std::vector<double> rest_squared_;  // rest length², mesh units²
};

}  // namespace sweep::assets
