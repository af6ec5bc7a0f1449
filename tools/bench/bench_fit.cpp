// Fitting: key sections K × radius samples n → fit time and fit error, on the diplodocus's tail and
// neck and on the triceratops's tail (CGAL's sample meshes).
//
// Error measure: fit_rms and fit_max, the RMS and largest radial distance |ρ − r(θ,t)| of the
// part's vertices from the fitted sweep surface (fit::measure_fit_error), given relative to the
// part's mean radius. Reference: the mesh's own vertices. Time: median wall time of a fit without
// the error measurement (tracing, sections, radii, part selection), the slicer built beforehand.
#include "bench_common.h"

namespace sweep::bench {
namespace {

struct Part {
  const char* mesh;
  Seeds seeds;
};

}  // namespace
}  // namespace sweep::bench

int main(int argc, char** argv) {
  using namespace sweep;
  using namespace sweep::bench;
  const Args args = parse_args(argc, argv);
  const Part parts[] = {
      {"diplodocus.off", test::kDiplodocusTail},
      {"diplodocus.off", test::kDiplodocusNeck},
      {"triceratops.off", {"tail", {-5.7, 1.0, 0.016}, {-10.29, 1.06, 0.04}}},
  };
  const std::vector<int> ks = args.quick ? std::vector<int>{4, 8, 16, 32} : std::vector<int>{4, 8, 16, 32, 64};
  const std::vector<int> ns = args.quick ? std::vector<int>{8, 16, 32} : std::vector<int>{4, 8, 16, 32, 64};
  const int runs = args.quick ? 1 : 3;
  std::string csv =
      "mesh,part,vertices,K,n,fit_ms,fit_rms,fit_max,mean_radius,length,rms_over_mean_radius,max_"
      "over_mean_radius\n";
  std::string md;
  for (const Part& part : parts) {
    const fs::path path = source_dir() / "meshes/cgal" / part.mesh;
    if (!fs::exists(path)) {
      std::fprintf(stderr, "warning: %s is absent (tools/setup-deps.sh unpacks it): skipped\n", path.string().c_str());
      continue;
    }
    const Mesh mesh = assets::read_mesh(path);
    const fit::SweepFitter fitter(mesh);
    md += fmt("\n**%s %s** — fit_rms / fit_max as %% of the mean radius; fit time ms (median of %d)\n\n", part.mesh,
              part.seeds.name, runs);
    md += "| K \\ n |";
    for (int n : ns) md += fmt(" %d |", n);
    md += "\n|---|";
    for (std::size_t c = 0; c < ns.size(); ++c) md += "---|";
    md += "\n";
    for (int k : ks) {
      md += fmt("| %d |", k);
      for (int n : ns) {
        fit::FitOptions o;
        o.name = part.seeds.name;
        o.root = part.seeds.root;
        o.tip = part.seeds.tip;
        o.sections = k;
        o.radial = n;
        o.measure_error = false;
        std::vector<double> times;
        for (int r = 0; r < runs; ++r) times.push_back(fitter.fit(o).seconds);
        o.measure_error = true;
        const fit::FitResult res = fitter.fit(o);
        const double ms = 1e3 * median(times);
        csv += fmt("%s,%s,%zu,%d,%d,%.4g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", part.mesh, part.seeds.name,
                   res.part_vertices.size(), k, n, ms, res.error.rms, res.error.max, res.mean_radius, res.length,
                   res.error.rms / res.mean_radius, res.error.max / res.mean_radius);
        md += fmt(" %.2f / %.1f, %.0f ms |", 100 * res.error.rms / res.mean_radius,
                  100 * res.error.max / res.mean_radius, ms);
      }
      md += "\n";
    }
  }
  write_text(args.out / "fit.csv", csv);
  write_text(args.out / "fit.md", md);
  std::fputs(md.c_str(), stdout);
  return 0;
}
