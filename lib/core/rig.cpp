#include "sweep/core/rig.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sweep/core/locate.h"

namespace sweep {

int SweepDef::section_index(const std::string& section_name) const {
  for (std::size_t i = 0; i < section_names.size(); ++i) {
    if (section_names[i] == section_name) return static_cast<int>(i);
  }
  return -1;
}

const SweepDef* Rig::find(const std::string& sweep_name) const {
  for (const SweepDef& s : sweeps) {
    if (s.name == sweep_name) return &s;
  }
  return nullptr;
}

SweepDef make_sweep(std::string name, SweepShape rest) {
  SweepDef def;
  def.name = std::move(name);
  const std::size_t k = rest.t.size();
  def.rest = std::move(rest);
  def.section_names.assign(k, "");
  def.springs.assign(k, def.default_springs);
  return def;
}

namespace {
double disc_radius(const SweepShape& rest, int section) {
  double largest = 0;
  for (const double r : rest.section_radii(section)) largest = std::max(largest, r);
  return kRootDiscRadii * largest;
}
}  // namespace

SweepShape without_narrow_lobes(const SweepShape& rest) {
  SweepShape out = rest;
  const int n = rest.radial_count;
  const int half = std::max(1, static_cast<int>(std::lround(n * kLobeWindowDegrees / 360)));
  std::vector<double> window(static_cast<std::size_t>(2 * half + 1));
  std::vector<Eigen::Vector2d> outline(static_cast<std::size_t>(n));
  std::vector<char> reflex(static_cast<std::size_t>(n));
  const auto at = [n](int j) { return static_cast<std::size_t>(((j % n) + n) % n); };
  for (int i = 0; i < rest.section_count(); ++i) {
    // The section's outline, its samples in turn; where it turns outwards (a reflex corner) a
    // lobe leaves the section. A convex outline (a circle, an ellipse however flat, a strip) has
    // no lobe, whatever its samples' median says.
    for (int j = 0; j < n; ++j) {
      const double theta = 2 * std::numbers::pi * j / n;
      outline[at(j)] = rest.radius_sample(i, j) * Eigen::Vector2d(std::cos(theta), std::sin(theta));
    }
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector2d a = outline[at(j)] - outline[at(j - 1)], b = outline[at(j + 1)] - outline[at(j)];
      const double lengths = a.norm() * b.norm();
      reflex[at(j)] = lengths > 0 && a.x() * b.y() - a.y() * b.x() < -kLobeBaseTurn * lengths;
    }
    for (int j = 0; j < n; ++j) {
      bool pinched = false;
      for (int d = 1; d <= half; ++d) pinched = pinched || reflex[at(j - d)] || reflex[at(j + d)];
      if (!pinched) continue;
      for (int d = -half; d <= half; ++d)
        window[static_cast<std::size_t>(d + half)] = rest.radius_sample(i, static_cast<int>(at(j + d)));
      std::nth_element(window.begin(), window.begin() + half, window.end());
      out.radii[static_cast<std::size_t>(i) * n + static_cast<std::size_t>(j)] =
          std::min(window[static_cast<std::size_t>(half)], rest.radius_sample(i, j));
    }
  }
  return out;
}

double root_disc_radius(const SweepShape& rest) {
  return disc_radius(rest, 0);
}
double tip_disc_radius(const SweepShape& rest) {
  return disc_radius(rest, rest.section_count() - 1);
}

std::vector<std::uint32_t> select_sweep_part(const Mesh& mesh, const Topology& topology, const SweepShape& rest,
                                             const PartSeeds& seeds) {
  const SweepLocator locator(rest);
  PartBound near_sweep;
  near_sweep.within = [&](const Vec3& p) {
    const SweepCoords c = locator.locate(p);
    if (c.z > 0) return true;  // past the tip section
    return c.s <= kPartReachRadii && -c.z <= kPartReachRadii * radius_at(rest, c.theta, c.t);
  };
  near_sweep.protrusion_reach = [&](const Vec3& p) {
    const SweepCoords c = locator.locate(p);
    return kProtrusionReachRadii * radius_at(rest, c.theta, c.t);
  };
  // Outwards, the part's surface is judged against the radii without their narrow lobes: a
  // neighbour fused alongside (a tusk) makes a lobe of the section towards it, which the fitted
  // radii follow as far as its foot is still in the part.
  const SweepShape lobeless = without_narrow_lobes(rest);
  near_sweep.on_surface = [&](const Vec3& p) {
    const SweepCoords c = locator.locate(p);
    if (c.z != 0) return true;
    if (c.s * radius_at(rest, c.theta, c.t) > (1 + kBridgeFootRadii) * radius_at(lobeless, c.theta, c.t)) return false;
    return std::abs(c.s - 1) <= kBridgeFootRadii;
  };
  if (seeds.tip_cut) {
    return select_part_between(mesh, topology, rest.frames.front(), root_disc_radius(rest), rest.frames.back(),
                               tip_disc_radius(rest), near_sweep);
  }
  // A tip before the root section (no section's plane passes by it) is refused by the walk
  // itself, which must then reach the root disc from behind: not bounded near the sweep.
  const bool tip_before_root =
      mesh.vertex_count() > 0 && locator.locate(mesh.positions[nearest_vertex(mesh, seeds.tip)]).z < 0;
  return select_part(mesh, topology, rest.frames.front(), root_disc_radius(rest), seeds.tip,
                     tip_before_root ? PartBound{} : near_sweep);
}

int Rig::format_version() const {
  if (!mesh_name.empty()) return kMeshNameFormatVersion;
  for (const SweepDef& def : sweeps) {
    if (def.part && def.part->tip_cut) return kTipCutFormatVersion;
  }
  return kFormatVersion;
}

}  // namespace sweep
