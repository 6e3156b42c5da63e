// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/force/force_presets.h>

#include <smoothforce/force/force_option_text.h>

namespace sf {

const std::vector<ForcePreset>& forcePresets() {
  // From the Pareto front of the trade-off study (docs/results.md "Speed against accuracy"): fast = the
  // fastest point of the front; balanced = the fastest point whose max SCP error is below 1e-5
  // of the bounding diagonal; accurate = the point with the smallest median error.
  static const std::vector<ForcePreset> presets = {
      {"fast", RefineMethod::Newton, 1e-2, 50, InitialGuess::Surface, 0, Precision::Float},
      {"balanced", RefineMethod::Newton, 1e-4, 10, InitialGuess::Surface, 0, Precision::Float},
      {"accurate", RefineMethod::Newton, 1e-6, 50, InitialGuess::Surface, 0, Precision::Double},
  };
  return presets;
}

const ForcePreset& findForcePreset(const std::string& name) { return findForcePreset(name, OptionSpelling::Flag); }

void applyForcePreset(const ForcePreset& p, ForceOptions& o) {
  o.refine = p.refine;
  o.angleTolerance = p.angleTolerance;
  o.maxIterations = p.maxIterations;
  o.initialGuess = p.initialGuess;
  o.tessellationLevel = p.tessellationLevel;
}

}  // namespace sf
