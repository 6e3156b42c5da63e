// SPDX-License-Identifier: Apache-2.0
// Nearest-point refinement on the patches (paper Section 4.2, Eq. 15 transitions) for a batch
// of HIPs at once on an OpenCL device: kernels/refine.cl runs gp_refine_newton
// (kernels/gp_refine.h), the Newton variant of PatchRefiner (patch_refine.h), one work-item
// per HIP.
//
// Agreement with PatchRefiner (both RefineMethods), asserted by tests/opencl/test_opencl_refine.cpp
// on the spot cage and the quad sphere: double caches: the same bits (SCP, normal, face, edge,
// iterations, status: the same operations on the host's constants, opencl_backend.h); float
// caches: the kernel computes in float (PatchRefiner in double around float evaluations), SCP
// within 1e-4 x diagonal, the normal the host's float evaluation at the device's point (see
// the test for the measured numbers).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <string>

#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/query/patch_refine.h>
#include <smoothforce/query/refine_options.h>

namespace sf {

/// One refinement query: refine from (face, xi, eta) towards the patch point nearest hip.
struct RefineQuery {
  Eigen::Vector3d hip{0, 0, 0};  ///< m
  int face = -1;                 ///< start face
  double xi = 0, eta = 0;        ///< start point in its domain (clamped into it)
  int edge = -1;                 ///< domain edge the start is held on (RefineResult::edge of the
                                 ///< refinement that ended there), -1 for none
  /// this query's iteration limit: -1 the options' maxIterations; 0 the start is evaluated and
  /// tested only (a seed: RefineResult::startMinimum); else >= 1
  int maxIterations = -1;
};

/// Reusable batch refiner over one cache: uploads the cache (face offsets, records, face
/// status, slot twins) once, then refine() runs N queries per call. Device and host staging
/// buffers grow only when N exceeds their capacity. The kernel works in the cache's precision
/// (double needs cl_khr_fp64). Both RefineMethods run on the device (kernels/gp_refine.h, as
/// PatchRefiner runs them on the CPU).
/// Errors: OpenCLError (opencl_context.h) naming the call, the error code and, for builds, the
/// build log; "device X has no cl_khr_fp64; use --precision float" for a double cache on such
/// a device; std::invalid_argument for a cache without records of its precision; InputError
/// for invalid options (validateRefineOptions).
class OpenCLRefiner {
 public:
  /// The cache must outlive the refiner (its bounding box and face sizes are read here).
  explicit OpenCLRefiner(const PatchCache& cache, const OpenCLOptions& opt = {});
  ~OpenCLRefiner();
  OpenCLRefiner(OpenCLRefiner&&) noexcept;
  OpenCLRefiner& operator=(OpenCLRefiner&&) noexcept;

  /// queries, out: n each. out[i] as PatchRefiner::refine(queries[i].hip, face, xi, eta,
  /// options) would return it (scp, normal, face, edge, xi, eta, distance, iterations,
  /// transitions, status = SF_TRACK_* | GP_ST_*); an unusable start gives SF_TRACK_DEGENERATE
  /// and zeros. options.angleTolerance (rad), positionTolerance, maxIterations and finalStep are
  /// used; refine must be Newton.
  void refine(const RefineQuery* queries, size_t n, const RefineOptions& options, RefineResult* out);

  Precision precision() const;
  std::string deviceName() const;
  /// Program build (or binary-cache load) wall time, s; device time of the cache upload, s.
  double buildSeconds() const;
  double uploadSeconds() const;
  /// Of the last refine(): kernel time and transfer time (profiling events), s.
  double lastKernelSeconds() const;
  double lastTransferSeconds() const;
  size_t workGroupSize() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot wrapper (builds or loads the program, uploads the cache, refines once).
void refineNearestPointsOpenCL(const PatchCache& cache, const RefineQuery* queries, size_t n,
                               const RefineOptions& options, RefineResult* out, const OpenCLOptions& opt = {});

}  // namespace sf
