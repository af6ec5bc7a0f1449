// Integration: the exact integrator against the textbook damped oscillator, step counts, the
// convergence order of semi-implicit Euler, and stability at extreme parameters.
#include "sweep/core/oscillator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace sweep {
namespace {

// Textbook solution of m ẍ + c ẋ + k x = f from (x0, v0), written per regime in long double and
// independently of the library's formulation.
struct Exact {
  long double x, v;
};
Exact textbook(const OscillatorParams& p, long double x0, long double v0, long double f, long double t) {
  const long double m = p.mass, c = p.damping, k = p.stiffness;
  const long double alpha = c / (2 * m), w2 = k / m, xe = f / k, a = x0 - xe;
  const long double disc = alpha * alpha - w2;
  if (std::fabs(disc) <= 1e-15L * w2) {  // critical
    const long double b = v0 + alpha * a, e = std::exp(-alpha * t);
    return {xe + e * (a + b * t), e * (b - alpha * (a + b * t))};
  }
  if (disc < 0) {  // under-damped: x − xe = e^{−αt}(A cos βt + B sin βt)
    const long double beta = std::sqrt(-disc), b = (v0 + alpha * a) / beta, e = std::exp(-alpha * t);
    const long double cs = std::cos(beta * t), sn = std::sin(beta * t);
    return {xe + e * (a * cs + b * sn), e * ((-alpha * a + beta * b) * cs + (-alpha * b - beta * a) * sn)};
  }
  // over-damped: x − xe = C1 e^{λ1 t} + C2 e^{λ2 t}
  const long double g = std::sqrt(disc), l1 = -alpha + g, l2 = -alpha - g;
  const long double c1 = (v0 - l2 * a) / (l1 - l2), c2 = a - c1;
  return {xe + c1 * std::exp(l1 * t) + c2 * std::exp(l2 * t), c1 * l1 * std::exp(l1 * t) + c2 * l2 * std::exp(l2 * t)};
}

OscillatorParams with_ratio(double mass, double frequency_hz, double zeta) {
  const double w = 2 * M_PI * frequency_hz;
  return {mass, 2 * zeta * mass * w, mass * w * w};
}

struct Regime {
  const char* name;
  double zeta;
};
const Regime kRegimes[] = {{"undamped", 0.0}, {"under", 0.2}, {"critical", 1.0}, {"over", 3.5}};

// Step response then release: force f from t = 0 to t_off, none after; compare on every step with
// the piecewise textbook solution. Errors are relative to the motion's own scale (its peak |x| and
// peak |v|), since x and v cross zero.
void check_step_and_release(const OscillatorParams& p, double dt, double t_end) {
  const double f = 3.0, t_off = t_end / 2;
  const int steps = static_cast<int>(std::llround(t_end / dt));
  const int off_step = static_cast<int>(std::llround(t_off / dt));
  const StepMap on = make_step_map(p, dt, Integrator::exact);
  double x = 0.25, v = -0.5;  // not from rest, so the homogeneous part is exercised too
  std::vector<Exact> ref, got;
  Exact at_off{};
  for (int s = 1; s <= steps; ++s) {
    on.apply(x, v, s <= off_step ? f : 0.0);
    const long double t = s * static_cast<long double>(dt);
    Exact r = s <= off_step ? textbook(p, 0.25L, -0.5L, f, t)
                            : textbook(p, at_off.x, at_off.v, 0.0L, t - off_step * (long double)dt);
    if (s == off_step) at_off = r;
    ref.push_back(r);
    got.push_back({x, v});
  }
  long double xs = 0, vs = 0;
  for (const Exact& r : ref) {
    xs = std::max(xs, std::fabs(r.x));
    vs = std::max(vs, std::fabs(r.v));
  }
  long double worst = 0;
  for (std::size_t s = 0; s < ref.size(); ++s) {
    worst = std::max(worst, std::fabs(got[s].x - ref[s].x) / xs);
    worst = std::max(worst, std::fabs(got[s].v - ref[s].v) / vs);
  }
  EXPECT_LE(static_cast<double>(worst), 1e-12) << "dt " << dt << " ζ " << p.damping;
}

TEST(ExactIntegrator, MatchesTheClosedFormInEveryRegimeAndStepSize) {
  for (const Regime& regime : kRegimes) {
    SCOPED_TRACE(regime.name);
    const OscillatorParams p = with_ratio(0.7, 1.3, regime.zeta);
    for (double dt : {1e-4, 1e-3, 1e-2, 0.1, 1.0}) check_step_and_release(p, dt, dt >= 0.1 ? 20.0 : 1.0);
  }
}

TEST(ExactIntegrator, NearCriticalDampingIsContinuous) {
  // Just either side of ζ = 1 the formulas change branch; the answers must not jump.
  for (double zeta : {1 - 1e-9, 1 + 1e-9, 1 - 1e-6, 1 + 1e-6}) {
    const OscillatorParams p = with_ratio(1.0, 2.0, zeta);
    check_step_and_release(p, 0.01, 2.0);
  }
}

TEST(ExactIntegrator, OneStepOrAThousandGiveTheSameState) {
  for (const Regime& regime : kRegimes) {
    const OscillatorParams p = with_ratio(2.0, 0.8, regime.zeta);
    double x1 = 0.1, v1 = 0.3, xn = 0.1, vn = 0.3;
    make_step_map(p, 1.0, Integrator::exact).apply(x1, v1, 5.0);
    const StepMap small = make_step_map(p, 1e-3, Integrator::exact);
    for (int s = 0; s < 1000; ++s) small.apply(xn, vn, 5.0);
    const double scale = std::max({std::abs(x1), 5.0 / p.stiffness});
    EXPECT_NEAR(xn, x1, 1e-12 * scale) << regime.name;
    EXPECT_NEAR(vn, v1, 1e-12 * std::max(std::abs(v1), std::sqrt(p.stiffness / p.mass) * scale)) << regime.name;
  }
}

// Worst error over a 2 s trajectory of an integrator with dt = 1/n s, against the textbook answer,
// in the state norm |x − x*| + |v − v*|/ω (position and velocity on one scale).
double trajectory_error(Integrator integrator, int n) {
  const OscillatorParams p = with_ratio(1.0, 1.0, 0.1);
  const double omega = std::sqrt(p.stiffness / p.mass);
  const StepMap map = make_step_map(p, 1.0 / n, integrator);
  double x = 1.0, v = 0.0, worst = 0;
  for (int s = 1; s <= 2 * n; ++s) {
    map.apply(x, v, 2.0);
    const Exact r = textbook(p, 1.0L, 0.0L, 2.0L, s / static_cast<long double>(n));
    worst = std::max(worst, static_cast<double>(std::fabs(x - r.x) + std::fabs(v - r.v) / omega));
  }
  return worst;
}

TEST(SemiImplicitEuler, ConvergesAtFirstOrder) {
  // Halving dt halves the error: the observed order log2(e(dt)/e(dt/2)) is 1.
  for (int n : {400, 800, 1600, 3200}) {
    const double order = std::log2(trajectory_error(Integrator::semi_implicit_euler, n) /
                                   trajectory_error(Integrator::semi_implicit_euler, 2 * n));
    EXPECT_NEAR(order, 1.0, 0.05) << "n " << n;
  }
}

TEST(RungeKutta4, ConvergesAtFourthOrder) {
  for (int n : {50, 100, 200}) {
    const double order = std::log2(trajectory_error(Integrator::rk4, n) / trajectory_error(Integrator::rk4, 2 * n));
    EXPECT_NEAR(order, 4.0, 0.1) << "n " << n;
  }
}

TEST(ExactIntegrator, StableAndNeverGainsEnergyAtExtremeParameters) {
  // Stiffness up to 1e9, mass down to 1e-6, dt up to 10 s, forces up to 1e9. Traps are on: any NaN
  // or Inf made on the way fails the test where it is born.
  int cases = 0;
  for (double k : {1e-3, 1.0, 1e4, 1e9}) {
    for (double m : {1e-6, 1e-2, 1.0, 1e3}) {
      for (double c : {0.0, 1e-3, 1.0, 1e3, 1e6}) {
        for (double dt : {1e-5, 1e-2, 1.0, 10.0}) {
          const OscillatorParams p{m, c, k};
          const StepMap map = make_step_map(p, dt, Integrator::exact);
          double x = 0, v = 0;
          // Driven by the largest force, then released: energy may only fall once it is free.
          for (int s = 0; s < 20; ++s) map.apply(x, v, 1e9);
          ASSERT_TRUE(std::isfinite(x) && std::isfinite(v));
          double e = oscillator_energy(p, x, v);
          for (int s = 0; s < 200; ++s) {
            map.apply(x, v, 0.0);
            ASSERT_TRUE(std::isfinite(x) && std::isfinite(v));
            const double e1 = oscillator_energy(p, x, v);
            ASSERT_LE(e1, e * (1 + 1e-12)) << "k " << k << " m " << m << " c " << c << " dt " << dt;
            e = e1;
          }
          ++cases;
        }
      }
    }
  }
  EXPECT_EQ(cases, 4 * 4 * 5 * 4);
}

TEST(Integrators, NamesRoundTrip) {
  for (Integrator i : {Integrator::exact, Integrator::semi_implicit_euler, Integrator::rk4}) {
    Integrator back{};
    ASSERT_TRUE(parse_integrator(integrator_name(i), &back));
    EXPECT_EQ(back, i);
  }
  Integrator unused{};
  EXPECT_FALSE(parse_integrator("verlet", &unused));
}

}  // namespace
}  // namespace sweep
