#pragma once
// Material mode: a sweep's sections as one chain of hinges, linearised at
// the rest pose, M q̈ + C q̇ + K q = τ over the joints' rotation vectors q (3 per movable section,
// in its own axes: bend about x, bend about y, twist about z). Joint j sits at section j's centre
// and turns everything beyond it, so M is dense: the mass beyond a joint loads it.
//  - Node masses and rotary inertias: span masses ρ A h lumped half to each end section (the root's
//    half stays with the body); rotary inertia ρ I ℓ about the section's axes.
//  - Joint stiffnesses: E I_xx / ℓ, E I_yy / ℓ with ℓ the length the joint stands for in bending:
//    half of each span beside it, and the whole first span for joint 1 (nothing bends at the fixed
//    root), so the static tip deflection is a quadrature of ∫ M(s)(L − s)/EI ds with O(h²) error;
//    G J / h with h the span before the joint, so the twist at each section is the sum of its spans'
//    (O(h²) in frequency; the half-span rule made it O(h): −1.6% at K = 32, now −0.01%).
//  - Section properties from each section's polygon (core/section_properties.h), lengths in metres
//    (mesh units × metres_per_unit).
// The modes (K φ = ω² M φ, M-orthonormal) are computed once; each is a damped oscillator stepped
// in closed form. Positional springs stay independent: stretch E A / ℓ and shear κ G A / ℓ on the
// mass beyond the joint. Radial handles: each moves the wedge of its section around it (k = E π h / n,
// moving mass ρ π r² h / 2n; chain_model.cpp says why).
#include <Eigen/Dense>
#include <vector>

#include "sweep/core/material.h"
#include "sweep/core/oscillator.h"
#include "sweep/core/sweep_shape.h"

namespace sweep {

// Timoshenko's shear coefficient for a solid, roughly round section.
inline constexpr double kShearCoefficient = 0.9;

struct ChainModel {
  int joints = 0;  // K − 1 (sections 1 .. K−1)
  double metres_per_unit = 1;
  Eigen::MatrixXd mass;               // 3·joints square: kg·m²
  Eigen::MatrixXd stiffness;          // 3·joints square, block diagonal: N·m/rad
  Eigen::VectorXd compliance;         // K⁻¹'s diagonal, rad/(N·m): K is diagonal (independent springs)
  Eigen::MatrixXd modes;              // Φ: columns M-orthonormal (Φᵀ M Φ = I), by growing frequency
  Eigen::VectorXd omega2;             // ω² of each mode, rad²/s²
  std::vector<double> damping_ratio;  // ζ of each mode
  std::vector<double> node_mass;      // kg, K entries (0 for the root)
  std::vector<Vec3> node_inertia;     // kg·m², K entries: rotary inertia about the section's own axes
  // Positional springs of each section (3 per section, its own axes), in mesh units: kg·(m/unit)
  // and N/unit, so that displacements stay in mesh units.
  std::vector<OscillatorParams> positional;
  // Radial springs, K·n entries (section-major), in mesh units as the positional ones.
  std::vector<OscillatorParams> radial;
  // The length of the part each section stands for (half of each span beside it), metres.
  std::vector<double> section_length;
};

// `materials` has one entry per section (the sweep's, overrides applied).
ChainModel build_chain_model(const SweepShape& rest, const std::vector<Material>& materials);

}  // namespace sweep
