// SPDX-License-Identifier: Apache-2.0
// Local nearest-point refinement on the patches (paper Section 4.2), crossing patch
// boundaries by Eq. 15 (design page, "Leaving the domain").
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/refine_options.h>

namespace sf {

class LazyPatches;

/// The refined surface contact point. status: the final point's GP_ST_* bits (evaluation |
/// face construction) and SF_TRACK_* bits (base/status.h): CONVERGED, MAX_ITER, STALLED,
/// BOUNDARY, DEGENERATE.
struct RefineResult {
  Eigen::Vector3d scp{0, 0, 0};     ///< m, G(xi, eta) on `face`
  Eigen::Vector3d normal{0, 0, 0};  ///< unit outward patch normal there
  int face = -1;
  int edge = -1;  ///< domain edge of `face` the SCP is held on (boundary, non-manifold), else -1
  double xi = 0, eta = 0;
  double distance = 0;                  ///< |SCP - HIP|, m
  int iterations = 0, transitions = 0;  ///< iterations run; Eq. 15 face changes
  uint32_t status = 0;
  /// Newton only: converged at its start (no iteration), not held on an edge, and a strict local
  /// minimum of the distance there (positive definite model Hessian): a start on the HIP's
  /// normal line that is no saddle or maximum (a HIP beyond the centre of curvature)
  bool startMinimum = false;
};

/// A reusable refiner: all memory is allocated in the constructor, refine() does not allocate,
/// lock or throw. Not thread-safe (one per thread); the cache must outlive it.
///
/// RefineMethod::Newton runs the one Newton refinement of the project, gp_refine_newton
/// (kernels/gp_refine.h, which the OpenCL kernel runs too): a trust-region Newton method on
/// f = |G - HIP|^2 / 2 whose trust region is measured in metres on the surface, an exact 2x2
/// subproblem, the ratio test (every accepted step decreases f), patch crossings by Eq. 15 that
/// carry the rest of a step into the neighbour's domain, boundary edges held (1-D Newton along
/// them). On the CPU it always computes in double: a float cache's records are widened on load,
/// so the float surface is refined to the same tolerance as a double one.
/// RefineMethod::PaperDescent runs gp_refine_descent (kernels/gp_refine.h, which the OpenCL
/// kernel runs too): the descent direction -grad f from central differences of |G - HIP|^2
/// (positions only, 4 evaluations); step length: the paper's Fig. 8 is not reproduced exactly -
/// we take the step that moves G, along the numerical tangent G_d of the direction d, to the
/// foot of the perpendicular from the HIP (alpha = -(r . G_d) / |G_d|^2), capped at 0.5 domain
/// units, halved until f decreases (backtracking); an iterate leaving the domain crosses domain
/// edge k at I0 on the ray from the origin and continues at I1 = C_i + s (C_{i+1} - C_i) on the
/// neighbour (Eq. 15 as printed); on a boundary or non-manifold edge it stays at the edge's
/// nearest point. The Fig. 8 reconstruction is ours. It evaluates a float cache in float.
/// Both stop when the tangential residual |(G - HIP) x n| is at most
/// min(sin(angleTolerance) |G - HIP|, positionTolerance x diagonal) (along a held edge: the
/// residual along the edge), after maxIterations, or when no step can decrease f. Newton also
/// stops, converged, at a singular point of a patch (|G_xi x G_eta| <= 1e-3 |G_xi| |G_eta|: a
/// fold line, where G - HIP lies along no normal and the residual test cannot be met) that is a
/// strict local minimum of its model whose Newton step would move f by at most that tolerance
/// squared over 2 (gp_rf_stationary, kernels/gp_refine.h).
class PatchRefiner {
 public:
  /// cache: a prebuilt cache, or a skeleton (hasPatchData false) with `lazy` building its
  /// patches on demand (lazy must then be given and outlive the refiner; not owned).
  explicit PatchRefiner(const PatchCache& cache, LazyPatches* lazy = nullptr);
  ~PatchRefiner();
  PatchRefiner(const PatchRefiner&) = delete;
  PatchRefiner& operator=(const PatchRefiner&) = delete;
  /// Refines from (face, xi, eta) (clamped into the domain; edge: the domain edge of `face` the
  /// start is held on, -1 for none) towards the point nearest `hip` (m).
  RefineResult refine(const Eigen::Vector3d& hip, int face, double xi, double eta, const RefineOptions& options,
                      int edge = -1) noexcept;
  /// refine() for a tracker's next step, which starts from the SCP of this refiner's previous
  /// refinement: reuses that refinement's final evaluation when the start is exactly its final
  /// point (the same bits), and its last second derivatives while the iterate stays within 1/8
  /// of a domain unit of where they were taken on the same face (gp_refine_newton_warm): two or
  /// three patch evaluations fewer per step. The result meets the same stopping rule as
  /// refine()'s but depends on the previous call (the path, not the tolerance). PaperDescent:
  /// refine().
  RefineResult refineNext(const Eigen::Vector3d& hip, int face, double xi, double eta, const RefineOptions& options,
                          int edge = -1) noexcept;
  /// True when face f's patch can be evaluated (built, n <= GP_MAX_N, finite input).
  bool evaluable(int f) const noexcept;
  /// One evaluation through the refiner's record buffer (same values as evaluatePatch).
  PatchPoint eval(int f, const Eigen::Vector2d& X) noexcept;
  /// The SIMD evaluator the refinement's point pairs go through, to lend between refinements
  /// (LazyPatchSurface::cells): its scratch is allocated with the refiner, so a servo step that
  /// borrows it allocates nothing. evaluateRecords on it costs the refiner at most one reload of
  /// its kept face. Null where the cache has no patches and no lazy store.
  FacePointEvaluator* pointEvaluator() noexcept;

 private:
  void load(int f) noexcept;
  RefineResult refineNewton(const Eigen::Vector3d& hip, int face, double xi, double eta, const RefineOptions& options,
                            int edge, bool warm) noexcept;
  RefineResult refineDescent(const Eigen::Vector3d& hip, int face, double xi, double eta, const RefineOptions& options,
                             int edge) noexcept;
  /// GP_ST_* construction bits of face f (from the lazy store when there is one).
  uint32_t faceStatus(int f) const noexcept;

  const PatchCache& cache_;
  LazyPatches* lazy_ = nullptr;
  std::vector<int32_t> slotFace_;  ///< #C: face owning each slot
  struct RefineState;              ///< the kernels' refinement (gp_refine.h): its view of the cache, its scratch
  std::unique_ptr<RefineState> state_;
  std::vector<double> recsD_;
  std::vector<float> recsF_;
  int loaded_ = -1;
  double scale_ = 1;  ///< bounding-box diagonal, m
};

/// One-shot refinement (allocates a PatchRefiner).
RefineResult refineNearestPoint(const PatchCache& cache, const Eigen::Vector3d& hip, int face, double xi, double eta,
                                const RefineOptions& options = {});

}  // namespace sf
