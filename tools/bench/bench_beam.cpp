// Material mode against beam theory at K = 8, 16, 32 and 64 sections: the cases of
// tests/core/beam_test.cpp (which asserts them at K = 32) on the same generated tubes
// (tests/core/beam_tubes.h: 3.1 m long, 5 cm radius, E = 10 MPa, ρ = 1100 kg/m³, 32 radii).
//
// Error measure: model / theory − 1, in percent, for the static tip deflection under a small tip
// load (F L³ / 3EI), the tip sag under its own weight (w L⁴ / 8EI), the first three bending
// frequencies (Euler–Bernoulli clamped–free, βL = 1.8751, 4.6941, 7.8548), the first twist frequency
// (π/2 · √(GJ/ρJ_p) / L), and for an elliptical tube (a = 2b) the ratio of its deflections down and
// across against the ratio of its polygon's second moments.
// Cost: building the model (section properties, mass and stiffness, the generalized eigenproblem;
// once per rig) and one step of the sweep under a chain force (median), in the same run.
#include "bench_common.h"
#include "core/beam_tubes.h"

int main(int argc, char** argv) {
  using namespace sweep;
  using namespace sweep::bench;
  using namespace sweep::test::beam;
  const Args args = parse_args(argc, argv);
  const int runs = args.quick ? 5 : 21;
  std::string csv =
      "sections,tip_load_pct,own_weight_pct,bend1_pct,bend2_pct,bend3_pct,twist1_pct,ellipse_ratio_pct,"
      "setup_ms,step_us\n";
  std::string md =
      "| K | tip load | own weight | bend 1 | bend 2 | bend 3 | twist 1 | ellipse ratio | model setup ms | "
      "µs per step |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const int k : {8, 16, 32, 64}) {
    const SweepDef round = test::beam::tube(kRadius, kRadius, 1.0, k);
    const SectionProperties p = props_of(round);
    const double l = length_m(round);
    const double force = 0.01, g = 0.01;  // small deflections
    const double tip =
        settled_tip_deflection(round, Vec3(0, force, 0), 0) / (force * l * l * l / (3 * kYoung * p.i_xx)) - 1;
    const double weight = settled_tip_deflection(round, Vec3::Zero(), g) /
                              (kDensity * p.area * g * std::pow(l, 4) / (8 * kYoung * p.i_xx)) -
                          1;
    const ElasticSweep free_tube(test::beam::tube(kRadius, kRadius, 0.0, k));
    const std::vector<double> bend = frequencies_about(*free_tube.chain(), 0);
    const std::vector<double> twist = frequencies_about(*free_tube.chain(), 2);
    double bend_err[3];
    for (int n = 0; n < 3; ++n) {
      bend_err[n] = n < static_cast<int>(bend.size()) ? bend[n] / euler_bernoulli(n, p, l) - 1 : NAN;
    }
    const double twist_err = twist.empty() ? NAN : twist[0] / first_twist(round, p) - 1;
    const SweepDef oval = test::beam::tube(0.6, 0.3, 1.0, k);
    const SectionProperties po = props_of(oval);
    const double ellipse =
        (settled_tip_deflection(oval, Vec3(0, 0.01, 0), 0) / settled_tip_deflection(oval, Vec3(0.01, 0, 0), 0)) /
            (po.i_yy / po.i_xx) -
        1;

    const double setup = median_seconds(runs, [&] { const ElasticSweep s(round); });
    ElasticSweep sweep(test::beam::tube(kRadius, kRadius, 0.05, k));
    ForceSpec f;
    f.t = 0.8 * sweep.rest().length();
    f.theta = 0.3;
    f.vector = Vec3(0.01, 0.02, 0);
    f.components = kPositional | kRotational | kRadial;
    f.target = RotationTarget::chain;
    f.moment = MomentModel::physical;
    sweep.add_force(f);
    const int steps = 480;
    const double step = median_seconds(runs,
                                       [&] {
                                         for (int s = 0; s < steps; ++s) sweep.step(1.0 / 480);
                                       }) /
                        steps;

    const double pct[7] = {tip, weight, bend_err[0], bend_err[1], bend_err[2], twist_err, ellipse};
    csv += fmt("%d", k);
    md += fmt("| %d |", k);
    for (const double e : pct) {
      csv += fmt(",%.4g", 100 * e);
      md += fmt(" %+.2f%% |", 100 * e);
    }
    csv += fmt(",%.4g,%.4g\n", 1e3 * setup, 1e6 * step);
    md += fmt(" %.3g | %.3g |\n", 1e3 * setup, 1e6 * step);
  }
  write_text(args.out / "beam.csv", csv);
  write_text(args.out / "beam.md", md);
  std::fputs(md.c_str(), stdout);
  return 0;
}
