#include "sweep/core/oscillator.h"

#include <cmath>

namespace sweep {

std::string_view integrator_name(Integrator integrator) {
  switch (integrator) {
    case Integrator::exact:
      return "exact";
    case Integrator::semi_implicit_euler:
      return "semi-implicit-euler";
    case Integrator::rk4:
      return "rk4";
  }
  return "exact";
}

bool parse_integrator(std::string_view name, Integrator* out) {
  for (Integrator i : {Integrator::exact, Integrator::semi_implicit_euler, Integrator::rk4}) {
    if (integrator_name(i) == name) {
      *out = i;
      return true;
    }
  }
  return false;
}

namespace {

// Closed form. With α = c/2m, ω² = k/m, β² = ω² − α², the free motion is
//   x(t) = Ec·x0 + Es·(v0 + α x0),   v(t) = Ec·v0 − Es·(α v0 + ω² x0),
// where Ec = e^{-αt}·C(t), Es = e^{-αt}·S(t), C'' = −β² C, C(0) = 1, S(0) = 0, S'(0) = 1.
// Ec and Es are computed in a form that neither overflows (cosh·e^{-αt} for heavy damping) nor
// cancels (near critical damping, S → t); the forced response is x_eq = f/k plus the free motion
// of x − x_eq.
void damped_kernels(const OscillatorParams& p, double t, double* ec, double* es) {
  const double alpha = p.damping / (2 * p.mass);
  const double omega2 = p.stiffness / p.mass;
  const double zeta = alpha / std::sqrt(omega2);
  // β² = ω²(1 − ζ)(1 + ζ): this product keeps its relative accuracy near ζ = 1.
  const double beta2 = omega2 * (1 - zeta) * (1 + zeta);
  if (beta2 > 0) {  // under-damped
    const double beta = std::sqrt(beta2);
    const double decay = std::exp(-alpha * t);
    *ec = decay * std::cos(beta * t);
    *es = decay * std::sin(beta * t) / beta;
  } else if (beta2 < 0) {  // over-damped: e^{-αt}cosh(γt) = ½(e^{-(α−γ)t} + e^{-(α+γ)t})
    const double gamma = std::sqrt(-beta2);
    const double slow = omega2 / (alpha + gamma);  // α − γ without cancellation
    const double e_slow = std::exp(-slow * t);
    const double m = std::expm1(-2 * gamma * t);  // e^{-2γt} − 1
    *ec = e_slow * (1 + 0.5 * m);
    *es = e_slow * (-m) / (2 * gamma);
  } else {  // critical
    const double decay = std::exp(-alpha * t);
    *ec = decay;
    *es = t * decay;
  }
}

StepMap exact_map(const OscillatorParams& p, double dt) {
  double ec = 0, es = 0;
  damped_kernels(p, dt, &ec, &es);
  const double alpha = p.damping / (2 * p.mass);
  const double omega2 = p.stiffness / p.mass;
  StepMap m;
  m.xx = ec + alpha * es;
  m.xv = es;
  m.vx = -omega2 * es;
  m.vv = ec - alpha * es;
  // x' = x_eq + xx (x − x_eq) + xv v, v' = vx (x − x_eq) + vv v with x_eq = f/k.
  m.xf = (1 - m.xx) / p.stiffness;
  m.vf = es / p.mass;
  return m;
}

StepMap semi_implicit_euler_map(const OscillatorParams& p, double dt) {
  StepMap m;
  m.vx = -dt * p.stiffness / p.mass;
  m.vv = 1 - dt * p.damping / p.mass;
  m.vf = dt / p.mass;
  m.xx = 1 + dt * m.vx;
  m.xv = dt * m.vv;
  m.xf = dt * m.vf;
  return m;
}

// RK4 on the linear system is linear in (x, v, f): run one step on each unit input to get the map.
StepMap rk4_map(const OscillatorParams& p, double dt) {
  auto step = [&](double x, double v, double f, double* x1, double* v1) {
    auto acc = [&](double xx, double vv) { return (f - p.damping * vv - p.stiffness * xx) / p.mass; };
    const double k1x = v, k1v = acc(x, v);
    const double k2x = v + 0.5 * dt * k1v, k2v = acc(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v);
    const double k3x = v + 0.5 * dt * k2v, k3v = acc(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v);
    const double k4x = v + dt * k3v, k4v = acc(x + dt * k3x, v + dt * k3v);
    *x1 = x + dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    *v1 = v + dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
  };
  StepMap m;
  step(1, 0, 0, &m.xx, &m.vx);
  step(0, 1, 0, &m.xv, &m.vv);
  step(0, 0, 1, &m.xf, &m.vf);
  return m;
}

}  // namespace

StepMap make_step_map(const OscillatorParams& p, double dt, Integrator integrator) {
  switch (integrator) {
    case Integrator::exact:
      return exact_map(p, dt);
    case Integrator::semi_implicit_euler:
      return semi_implicit_euler_map(p, dt);
    case Integrator::rk4:
      return rk4_map(p, dt);
  }
  return exact_map(p, dt);
}

}  // namespace sweep
