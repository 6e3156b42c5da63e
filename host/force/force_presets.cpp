// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/force/force_presets.h>

#include <smoothforce/force/force_option_text.h>

namespace sf {

const std::vector<ForcePreset>& forcePresets() {
  // From the Pareto front of the trade-off study (docs/results.md "Speed against accuracy"), among
  // its points with the surface start (the exact global query: no missed or far contact): fast =
  // the fastest; balanced = the fastest whose max SCP error is below 1e-5 of the bounding
  // diagonal; accurate = the one with the smallest max error, with the default position
  // tolerance kept (never looser than no preset). Double caches: float records, widened for
  // every evaluation, were slower in every configuration.
  static const std::vector<ForcePreset> presets = {
      {"fast", RefineMethod::Newton, 1e-3, 1.0, 50, InitialGuess::Surface, 0, Precision::Double},
      {"balanced", RefineMethod::Newton, 1e-4, 1.0, 50, InitialGuess::Surface, 0, Precision::Double},
      {"accurate", RefineMethod::Newton, 1e-6, 1e-10, 50, InitialGuess::Surface, 0, Precision::Double},
  };
  return presets;
}

const ForcePreset& findForcePreset(const std::string& name) { return findForcePreset(name, OptionSpelling::Flag); }

void applyForcePreset(const ForcePreset& p, ForceOptions& o) {
  o.refine = p.refine;
  o.angleTolerance = p.angleTolerance;
  o.positionTolerance = p.positionTolerance;
  o.maxIterations = p.maxIterations;
  o.initialGuess = p.initialGuess;
  o.tessellationLevel = p.tessellationLevel;
}

}  // namespace sf
