#pragma once
// The runtime: one elastic sweep (DESIGN.md §2.2–2.5). Load a SweepDef, add or remove forces,
// step(dt), read the deformed key frames and radii. No file or console I/O.
//
// Kinematics: the deformed frame of section i is M'_i = M'_{i-1} · T_{i-1,i} · D_i with
// D_i = [exp(φ_i) | x_i] acting in A_i = M'_{i-1}·T_{i-1,i}, i.e. about the section's own centre and in
// its own axes. Section 0 is the root, fixed to the body: it never moves. Springs are independent
// damped oscillators: 3 positional (x_i), 3 rotational (φ_i: bend about local x and y, twist about
// local z) and n radial (δ_i[j]: the deformed radius is r_i[j] + δ_i[j], floored at
// kMinRadiusFraction·r_i[j] so a handle can never invert its section).
#include <vector>

#include "core/force.h"
#include "core/oscillator.h"
#include "core/rig.h"

namespace sweep {

using ForceId = int;

class ElasticSweep {
 public:
  explicit ElasticSweep(SweepDef def);

  const SweepDef& definition() const { return def_; }
  const SweepShape& rest() const { return def_.rest; }
  const SweepShape& deformed() const { return deformed_; }  // current frames and radii

  // Forces act from now until removed; each is re-split every step at its point on the current
  // surface. A force given at a world point is projected to the current surface here, once.
  ForceId add_force(const ForceSpec& force);
  bool remove_force(ForceId id);
  void clear_forces();
  std::size_t force_count() const { return forces_.size(); }

  // An impulse (N·s): the same split as a force, applied at once as a change of velocity.
  void apply_impulse(const ForceSpec& impulse);

  void set_integrator(Integrator integrator) { integrator_ = integrator; }
  Integrator integrator() const { return integrator_; }

  // Advances the springs by dt seconds with every current force held over the step.
  void step(double dt);

  // Spring coordinates of section i (section 0 is always zero), settable for scripted poses.
  Vec3 section_offset(int i) const;
  Vec3 rotation_vector(int i) const;
  double radial_offset(int i, int j) const;
  void set_section_pose(int i, const Vec3& offset, const Vec3& rotation_vector);
  void set_radial_offset(int i, int j, double delta);
  void reset();  // back to rest, at rest, forces kept

  double energy() const;     // Σ ½ m v² + ½ k x² over every spring (force potential not counted)
  double max_speed() const;  // largest |v| over every spring coordinate
  double max_displacement() const;  // largest |x| over every spring coordinate
  bool is_finite() const;    // false once any state is NaN or Inf (a diverged integrator)

  // Which spring kinds have ever been driven (a kind never driven is not stepped).
  bool positional_active() const { return positional_.active; }
  bool rotational_active() const { return rotational_.active; }
  bool radial_active() const { return radial_.active; }

 private:
  // All oscillators of one kind, flat: coordinate c of section i at index i·width + c.
  struct Bank {
    int width = 0;
    std::vector<double> x, v, f;
    std::vector<OscillatorParams> params;
    std::vector<StepMap> maps;
    bool active = false;
  };
  struct ActiveForce {
    ForceId id;
    ForceSpec spec;
    double t, theta;
  };

  void init_bank(Bank& bank, int width, const SpringSettings& (*pick)(const SectionSprings&, int));
  void gather_loads(const std::vector<ActiveForce>& forces);
  void rebuild();

  SweepDef def_;
  SweepShape deformed_;
  std::vector<Frame> relative_;  // T_{i-1,i} (entry 0: identity)
  std::vector<Frame> pre_;       // A_i, the frame D_i acts in
  Bank positional_, rotational_, radial_;
  SectionLoads loads_;
  std::vector<ActiveForce> forces_;
  ForceId next_id_ = 1;
  Integrator integrator_ = Integrator::exact;
  double map_dt_ = 0;
  Integrator map_integrator_ = Integrator::exact;
};

}  // namespace sweep
