// SPDX-License-Identifier: Apache-2.0
// Options of the SCP refinement on the patches (paper Section 4.2), shared by the CPU
// refiner (patch_refine.h), the OpenCL refiner and the force methods (ForceOptions).
#pragma once

#include <string>

namespace sf {

/// Refinement of the SCP on a patch (paper 4.2): the paper's descent with numerical
/// differences and the Fig. 8 adaptive step, or Newton / Gauss-Newton on exact derivatives.
enum class RefineMethod { PaperDescent, Newton };
/// The patch method's global query (out of contact). surface (default): the nearest point of the
/// patch surface itself, from the candidates of a tessellation BVH (PatchSurface), each refined,
/// the nearest wins, and contact starts when the HIP is inside the surface (winding number);
/// needs prebuilt patches (a skeleton falls back to polygon). polygon: the paper's Section 4.1,
/// the nearest point of the base polygons (Embree) mapped to the domain by mean value
/// coordinates, refined once, contact when (HIP - SCP) . n < 0. Used by ForceMethod::Patch only.
enum class InitialGuess { Surface, Polygon };
/// How the Newton refinement takes the point of its last, converging step. evaluated (default):
/// the patch is evaluated there, so the SCP lies on the patch and its normal is the patch's at
/// its domain point to rounding. model: where the step is predicted to converge, stays on its
/// face, moves at most 1e-4 domain units and starts where the second differences were taken, the
/// point, its derivatives and normal come from the quadratic model there (G + J s + s^T H s / 2,
/// J + H s; kernels/gp_refine.h, GP_RF_MODEL_STEP) and carry SF_ST_MODEL_POINT: one patch
/// evaluation fewer per tracking step, at a model error far below the stopping tolerances
/// (docs/results.md "Speed against accuracy": measured bounds). Model needs RefineMethod::Newton.
enum class FinalStep { Evaluated, Model };

/// Parsers throw InputError naming the value; toString gives the option spelling
/// (InitialGuess: "surface"|"polygon"; "tessellation", its former name, parses as Surface).
RefineMethod parseRefineMethod(const std::string& s);
InitialGuess parseInitialGuess(const std::string& s);
FinalStep parseFinalStep(const std::string& s);  ///< "evaluated"|"model"
const char* toString(RefineMethod m);
const char* toString(InitialGuess g);
const char* toString(FinalStep s);

/// Refinement options. Units: radians; positionTolerance is a fraction of the mesh's
/// bounding-box diagonal.
struct RefineOptions {
  RefineMethod refine = RefineMethod::Newton;
  /// Refinement stops when the tangential residual |(HIP - SCP) x n| is at most
  /// min(sin(angleTolerance) |HIP - SCP|, positionTolerance x bounding-box diagonal).
  double angleTolerance = 1e-5;      ///< rad, > 0
  double positionTolerance = 1e-10;  ///< fraction of the mesh's bounding-box diagonal, > 0
  int maxIterations = 50;            ///< per refinement
  InitialGuess initialGuess = InitialGuess::Surface;
  /// InitialGuess::Surface: level of the patch tessellation (each polygon edge split in L),
  /// 1..64; 0 chooses it (PatchSurfaceOptions: error bound below 1e-4 of the diagonal within a
  /// triangle budget).
  int tessellationLevel = 0;
  FinalStep finalStep = FinalStep::Evaluated;  ///< the converging step's point (Newton only)
};

/// Checks angleTolerance > 0, positionTolerance > 0 (both finite), maxIterations >= 1,
/// tessellationLevel in 0..64, finalStep one of its values and Model only with Newton; throws
/// InputError naming the bad value.
void validateRefineOptions(const RefineOptions& options);

}  // namespace sf
