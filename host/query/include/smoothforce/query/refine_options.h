// Options of the SCP refinement on the patches (paper Section 4.2), shared by the CPU
// refiner (patch_refine.h), the OpenCL refiner and the force methods (ForceOptions).
#pragma once

#include <string>

namespace sf {

/// Refinement of the SCP on a patch (paper 4.2): the paper's descent with numerical
/// differences and the Fig. 8 adaptive step, or Newton / Gauss-Newton on exact derivatives.
enum class RefineMethod { PaperDescent, Newton };
/// Where the patch method's global query starts refinement (out of contact): polygon = the
/// nearest point of the base polygons (Embree) mapped to the domain by mean value coordinates
/// (paper 4.1); tessellation = the nearest vertex of a level-L tessellation of the patches
/// (k-d tree), which carries its (face, xi, eta). Used by ForceMethod::Patch only.
enum class InitialGuess { Polygon, Tessellation };

/// Parsers throw InputError naming the value; toString gives the option spelling.
RefineMethod parseRefineMethod(const std::string& s);
InitialGuess parseInitialGuess(const std::string& s);
const char* toString(RefineMethod m);
const char* toString(InitialGuess g);

/// Refinement options. Units: radians.
struct RefineOptions {
  RefineMethod refine = RefineMethod::Newton;
  double angleTolerance = 1e-5;  ///< stop when angle(G - HIP, normal) below this, rad
  int maxIterations = 50;        ///< per refinement
  InitialGuess initialGuess = InitialGuess::Polygon;
  int tessellationLevel = 2;  ///< for InitialGuess::Tessellation: each polygon edge split in L, 1..64
};

/// Checks angleTolerance > 0 and finite, maxIterations >= 1, tessellationLevel in 1..64;
/// throws InputError naming the bad value.
void validateRefineOptions(const RefineOptions& options);

}  // namespace sf
