#pragma once
// The fast deformation path (DESIGN.md §4, §6). Each frame the moving sweep is evaluated once at
// `stations_per_span` stations per span (centre, axes and the radii at the n sample angles); each
// bound vertex is then rebuilt from the two stations around it by linear interpolation in t and
// the same periodic Catmull-Rom in θ as the exact path, in one flat, allocation-free loop over
// structure-of-arrays float data.
//
// Layout is deliberate: vertices are grouped by station span at construction, so the two stations
// a vertex needs are loop invariants of its group (broadcast, no gathers), and the per-vertex data
// is only what the loop reads. A permutation (`vertex_`) writes results back in mesh order.
// Results do not depend on the thread count: every vertex is computed independently.
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "bind/bind.h"
#include "core/sweep_shape.h"

namespace sweep::sim {

using Vec3f = Eigen::Vector3f;

// Below this many vertices the loop runs on one thread: waking a thread team costs tens of µs on
// these machines (DESIGN.md §6), more than the loop itself.
inline constexpr std::size_t kParallelVertexThreshold = 40000;

class FastDeformer {
 public:
  // `rest_positions` is the whole mesh in float (blend-zone vertices need their rest position).
  FastDeformer(const SweepShape& rest, const bind::SweepBinding& bound, std::span<const Vec3f> rest_positions,
               int stations_per_span = 8);

  // Writes the deformed positions of this sweep's vertices into `out` (the whole mesh, mesh order).
  void deform(const SweepShape& deformed, std::span<Vec3f> out);

  std::size_t vertex_count() const { return vertex_.size(); }
  int station_count() const { return static_cast<int>(station_t_.size()); }

 private:
  void tabulate(const SweepShape& shape);

  int n_ = 0;                       // radial samples
  int row_ = 0;                     // floats per station: 12 (C, X, Y, Z) + n + 3 padded radii
  std::vector<double> station_t_;   // parameter of each station
  std::vector<float> stations_;     // row_ floats a station, rewritten each frame
  std::vector<double> radii_scratch_;

  // Per vertex, grouped by station span (group g = vertices [group_begin_[g], group_begin_[g+1])).
  std::vector<std::uint32_t> group_begin_;
  std::vector<std::uint32_t> vertex_;  // mesh index
  std::vector<float> u_;               // position between the span's two stations, [0, 1]
  std::vector<float> a_, b_, z_;       // s·cos θ, s·sin θ, axial offset
  std::vector<float> c0_, c1_, c2_, c3_;  // Catmull-Rom weights in θ
  std::vector<std::uint16_t> j_;          // first of the 4 padded radii the weights apply to
  // Blend-zone vertices (weight < 1): indices into the arrays above, with weight and rest position.
  std::vector<std::uint32_t> blend_index_;
  std::vector<float> blend_weight_;
  std::vector<Vec3f> blend_rest_;
  float radius_floor_ = 0;
};

}  // namespace sweep::sim
