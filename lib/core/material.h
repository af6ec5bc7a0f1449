#pragma once
// A material for a sweep: instead of spring frequencies, the part's stiffness and mass
// follow from what it is made of and how big it is. Given per sweep, overridable per section.
#include <cmath>

namespace sweep {

struct Material {
  double youngs_modulus = 1e6;  // E, Pa. Rubber ~1e6–1e7, soft tissue ~1e4–1e6, wood ~1e10
  double poisson_ratio = 0.45;  // ν, used when shear_modulus is 0: G = E / (2 (1 + ν))
  double shear_modulus = 0;     // G, Pa; 0 = from E and ν
  double density = 1000;        // ρ, kg/m³ (water 1000, flesh ~1050)
  double metres_per_unit = 1;   // the mesh's scale: one mesh unit is this many metres
  double damping_ratio = 0.05;  // ζ of every bending and twisting mode (0 rings forever)

  double shear() const { return shear_modulus > 0 ? shear_modulus : youngs_modulus / (2 * (1 + poisson_ratio)); }
  bool operator==(const Material&) const = default;
};

}  // namespace sweep
