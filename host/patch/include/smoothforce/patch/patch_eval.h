// SPDX-License-Identifier: Apache-2.0
// Evaluating cached patches: one point, or batches on the CPU.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/patch/patch_simd.h>

namespace sf {

/// A point on a patch: G, dG/dxi, dG/deta, unit normal (Eq. 2-5, exact derivatives) and
/// GP_ST_* status bits (evaluation bits | the face's construction bits).
struct PatchPoint {
  Eigen::Vector3d pos{0, 0, 0}, dxi{0, 0, 0}, deta{0, 0, 0}, normal{0, 0, 0};
  uint32_t status = 0;
};

/// Geometry of the regular n-gon domain of circumradius 1 (design page, "Domain"; Eq. 3), in
/// double: the kernels' definitions (kernels/gp_tables.h, gp_domain.h), read from their domain
/// table for 3 <= n <= GP_MAX_N and computed by the same formulas for any other n (faces that
/// get no patch, which the god-object still maps onto their domain).
///
/// Domain corner C_k = (cos 2 pi k/n, sin 2 pi k/n); any k (taken modulo n by the formula).
Eigen::Vector2d domainCorner(int n, int k);
/// True when (xi, eta) lies in the domain up to `tol` in distance: cos(pi/n) - X . m_k >= -tol
/// for every unit edge normal m_k (a negative tol demands that much inside). False for n < 3
/// and for non-finite coordinates. The kernels' inside test (gp_dom_inside) has tolerance 0.
bool insideDomain(int n, double xi, double eta, double tol = 1e-12);
/// Largest X . m_k over the domain's edges; k receives its edge (0 when n < 1). X is inside
/// iff this is <= cos(pi/n) (gp_dom_edge_max).
double domainEdgeMax(int n, const Eigen::Vector2d& X, int& k) noexcept;
/// X scaled towards the origin onto the domain boundary when outside (the ray of Eq. 15);
/// unchanged inside (gp_dom_clamp).
Eigen::Vector2d clampToDomain(int n, const Eigen::Vector2d& X) noexcept;

/// Evaluates face f's patch at (xi, eta) in the cache's precision.
/// Throws std::out_of_range for a face index outside [0, #F). A point outside the domain
/// is not an error here: status has GP_ST_OUTSIDE and the vectors are zero.
PatchPoint evaluatePatch(const PatchCache& cache, int f, double xi, double eta);

/// A few points (1..16) of one face at a time: side by side on the narrowest SIMD target this
/// CPU runs whose vector holds them all (SSE4 for 2 doubles; the widest when none does; one
/// point: the scalar path), so that 2-4 points cost about one evaluation (the refinement's
/// finite differences). Bit-identical to evaluatePatch. Its scratch is allocated in the
/// constructor: evaluate() never allocates, locks or throws. Not thread-safe (one per thread);
/// the cache must outlive it.
class FacePointEvaluator {
 public:
  /// Throws std::invalid_argument for a cache without patch data (a skeleton).
  explicit FacePointEvaluator(const PatchCache& cache);
  /// Without a cache: evaluateRecords only (the records of a lazy store).
  FacePointEvaluator();
  ~FacePointEvaluator();
  FacePointEvaluator(const FacePointEvaluator&) = delete;
  FacePointEvaluator& operator=(const FacePointEvaluator&) = delete;

  /// Evaluates face f at (xi[i], eta[i]), i < count (clamped to 0..16), into out[i]. f must
  /// index a face with 3..GP_MAX_N sides. The last face's records are kept as SIMD vectors for
  /// the next call on it (as the refiner keeps its loaded face): the cache's records must not
  /// change while the evaluator lives.
  void evaluate(int f, const double* xi, const double* eta, int count, PatchPoint* out) noexcept;
  /// The same on double records given by the caller: n (3..GP_MAX_N) records of GP_E_NFIELDS,
  /// field-major (field i of corner k at recs[i * n + k]); mode: the cross-tangent mode (GP_CT_*);
  /// faceStatus: the face's GP_ST_* construction bits, added to every point's status (GP_ST_AFFINE:
  /// the patch is the triangle's affine map, gp_eval_mode).
  void evaluateRecords(int n, int mode, uint32_t faceStatus, const double* recs, const double* xi, const double* eta,
                       int count, PatchPoint* out) noexcept;

 private:
  struct Scratch;
  const PatchCache* cache_;
  std::unique_ptr<Scratch> scratch_;
};

/// Writes n (3..GP_MAX_N) corner records from record-major order (field i of corner k at
/// recordMajor[k * GP_E_NFIELDS + i], as buildPatchEdges, the caches and a lazy store hold them)
/// into the field-major order FacePointEvaluator::evaluateRecords takes (field i of corner k at
/// fieldMajor[i * n + k]); float records are widened to double, exactly.
void recordsFieldMajor(int n, const double* recordMajor, double* fieldMajor) noexcept;
void recordsFieldMajor(int n, const float* recordMajor, double* fieldMajor) noexcept;

/// Options of the CPU batch evaluator.
struct EvalOptions {
  Backend backend = Backend::Tbb;      ///< Serial (the calling thread) or Tbb; OpenCL: opencl_backend.h
  int threads = 0;                     ///< Tbb worker limit (<= 0: oneTBB's default), in a task_arena
  SimdTarget simd = SimdTarget::Auto;  ///< instruction set (patch_simd.h); every one gives the same bits
};

/// Reusable CPU batch evaluator; evaluatePatches is its one-shot form. Groups the queries by
/// face, reads each face's records once per group from the cache (in place, field-major) and
/// evaluates the group's points side by side on SIMD lanes (Scalar: one after the other).
/// Results are bit-identical for every target, thread count and query order, and equal to
/// evaluatePatch. Keeps its scratch buffers between calls; not thread-safe (one per thread).
/// The cache must outlive it.
class PatchEvaluator {
 public:
  /// Throws std::invalid_argument for Backend::OpenCL, a SIMD target this CPU or build lacks,
  /// or a cache without patch data (a skeleton, hasPatchData false).
  explicit PatchEvaluator(const PatchCache& cache, const EvalOptions& options = {});

  /// Evaluates N points: faces, xi, eta are N long (face indices into the cache, domain
  /// points); out gets N results, in order. A face index outside [0, #F) gives GP_ST_OUTSIDE
  /// and zeros, a face with n outside 3..GP_MAX_N GP_ST_TOO_MANY_SIDES and zeros; a point
  /// outside its domain GP_ST_OUTSIDE (with the face's bits) and zeros. Never throws.
  void evaluate(const int32_t* faces, const double* xi, const double* eta, size_t count, PatchPoint* out) noexcept;

  /// The instruction set in use (Auto resolved).
  SimdTarget target() const { return target_; }

 private:
  struct Chunk {
    int32_t face;
    uint32_t begin, end;  // range of order_
  };
  const PatchCache* cache_;
  EvalOptions options_;
  SimdTarget target_;
  std::vector<uint32_t> order_, start_;
  std::vector<Chunk> chunks_;
};

/// Evaluates N points: faces, xi, eta are N long; out gets N results, in order.
/// Backend::Serial or Backend::Tbb (threads <= 0: oneTBB default); OpenCL: see
/// opencl_backend.h. Bad face indices give status GP_ST_OUTSIDE. A PatchEvaluator with the
/// widest SIMD target this CPU runs; throws as its constructor does.
void evaluatePatches(const PatchCache& cache, const int32_t* faces, const double* xi, const double* eta, size_t count,
                     PatchPoint* out, Backend backend, int threads = 0);

/// A batch evaluator: (faces, xi, eta, count, out) as in evaluatePatches, whatever backend.
using BatchEvaluator =
    std::function<void(const int32_t* faces, const double* xi, const double* eta, size_t count, PatchPoint* out)>;

}  // namespace sf
