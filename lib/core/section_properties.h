#pragma once
// Properties of one key cross-section's polygon, from its n radius samples: the
// vertices are p_j = r_j (cos θ_j, sin θ_j) with θ_j = 2πj/n, in the section's own x, y axes.
// Lengths in whatever unit the radii are given in (multiply by the mesh scale first for metres).
#include <span>

namespace sweep {

struct SectionProperties {
  double area = 0;                        // A (length²)
  double centroid_x = 0, centroid_y = 0;  // offset of the centroid from the section centre
  double i_xx = 0;                        // ∫ y² dA about the centroid: resists bending about the section's x axis
  double i_yy = 0;                        // ∫ x² dA about the centroid: resists bending about y
  double i_xy = 0;                        // ∫ x y dA about the centroid (0 for a section symmetric about an axis)
  double polar = 0;                       // I_p = I_xx + I_yy: the twist's rotary inertia per density and length
  double torsion = 0;                     // J: I_p for a circle, A⁴ / (4π² I_p) (Saint-Venant) otherwise
};

// `radii` must hold n ≥ 3 positive samples.
SectionProperties section_properties(std::span<const double> radii);

}  // namespace sweep
