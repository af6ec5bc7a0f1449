#include "sweep/fit/offered_parts.h"

#include <map>
#include <utility>

#include "sweep/core/error.h"

namespace sweep::fit {

OfferedParts find_fitting_parts(const Mesh& mesh, const SweepFitter& fitter, const DiscoverOptions& discover,
                                const FitOptions& fit, std::vector<std::string>* passed_over) {
  std::map<std::uint32_t, FitResult> fitted;
  DiscoverOptions o = discover;
  o.refuse = [&](const FoundPart& part) -> std::string {
    FitOptions f = fit;
    f.tip_vertex = part.tip_vertex;
    try {
      FitResult r = fitter.fit(f);
      if (!r.problems.empty()) return "a fit from there is refused: " + r.problems.front();
      fitted.emplace(part.tip_vertex, std::move(r));
      return {};
    } catch (const Error& e) {
      if (e.category() != ErrorCategory::bad_input) throw;
      return std::string("a fit from there fails: ") + e.what();
    }
  };
  OfferedParts out;
  out.parts = find_parts(mesh, fitter.patched_topology(), o, passed_over);
  std::vector<FoundPart> kept;
  for (const FoundPart& p : out.parts) {
    // (A mesh that is one tube is offered by find_parts after its search, unchecked.)
    if (!fitted.contains(p.tip_vertex)) {
      if (const std::string why = o.refuse(p); !why.empty()) {
        if (passed_over) passed_over->push_back("vertex " + std::to_string(p.tip_vertex) + ": " + why);
        continue;
      }
    }
    FitResult r = std::move(fitted.at(p.tip_vertex));
    r.sweep.name = p.name;
    out.fits.push_back(std::move(r));
    kept.push_back(p);
  }
  out.parts = std::move(kept);
  return out;
}

}  // namespace sweep::fit
