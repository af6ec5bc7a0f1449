// Material mode's step: the geometrically exact chain (core/chain_dynamics.h) against the rest-pose
// modal step it replaced, at K = 8, 16, 32 sections, in one run. The scene: the generated tube of
// tests/core/beam_tubes.h (3.1 m, 5 cm radius) made soft (E = 1e6 Pa, ζ = 0.05), released level
// under gravity (not pre-loaded) with a follower force at 0.8 L: a large motion, the exact chain's
// hard case. Cost: the median wall time per ElasticSweep::step over 2 s of it (every load split,
// the positional and radial springs, the rebuild of the shape: what a simulator pays), at the
// default internal step 1/480 s and at 1/120 s; and the exact chain's Newton iterations and
// factorizations per step, and of those the dense S's (where the structured one steered too slowly).
#include "bench_common.h"
#include "core/beam_tubes.h"
#include "sweep/core/elastic_sweep.h"

namespace {

using namespace sweep;

struct Cost {
  double us_per_step = 0;
};

ElasticSweep released_tube(int sections, bool exact) {
  SweepDef def = test::beam::tube(test::beam::kRadius, test::beam::kRadius, 0.05, sections);
  test::beam::set_youngs_modulus(def, 1e6);
  ElasticSweep sweep(std::move(def));
  sweep.set_exact_chain(exact);
  sweep.set_gravity(Vec3(0, -9.81, 0), false);
  ForceSpec f;
  f.t = 0.8 * sweep.rest().length();
  f.theta = 0.3;
  f.vector = Vec3(0.5, 0.2, 0);
  f.components = kPositional | kRotational | kRadial;
  f.target = RotationTarget::chain;
  f.moment = MomentModel::physical;
  sweep.add_force(f);
  return sweep;
}

double us_per_step(int sections, bool exact, double h, int runs) {
  const int steps = static_cast<int>(std::lround(2.0 / h));
  return 1e6 *
         sweep::bench::median_seconds(runs,
                                      [&] {
                                        ElasticSweep sweep = released_tube(sections, exact);
                                        for (int s = 0; s < steps; ++s) sweep.step(h);
                                      }) /
         steps;
}

// The exact chain's Newton iterations and factorizations of its Newton matrix per step.
struct Counts {
  double iterations = 0, factorizations = 0, dense = 0;
};
Counts exact_counts(int sections, double h) {
  const int steps = static_cast<int>(std::lround(2.0 / h));
  ElasticSweep sweep = released_tube(sections, true);
  for (int s = 0; s < steps; ++s) sweep.step(h);
  const ChainDynamics& chain = *sweep.exact_chain_state();
  return {static_cast<double>(chain.iterations()) / steps, static_cast<double>(chain.factorizations()) / steps,
          static_cast<double>(chain.dense_factorizations()) / steps};
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sweep::bench;
  const Args args = parse_args(argc, argv);
  const int runs = args.quick ? 3 : 9;
  std::string csv =
      "sections,step_s,modal_us_per_step,exact_us_per_step,ratio,iterations,factorizations,dense_factorizations\n";
  std::string md =
      "| K | step (s) | modal step (µs) | exact step (µs) | exact / modal | iterations / step | factorizations / step "
      "| dense S / step |\n"
      "|---|---|---|---|---|---|---|---|\n";
  for (const double h : {1.0 / 480, 1.0 / 120}) {
    for (const int k : {8, 16, 32}) {
      const double modal = us_per_step(k, false, h, runs), exact = us_per_step(k, true, h, runs);
      const Counts n = exact_counts(k, h);
      csv += fmt("%d,%.6g,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g\n", k, h, modal, exact, exact / modal, n.iterations,
                 n.factorizations, n.dense);
      md += fmt("| %d | 1/%.0f | %.3g | %.3g | %.2f× | %.2f | %.3f | %.3f |\n", k, 1 / h, modal, exact, exact / modal,
                n.iterations, n.factorizations, n.dense);
    }
  }
  write_text(args.out / "chain.csv", csv);
  write_text(args.out / "chain.md", md);
  std::fputs(md.c_str(), stdout);
  return 0;
}
