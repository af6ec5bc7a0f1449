#pragma once
// One damped linear oscillator m ẍ + c ẋ + k x = f (the paper's §II, Fig. 1), with the force held constant
// over each step. Every integrator offered is, for this linear system, an affine map of (x, v, f):
//   x' = xx·x + xv·v + xf·f,   v' = vx·x + vv·v + vf·f.
// So each integrator is just a different way to fill a StepMap (computed once per parameter set
// and dt), and stepping thousands of oscillators is one flat loop, whichever integrator was chosen.
#include <string_view>

namespace sweep {

enum class Integrator {
  exact,                // closed-form solution for a force held over the step: stable for every dt
  semi_implicit_euler,  // v += dt·a(x, v); x += dt·v — first order, unstable for dt > 2/ω
  rk4,                  // classical Runge–Kutta, fourth order, unstable for large ω·dt
};
std::string_view integrator_name(Integrator integrator);
bool parse_integrator(std::string_view name, Integrator* out);

struct OscillatorParams {
  double mass = 1;       // m > 0
  double damping = 0;    // c ≥ 0
  double stiffness = 1;  // k > 0
};

struct StepMap {
  double xx = 1, xv = 0, xf = 0;
  double vx = 0, vv = 1, vf = 0;

  void apply(double& x, double& v, double f) const {
    const double x1 = xx * x + xv * v + xf * f;
    const double v1 = vx * x + vv * v + vf * f;
    x = x1;
    v = v1;
  }
};

StepMap make_step_map(const OscillatorParams& p, double dt, Integrator integrator);

// The spring's energy ½ m v² + ½ k x² (with the force off).
inline double oscillator_energy(const OscillatorParams& p, double x, double v) {
  return 0.5 * p.mass * v * v + 0.5 * p.stiffness * x * x;
}

}  // namespace sweep
