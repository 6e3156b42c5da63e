// Local nearest-point refinement on the patches (paper Section 4.2), crossing patch
// boundaries by Eq. 15 (design page, "Leaving the domain").
#pragma once

#include <Eigen/Core>
#include <cstdint>
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
};

/// A reusable refiner: all memory is allocated in the constructor, refine() does not allocate,
/// lock or throw. Not thread-safe (one per thread); the cache must outlive it.
///
/// RefineMethod::Newton: Newton on f = |G - HIP|^2 / 2 with the exact gradient J^T r and the
/// Hessian J^T J + sum r_i d2G_i, the second-order part from forward differences of the exact
/// derivatives (2 extra evaluations); Gauss-Newton (J^T J) when that Hessian is not positive
/// definite; a trust region in the domain (radius doubled after a full accepted step,
/// quartered after a rejected one; acceptance: see better()).
/// RefineMethod::PaperDescent: the descent direction -grad f from central differences of
/// |G - HIP|^2 (positions only, 4 evaluations); step length: the paper's Fig. 8 is not
/// reproduced exactly - we take the step that moves G, along the numerical tangent G_d of the
/// direction d, to the foot of the perpendicular from the HIP (alpha = -(r . G_d) / |G_d|^2),
/// capped at 0.5 domain units, halved until f decreases (backtracking).
/// Both stop when the angle between G - HIP and the patch normal is below angleTolerance (or
/// |G - HIP| is below 1e-12 of the mesh size), after maxIterations, or when the step vanishes.
/// An iterate leaving the domain crosses domain edge k at I0 on the ray from the origin and
/// continues at I1 = C_i + s (C_{i+1} - C_i) on the neighbour (slotTwin); on a boundary or
/// non-manifold edge it stays on the edge: at the edge's nearest point to X in the domain (a
/// projected step, so that it can slide along the edge; converged when G - HIP is orthogonal
/// to the edge's tangent). Acceptance of a step (both variants): f decreases; or the step moved
/// onto the neighbour with f unchanged up to its evaluation noise (Eq. 15 drops the rest of the
/// step, so the new point is often the same 3D point, and refusing it would stall the iterate
/// against the edge); or f is unchanged up to its noise and the angle shrinks (float caches).
/// The Fig. 8 reconstruction and these rules are ours; the paper's Fig. 8 is not available to us.
class PatchRefiner {
 public:
  /// cache: a prebuilt cache, or a skeleton (hasPatchData false) with `lazy` building its
  /// patches on demand (lazy must then be given and outlive the refiner; not owned).
  explicit PatchRefiner(const PatchCache& cache, LazyPatches* lazy = nullptr);
  /// Refines from (face, xi, eta) (clamped into the domain) towards the point nearest `hip`.
  RefineResult refine(const Eigen::Vector3d& hip, int face, double xi, double eta,
                      const RefineOptions& options) noexcept;
  /// True when face f's patch can be evaluated (built, n <= GP_MAX_N, finite input).
  bool evaluable(int f) const noexcept;
  /// One evaluation through the refiner's record buffer (same values as evaluatePatch).
  PatchPoint eval(int f, const Eigen::Vector2d& X) noexcept;

 private:
  struct Iterate {
    int face;
    int edge;  // domain edge the iterate is held on (boundary), else -1
    Eigen::Vector2d X;
    PatchPoint p;
    double f;  // |G - HIP|^2 / 2
  };
  void load(int f) noexcept;
  /// GP_ST_* construction bits of face f (from the lazy store when there is one).
  uint32_t faceStatus(int f) const noexcept;
  Iterate at(int f, const Eigen::Vector2d& X, const Eigen::Vector3d& hip) noexcept;
  /// Eq. 15: maps an X outside face f's domain onto the neighbour (or onto the edge).
  void transfer(int& f, Eigen::Vector2d& X, int& edge, int& transitions, uint32_t& status) const noexcept;
  Eigen::Vector2d interior(int n, const Eigen::Vector2d& X, double eps) const noexcept;
  bool converged(const Iterate& it, const Eigen::Vector3d& hip, double tol) const noexcept;
  /// Step acceptance: f decreases, or stays within its evaluation noise while the angle
  /// between G - HIP and the normal shrinks.
  bool better(const Iterate& trial, const Iterate& cur, const Eigen::Vector3d& hip) const noexcept;
  /// Moves cur by `step` in its domain (across an edge by Eq. 15 via transfer) and keeps the
  /// result when better() accepts it; transitions and status then take the move's.
  bool tryStep(Iterate& cur, const Eigen::Vector2d& step, const Eigen::Vector3d& hip, int& transitions,
               uint32_t& status) noexcept;
  void newtonStep(Iterate& cur, const Eigen::Vector3d& hip, double& radius, int& transitions, uint32_t& status,
                  bool& stalled) noexcept;
  void descentStep(Iterate& cur, const Eigen::Vector3d& hip, int& transitions, uint32_t& status,
                   bool& stalled) noexcept;

  const PatchCache& cache_;
  LazyPatches* lazy_ = nullptr;
  std::vector<int32_t> slotFace_;  ///< #C: face owning each slot
  std::vector<double> recsD_;
  std::vector<float> recsF_;
  int loaded_ = -1;
  double scale_ = 1;     ///< bounding-box diagonal, m
  double eps_ = 1e-6;    ///< finite-difference step in the domain (1e-3 for float caches)
  double posNoise_ = 0;  ///< m: evaluation noise of positions (1e-14 / 1e-6 of the mesh size)
  int lastFace_ = -1;    ///< the last accepted iterate, reused when the next call starts there
  Eigen::Vector2d lastX_{0, 0};
  PatchPoint lastP_;
  int lastEdge_ = -1;
};

/// One-shot refinement (allocates a PatchRefiner).
RefineResult refineNearestPoint(const PatchCache& cache, const Eigen::Vector3d& hip, int face, double xi, double eta,
                                const RefineOptions& options = {});

}  // namespace sf
