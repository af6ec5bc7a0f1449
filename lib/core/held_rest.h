#pragma once
// Whether a material part's as-modelled rest holds under gravity. "As modelled"
// (ElasticSweep::set_gravity, pre-loaded) takes the mesh as the pose under gravity: the joints'
// springs are pre-loaded so that it is an equilibrium, to the last bit by construction. Whether it
// is a stable one is physics. A part held level carries its own weight's bending moment, which its
// unloaded shape must supply: that shape curls up by about β/6 rad at the tip (β = q L³ / E I, the
// weight against the bending stiffness). Twist such a part a little and that moment turns with
// its sections and bends it sideways, and its weight's moment about the bent axis twists it
// further: the lateral–torsional buckling of a cantilever under its own weight, with the section
// kept straight in its plane (here by its curled unloaded shape), which sets in at
// q L³ = 12.85 √(E I · G J) (Timoshenko & Gere; β = 10.7 for a round section at ν = 0.45).
// Past it the held pose is a saddle: nudged, the part rolls over sideways and sags with its curl
// hanging down. A part standing up from its root (a neck raised, a stem) buckles likewise under
// its weight (Greenhill's column, q L³ = 7.84 E I).
//
// The check: the tangent stiffness of the exact chain's static residual (ChainDynamics::
// static_residual) at the held pose, K + G, by central differences — K the joints' springs, G the
// geometric stiffness of gravity and of the springs' pre-load, neither of which depends on the
// material's stiffness (the pre-load is the weight's moment). The pose holds when K + G is
// positive definite, i.e. when every eigenvalue of −G v = f K v is below 1: the largest, the load
// factor f, says how many times stiffer the part must be for it to hold (E × f). Cost: 6(K−1)
// Newton–Euler passes and two dense eigen-solves of 3(K−1), about what the chain's modes cost.
#include "sweep/core/chain_model.h"
#include "sweep/core/rig.h"

namespace sweep {

struct HeldRest {
  // λ_max(−G, K): the held pose holds when it is below 1 (and the part would need E × load_factor
  // to hold when it is not). ≤ 0: gravity stiffens the pose (a part hanging down).
  double load_factor = 0;
  // The lowest eigenvalue μ of (K + G) v = μ M v at the held pose, 1/s²: ω² of the slowest sway
  // about it, or, negative, the square of the undamped rate a nudge grows at.
  double lowest = 0;
  // Unstable: the rate (1/s) the nudge grows at, e^{rt}, with the joints' damping (r² + c r + μ = 0,
  // c the damping of the unstable mode); 0 when the pose holds.
  double growth_rate = 0;
  // q L³ / E I: the part's mean weight per length q (N/m), length L (m), and E I (N·m²) of its
  // first section, about its weaker axis. What the warning names; the verdict is the load factor's.
  double beta = 0;
  bool holds() const { return load_factor < 1; }
};

// `gravity` m/s² in the rig's axes (the body's at the start); `model` built for def's rest shape
// and materials (material mode).
HeldRest held_rest(const SweepDef& def, const ChainModel& model, const Vec3& gravity);

// A part whose Young's modulus was solved for a sway frequency (a preset's) can be too weak to
// hold the pose it was modelled in: a raised neck buckles as a column, a level tail rolls over.
// Raises the Young's modulus of `def`'s material (and of every section's: they must all be the
// material's, with G from ν) so that the held pose's load factor under `gravity` (m/s², the rig's
// axes) is `largest_load_factor` when it was above. The load factor goes as 1/E — the springs
// scale with E, gravity's and the pre-load's geometric stiffness do not — so one check sizes E.
// Returns the held rest as the part was given (its load factor ≤ largest: nothing changed).
HeldRest stiffen_to_hold(SweepDef& def, const Vec3& gravity, double largest_load_factor);

}  // namespace sweep
