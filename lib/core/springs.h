#pragma once
// Spring settings as an artist reasons about them (the Jolt way): a natural frequency in Hz and a
// damping ratio, plus the mass that the force acts on. The raw m, c, k follow from these.
#include <cmath>
#include <numbers>

namespace sweep {

struct SpringSettings {
  double mass = 1.0;           // kg; for rotational springs the moment of inertia, kg·m²
  double frequency_hz = 1.5;   // undamped natural frequency f0 (> 0). Higher = stiffer, faster wobble
  double damping_ratio = 0.3;  // ζ ≥ 0: 0 rings forever, 1 = critical (no overshoot), > 1 sluggish

  double stiffness() const {  // k = m (2π f0)²
    const double w = 2.0 * std::numbers::pi * frequency_hz;
    return mass * w * w;
  }
  double damping() const {  // c = 2 ζ m ω0
    return 2.0 * damping_ratio * mass * 2.0 * std::numbers::pi * frequency_hz;
  }
  bool operator==(const SpringSettings&) const = default;
};

// The four oscillator kinds of one key section (the paper's §II, Fig. 1). Rotation is a rotation vector φ in
// the section's own frame: bend springs act about its local x and y axes, twist about its axis z.
struct SectionSprings {
  SpringSettings positional{1.0, 1.5, 0.3};
  SpringSettings bend{1.0, 1.5, 0.3};
  SpringSettings twist{1.0, 2.0, 0.3};
  SpringSettings radial{1.0, 3.0, 0.4};
  bool operator==(const SectionSprings&) const = default;
};

}  // namespace sweep
