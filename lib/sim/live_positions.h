#pragma once
// The world-space vertices a live frame hands an engine (libsweep's sweep_positions): every vertex
// of the mesh, the parts' deformed by the fast path, the rest carried rigidly by the body.
//
// Laid out for a frame whose caches went cold since the last one (a game's frame, 1/60 s apart):
// each part's deformed vertices are kept in its fast path's grouped order (FastDeformer::
// deform_grouped: contiguous stores, where deforming into a mesh-order copy stores at scattered
// places of a mesh-sized array that has gone cold), and the world copy is two passes: every vertex
// from its rest position, streamed (the bound ones too: a mesh's parts' vertices lie scattered, the
// diplodocus's in ~6000 runs of its 24k vertices, and skipping them costs more than it saves), then
// the parts' vertices from their small arrays over them, into lines the first pass just brought
// into cache. (One pass reading each vertex through an index was slower still.) The first pass
// runs as a banded product over the flat floats (five shifted vector loads, no shuffles: half the
// instructions of the x y z loop). The result is the same floats as deforming into a mesh-order
// copy and transforming that (bind::deform_sweeps, bind::transform_positions), bit for bit but for
// the sign of a zero coordinate.
//
// An engine that draws the mesh under the body's transform itself takes the vertices in the mesh's
// own space instead (local, bound): no product at all, and the vertices no part binds are then
// their rest positions, which never change — bound() hands over the parts' vertices alone, in
// the order of bound_indices(), as the block they are kept in (a copy, no scatter).
//
// A part not deformed yet holds its vertices' rest positions. Allocation-free after construction.
// The rest positions are read-only and may be shared by many (a crowd of one creature: one copy,
// which stays in cache from one creature's frame to the next).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "sweep/bind/fast_deform.h"

namespace sweep::sim {

class LivePositions {
 public:
  // `rest`: the whole mesh; `parts`: each part's fast path (their vertices disjoint).
  LivePositions(std::span<const bind::Vec3f> rest, std::span<const bind::FastDeformer* const> parts);
  // The same, reading the rest positions from `rest` (not copied; shared).
  LivePositions(std::shared_ptr<const std::vector<bind::Vec3f>> rest, std::span<const bind::FastDeformer* const> parts);

  // Part p's vertices deformed by `shape` (mesh space), with `fast`, the part's fast path.
  void deform(int part, bind::FastDeformer& fast, const SweepShape& shape);
  // Every vertex, world = rotation · mesh + translation, as flat x y z floats (3 × rest.size()).
  void world(const Eigen::Matrix3f& rotation, const bind::Vec3f& translation, float* out) const;
  // Every vertex in the mesh's space (world = rotation · these + translation), as flat x y z floats:
  // the unbound ones their rest positions, the bound ones as deformed.
  void local(float* out) const;
  // The bound vertices in the mesh's space, each part's in its grouped order, the parts in order;
  // bound_indices()[i] is the mesh index of bound()[i] (fixed from construction on).
  std::span<const bind::Vec3f> bound() const { return points_; }
  std::span<const std::uint32_t> bound_indices() const { return target_; }

 private:
  std::shared_ptr<const std::vector<bind::Vec3f>> rest_;  // every vertex
  std::vector<bind::Vec3f> points_;                       // each part's deformed vertices in its grouped order
  std::vector<std::size_t> offset_;                       // part p's first in points_
  std::vector<std::uint32_t> target_;                     // the mesh index of each vertex in points_
  mutable std::vector<bind::Vec3f> world_points_;         // scratch of world(): points_ carried by the body
};

}  // namespace sweep::sim
