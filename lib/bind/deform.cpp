#include "sweep/bind/deform.h"

#include <algorithm>
#include <cassert>

#include "sweep/core/deform_point.h"

namespace sweep::bind {

void deform_exact(const Binding& binding, std::span<const SweepShape* const> deformed_per_sweep,
                  std::span<const Vec3> rest_positions, std::span<Vec3> out) {
  assert(deformed_per_sweep.size() == binding.sweeps.size());
  assert(rest_positions.size() == binding.vertex_count && out.size() == binding.vertex_count);
  std::copy(rest_positions.begin(), rest_positions.end(), out.begin());
  for (std::size_t i = 0; i < binding.sweeps.size(); ++i) {
    const SweepBinding& table = binding.sweeps[i];
    const SweepShape& shape = *deformed_per_sweep[i];
    const auto count = static_cast<std::ptrdiff_t>(table.size());
#pragma omp parallel for schedule(static) if (count >= kMinParallelVertices)
    for (std::ptrdiff_t k = 0; k < count; ++k) {
      const std::uint32_t v = table.vertices[k];
      const Vec3 moved = deform_point(shape, table.coords(static_cast<std::size_t>(k)));
      const double w = table.weight[k];
      out[v] = w == 1 ? moved : Vec3(rest_positions[v] + w * (moved - rest_positions[v]));
    }
  }
}

void deform_exact(const Binding& binding, std::span<const SweepShape> deformed_per_sweep,
                  std::span<const Vec3> rest_positions, std::span<Vec3> out) {
  std::vector<const SweepShape*> shapes;
  shapes.reserve(deformed_per_sweep.size());
  for (const SweepShape& s : deformed_per_sweep) shapes.push_back(&s);
  deform_exact(binding, std::span<const SweepShape* const>(shapes), rest_positions, out);
}

double max_rebuild_error(const SweepBinding& table, const SweepShape& shape, std::span<const Vec3> positions) {
  double worst = 0;
  const auto count = static_cast<std::ptrdiff_t>(table.size());
#pragma omp parallel for reduction(max : worst) schedule(static) if (count >= kMinParallelVertices)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    const Vec3 rebuilt = deform_point(shape, table.coords(static_cast<std::size_t>(k)));
    worst = std::max(worst, (rebuilt - positions[table.vertices[k]]).norm());
  }
  return worst;
}

}  // namespace sweep::bind
