#pragma once
// The parts `sweep-fit --list` offers and `--all` fits: those find_parts finds whose fit from their
// tip, at the options given, is trusted (no problems, fit/fit.h). A part the search finds but whose
// fit is then refused (it leaks past its root into the body, strays from the mesh) is passed over
// with the fit's reason: a suggestion the tool itself then refuses helps nobody.
#include <string>
#include <vector>

#include "sweep/fit/discover.h"
#include "sweep/fit/fit.h"

namespace sweep::fit {

struct OfferedParts {
  std::vector<FoundPart> parts;
  std::vector<FitResult> fits;  // fits[i]: parts[i]'s, its sweep named parts[i].name
};

OfferedParts find_fitting_parts(const Mesh& mesh, const SweepFitter& fitter, const DiscoverOptions& discover,
                                const FitOptions& fit, std::vector<std::string>* passed_over = nullptr);

}  // namespace sweep::fit
