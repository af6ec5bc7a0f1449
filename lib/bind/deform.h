#pragma once
// Deforming a mesh from a binding and the sweeps' current shapes: the exact per-vertex path of
// the paper's §III (deform_point on each bound vertex), the reference a faster station-sampled path
// is measured against. For a vertex bound to sweep i with coordinates c and blend weight w,
//     out = rest + w·(deform_point(deformed[i], c) − rest);
// unbound vertices are copied from rest. Parallel over vertices (OpenMP); results do not depend
// on the thread count.
#include <span>

#include "sweep/bind/bind.h"

namespace sweep::bind {

// `deformed_per_sweep` has one shape per binding sweep, in the same order (e.g.
// ElasticSweep::deformed(), or the rig's rest shapes for the rest pose); `rest_positions` and
// `out` have binding.vertex_count entries and must not overlap.
void deform_exact(const Binding& binding, std::span<const SweepShape> deformed_per_sweep,
                  std::span<const Vec3> rest_positions, std::span<Vec3> out);

// The same with the shapes given by pointer (one per binding sweep), for callers that hold the
// shapes inside other objects (ElasticSweep).
void deform_exact(const Binding& binding, std::span<const SweepShape* const> deformed_per_sweep,
                  std::span<const Vec3> rest_positions, std::span<Vec3> out);

// Largest distance, over one sweep's bound vertices, between the vertex and its position rebuilt
// from the stored coordinates on `shape` (no blend), mesh units. On the rest shape it measures how
// exactly the binding reproduces the mesh.
double max_rebuild_error(const SweepBinding& table, const SweepShape& shape, std::span<const Vec3> positions);

}  // namespace sweep::bind
