// Stress, the long runs (tests/stress has the fast versions): random seeded forces on the
// diplodocus's tail with springs, force scales and time steps spanning many orders of magnitude,
// every invariant of tests/stress/stress_harness.h checked after every step; and the explicit
// integrators at steps where they are unstable, to show divergence is caught, not written.
#include "bench_common.h"
#include "stress/stress_harness.h"

int main(int argc, char** argv) {
  using namespace sweep;
  using namespace sweep::bench;
  using namespace sweep::stress;
  const Args args = parse_args(argc, argv);
  const long long long_steps = args.quick ? 10000 : 100000;
  SweepDef tail;
  {
    const RealRig dino = diplodocus_rig();
    tail = dino.rig.sweeps[0];
  }
  struct Case {
    StressParams p;
    long long steps;
  };
  std::vector<Case> cases;
  // The long runs: 100,000 steps (10,000 in quick mode), the first half forced.
  for (double dt : {1e-5, 1e-3, 1.0 / 60, 1.0}) {
    StressParams p;
    p.dt = dt;
    p.force = 1e3;
    cases.push_back({p, long_steps});
  }
  // The extremes: every corner of mass × frequency × damping × force scale × dt, 2,000 steps each.
  for (double m : {1e-4, 1e4}) {
    for (double f : {1e-2, 1e3}) {
      for (double z : {0.01, 1.0, 100.0}) {
        for (double c : {1e-3, 1e3}) {
          for (double dt : {1e-5, 1.0}) {
            StressParams p{m, f, z, c, c, dt, 1e3, Integrator::exact, {}};
            cases.push_back({p, args.quick ? 500 : 2000});
          }
        }
      }
    }
  }
  // Material mode: long runs, and the corners of stiffness × density × mesh scale ×
  // damping × dt.
  auto material = [](double e, double rho, double scale, double z) {
    Material m;
    m.youngs_modulus = e;
    m.density = rho;
    m.metres_per_unit = scale;
    m.damping_ratio = z;
    return m;
  };
  for (double dt : {1e-5, 1e-3, 1.0 / 60, 1.0}) {
    StressParams p;
    p.dt = dt;
    p.force = 1e3;
    p.material = material(1e6, 1000, 10, 0.3);  // the tail taken as ~10 m long
    cases.push_back({p, long_steps});
  }
  for (double e : {1e3, 1e11}) {
    for (double rho : {10.0, 2e4}) {
      for (double scale : {1e-3, 10.0}) {
        for (double z : {0.01, 1.0, 100.0}) {
          for (double dt : {1e-5, 1.0}) {
            StressParams p;
            p.dt = dt;
            p.force = 1e3;
            p.material = material(e, rho, scale, z);
            cases.push_back({p, args.quick ? 500 : 2000});
          }
        }
      }
    }
  }
  // Explicit integrators beyond their stability limit: expected to fail with non-finite or runaway
  // values, which the simulator reports as divergence (Error(diverged)) before anything is written.
  for (Integrator integ : {Integrator::semi_implicit_euler, Integrator::rk4}) {
    StressParams p;
    p.frequency_hz = 50;
    p.dt = 0.1;
    p.integrator = integ;
    cases.push_back({p, 2000});
  }

  std::string csv =
      "integrator,model,mass,frequency_hz,youngs_modulus_pa,density_kg_m3,metres_per_unit,damping_ratio,"
      "c_rot,c_rad,dt,force,steps_asked,steps_run,result,max_orthonormality_error,min_radius_ratio,"
      "max_energy_growth,peak_displacement,final_displacement,rest_expected,returned_to_rest,seconds\n";
  std::string md =
      "| integrator | springs (m, f0 Hz) or material (E Pa, ρ kg/m³, m/unit) | ζ | C_rot = C_rad | dt s | "
      "steps | result | max ‖RᵀR−I‖ | min r/r_rest | max energy growth (free) | back to rest | s |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  int failures = 0, expected_failures = 0;
  long long total_steps = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const auto t0 = Clock::now();
    const StressResult r = run_stress(tail, c.p, 1000 + i, c.steps, c.steps / 2);
    const double secs = seconds_since(t0);
    total_steps += r.steps;
    const bool explicit_integrator = c.p.integrator != Integrator::exact;
    if (!r.ok()) (explicit_integrator ? expected_failures : failures) += 1;
    const std::string result = r.ok() ? "ok" : (explicit_integrator ? "diverged (caught): " : "FAILED: ") + r.failure;
    const std::string name(integrator_name(c.p.integrator));
    const Material mat = c.p.material.value_or(Material{});
    const double zeta = c.p.material ? mat.damping_ratio : c.p.damping_ratio;
    const std::string model = c.p.material
                                  ? fmt("material %g, %g, %g", mat.youngs_modulus, mat.density, mat.metres_per_unit)
                                  : fmt("springs %g, %g", c.p.mass, c.p.frequency_hz);
    csv +=
        fmt("%s,%s,%g,%g,%g,%g,%g,%g,%g,%g,%g,%g,%lld,%lld,\"%s\",%.3g,%.3g,%.3g,%.3g,%.3g,%d,%d,%.3g\n", name.c_str(),
            c.p.material ? "material" : "springs", c.p.material ? 0.0 : c.p.mass, c.p.material ? 0.0 : c.p.frequency_hz,
            c.p.material ? mat.youngs_modulus : 0.0, c.p.material ? mat.density : 0.0,
            c.p.material ? mat.metres_per_unit : 0.0, zeta, c.p.c_rot, c.p.c_rad, c.p.dt, c.p.force, c.steps, r.steps,
            result.c_str(), r.max_orthonormality_error, r.min_radius_ratio, r.max_energy_growth, r.peak_displacement,
            r.final_displacement, r.rest_expected, r.returned_to_rest, secs);
    md += fmt("| %s | %s | %g | %s | %g | %lld | %s | %.1e | %.3f | %.1e | %s | %.2f |\n", name.c_str(), model.c_str(),
              zeta, c.p.material ? "–" : fmt("%g", c.p.c_rot).c_str(), c.p.dt, r.steps, result.c_str(),
              r.max_orthonormality_error, r.min_radius_ratio, r.max_energy_growth,
              r.rest_expected ? (r.returned_to_rest ? "yes" : "NO") : (r.returned_to_rest ? "yes" : "not expected"),
              secs);
  }
  md +=
      fmt("\n%zu runs, %lld steps in all on the diplodocus tail (K = %d, n = %d): %d invariant "
          "failures with the "
          "exact integrator; %d explicit-integrator runs beyond their stability limit caught as "
          "divergence.\n",
          cases.size(), total_steps, tail.rest.section_count(), tail.rest.radial_count, failures, expected_failures);
  write_text(args.out / "stress.csv", csv);
  write_text(args.out / "stress.md", md);
  std::fputs(md.c_str(), stdout);
  return failures == 0 ? 0 : 1;
}
