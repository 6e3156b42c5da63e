// SPDX-License-Identifier: Apache-2.0
// Named speed/accuracy presets of the patch method (`--preset fast|balanced|accurate`),
// chosen from the Pareto front of the trade-off study (bench/study_tradeoff.cpp; docs/results.md,
// "Speed against accuracy", which lists each preset's measured time and error).
#pragma once

#include <string>
#include <vector>

#include <smoothforce/force/force_method.h>
#include <smoothforce/patch/patch_options.h>

namespace sf {

/// One preset: the refinement options it sets and the cache precision it advises.
struct ForcePreset {
  std::string name;
  RefineMethod refine = RefineMethod::Newton;
  double angleTolerance = 1e-5;  ///< rad
  /// Fraction of the bounding-box diagonal (RefineOptions::positionTolerance). The refinement
  /// stops at the smaller of the two tolerances, so 1 (the diagonal) leaves the angle tolerance
  /// alone to decide, as the study measured fast and balanced; accurate keeps the default 1e-10.
  double positionTolerance = 1e-10;
  int maxIterations = 50;
  InitialGuess initialGuess = InitialGuess::Surface;
  int tessellationLevel = 0;
  /// Precision of the patch records the study measured this preset with: applied when a
  /// command builds patches from a mesh and --precision is not given (a cache file keeps its own).
  Precision precision = Precision::Double;
};

/// All presets: fast, balanced, accurate (in that order).
const std::vector<ForcePreset>& forcePresets();

/// The preset called `name`; throws InputError "--preset: expected fast|balanced|accurate, got 'x'".
const ForcePreset& findForcePreset(const std::string& name);

/// Sets options' refine, angleTolerance, positionTolerance, maxIterations, initialGuess and
/// tessellationLevel from the preset; stiffness is left alone. Apply the preset first, explicit
/// options after.
void applyForcePreset(const ForcePreset& preset, ForceOptions& options);

}  // namespace sf
