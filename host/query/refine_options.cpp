// SPDX-License-Identifier: Apache-2.0
// Parsing, naming and validation of the refinement options.
#include <smoothforce/query/refine_options.h>

#include <cmath>
#include <cstdio>

#include <smoothforce/base/error.h>

namespace sf {

RefineMethod parseRefineMethod(const std::string& s) {
  if (s == "newton") return RefineMethod::Newton;
  if (s == "paper") return RefineMethod::PaperDescent;
  throw InputError("refinement: expected newton|paper, got '" + s + "'");
}

InitialGuess parseInitialGuess(const std::string& s) {
  if (s == "surface" || s == "tessellation") return InitialGuess::Surface;  // tessellation: its former name
  if (s == "polygon") return InitialGuess::Polygon;
  throw InputError("initial guess: expected surface|polygon, got '" + s + "'");
}

FinalStep parseFinalStep(const std::string& s) {
  if (s == "evaluated") return FinalStep::Evaluated;
  if (s == "model") return FinalStep::Model;
  throw InputError("final step: expected evaluated|model, got '" + s + "'");
}

const char* toString(RefineMethod m) { return m == RefineMethod::Newton ? "newton" : "paper"; }
const char* toString(InitialGuess g) { return g == InitialGuess::Polygon ? "polygon" : "surface"; }
const char* toString(FinalStep s) { return s == FinalStep::Model ? "model" : "evaluated"; }

void validateRefineOptions(const RefineOptions& o) {
  // the command line's option beside the field's name; %g, not to_string's %f (1e-308 is 0.000000)
  auto num = [](double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return std::string(b);
  };
  if (!(o.angleTolerance > 0) || !std::isfinite(o.angleTolerance))
    throw InputError("angle tolerance (--angle-tol, angleTolerance) must be a finite value > 0 rad, got " +
                     num(o.angleTolerance));
  if (!(o.positionTolerance > 0) || !std::isfinite(o.positionTolerance))
    throw InputError("position tolerance (--position-tol, positionTolerance) must be a finite value > 0 (fraction of "
                     "the diagonal), got " + num(o.positionTolerance));
  if (o.maxIterations < 1)
    throw InputError("iteration cap (--max-iter, maxIterations) must be >= 1, got " + std::to_string(o.maxIterations));
  if (o.finalStep != FinalStep::Evaluated && o.finalStep != FinalStep::Model)
    throw InputError("final step (--final-step, finalStep) must be evaluated or model, got " +
                     std::to_string(static_cast<int>(o.finalStep)));
  if (o.finalStep == FinalStep::Model && o.refine != RefineMethod::Newton)
    throw InputError("final step (--final-step, finalStep) 'model' ends a Newton step on its model: it needs "
                     "--refine newton, got --refine " + std::string(toString(o.refine)));
  if (o.tessellationLevel < 0 || o.tessellationLevel > 64)
    throw InputError("tessellation level (--guess-level, tessellationLevel) must be in 0..64 (0: chosen), got " +
                     std::to_string(o.tessellationLevel));
}

}  // namespace sf
