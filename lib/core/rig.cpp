#include "core/rig.h"

#include <algorithm>

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

double root_disc_radius(const SweepShape& rest) {
  double largest = 0;
  for (const double r : rest.section_radii(0)) largest = std::max(largest, r);
  return kRootDiscRadii * largest;
}

}  // namespace sweep
