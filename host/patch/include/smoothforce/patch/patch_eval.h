// Evaluating cached patches: one point, or batches on the CPU.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <functional>

#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// A point on a patch: G, dG/dxi, dG/deta, unit normal (Eq. 2-5, exact derivatives) and
/// GP_ST_* status bits (evaluation bits | the face's construction bits).
struct PatchPoint {
  Eigen::Vector3d pos{0, 0, 0}, dxi{0, 0, 0}, deta{0, 0, 0}, normal{0, 0, 0};
  uint32_t status = 0;
};

/// Domain corner C_k = (cos 2 pi k/n, sin 2 pi k/n) (design page, "Domain").
Eigen::Vector2d domainCorner(int n, int k);
/// True when (xi, eta) lies in the regular n-gon domain, up to `tol` in distance.
bool insideDomain(int n, double xi, double eta, double tol = 1e-12);

/// Evaluates face f's patch at (xi, eta) in the cache's precision.
/// Throws std::out_of_range for a face index outside [0, #F). A point outside the domain
/// is not an error here: status has GP_ST_OUTSIDE and the vectors are zero.
PatchPoint evaluatePatch(const PatchCache& cache, int f, double xi, double eta);

/// Evaluates N points: faces, xi, eta are N long; out gets N results, in order.
/// Backend::Serial or Backend::Tbb (threads <= 0: oneTBB default); OpenCL: see
/// opencl_backend.h. Bad face indices give status GP_ST_OUTSIDE.
void evaluatePatches(const PatchCache& cache, const int32_t* faces, const double* xi, const double* eta, size_t count,
                     PatchPoint* out, Backend backend, int threads = 0);

/// A batch evaluator: (faces, xi, eta, count, out) as in evaluatePatches, whatever backend.
using BatchEvaluator =
    std::function<void(const int32_t* faces, const double* xi, const double* eta, size_t count, PatchPoint* out)>;

}  // namespace sf
