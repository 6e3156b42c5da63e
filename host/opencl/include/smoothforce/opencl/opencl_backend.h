// SPDX-License-Identifier: Apache-2.0
// OpenCL backend: patch construction and batch evaluation on an OpenCL device, with the
// same single-source math (kernels/gp_patch.h) as the CPU backends.
//
// Floating-point decision: contraction is pinned OFF on both sides (kernels/gp_config.h has
// `#pragma OPENCL FP_CONTRACT OFF`; the host builds with -ffp-contract=off), float programs get
// -cl-fp32-correctly-rounded-divide-sqrt where the device offers it, and the kernels read the
// domain's cos and sin (gp_tables.h) from the host's table, uploaded once per program
// (Device::domainTable), instead of computing their own: the device's libm differs from the
// host's by an ulp in many of them (bench/opencl_rounding: 684 of 8,370 double constants on
// PoCL 3.1, 1,154 on an NVIDIA H200), and near a domain edge an ulp there is amplified: with
// their own cos and sin the kernels left a sliver triangle's double evaluation 2.8e-8 off and
// float normals 5.2e-4 rad off on an H100, 4.0e-4 rad and a tie on another face on an H200. So
// the kernels round every operation as the C++ instantiation does.
// Measured against constructPatches / evaluatePatches / PatchRefiner on the meshes of
// tests/opencl (spot cage, hexaSphere, dodecahedron, random prisms and antiprisms, the extreme
// polygons of tests/robustness), on PoCL 3.1 (CPU, LLVM 15) and on an NVIDIA H200 (driver
// 580.159.04): records, bulges, status words, evaluations and refinements the same bits, in
// double and in float.
// tests/opencl asserts exactly that: equality in double; in float where / and sqrt are
// correctly rounded on the device, else within 2e-5 x diagonal (normals: 2 x the CPU's own
// float-vs-double error + 2e-5).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/patch/patch_eval.h>

namespace sf {

/// Where and how OpenCL programs are built.
/// device:         "" = first GPU, else first CPU; "<k>" = k-th device over all platforms
///                 in order; otherwise a case-insensitive substring of the device name.
/// binaryCacheDir: program-binary cache; "" = $XDG_CACHE_HOME/smoothforce/cl or
///                 ~/.cache/smoothforce/cl.
/// useBinaryCache: false = always build from source (and write nothing).
/// workGroupSize:  work-items per work-group; 0 = automatic: 64 on GPUs; on CPU devices
///                 small enough that the group's private arrays (~30 KB per item in double
///                 for GP_MAX_N = 64) stay within 1 MiB of the worker thread's stack (32 on
///                 PoCL; larger groups crashed PoCL, and speed is flat from 1 to 128).
struct OpenCLOptions {
  std::string device;
  std::string binaryCacheDir;
  bool useBinaryCache = true;
  size_t workGroupSize = 0;
};

/// True when at least one OpenCL device exists; otherwise *why gets the reason. Never throws.
bool openclAvailable(std::string* why = nullptr);

/// Reusable patch construction: one work-item per face runs gp_build_patch +
/// gp_patch_quality. Programs (float, double) are built on first use and kept.
/// Errors: OpenCLError (opencl_context.h) for any OpenCL failure, naming the call and error
/// code, with the build log for build failures; for double precision on a device without
/// cl_khr_fp64: "device X has no cl_khr_fp64; use --precision float".
class OpenCLConstructor {
 public:
  explicit OpenCLConstructor(const OpenCLOptions& opt = {});
  ~OpenCLConstructor();
  OpenCLConstructor(OpenCLConstructor&&) noexcept;
  OpenCLConstructor& operator=(OpenCLConstructor&&) noexcept;

  /// Fills cache.edgeDataD or edgeDataF (per cache.options.precision), faceStatus and
  /// faceBulge exactly as constructPatches(cache, Backend::Tbb) does. The cache must come
  /// from preparePatchCache (array sizes are checked: std::invalid_argument).
  void construct(PatchCache& cache);

  std::string deviceName() const;
  /// Wall time to obtain the program last used (create + build, or load from the binary
  /// cache), seconds; and whether it came from the cache.
  double buildSeconds() const;
  bool programFromCache() const;
  /// Of the last construct(): kernel time and host<->device transfer time (profiling
  /// events, device clock), seconds.
  double lastKernelSeconds() const;
  double lastTransferSeconds() const;
  /// Work-group size used by the last construct().
  size_t workGroupSize() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Fills cache.edgeDataD/F, faceStatus, faceBulge exactly as constructPatches(Backend::Tbb)
/// does, with one work-item per face running gp_build_patch + gp_patch_quality.
/// One-shot: builds (or loads) the program each call; use OpenCLConstructor for repeats.
void constructPatchesOpenCL(PatchCache& cache, const OpenCLOptions& opt = {});

/// Reusable batch evaluator: uploads a cache once (face offsets, records, face status),
/// then evaluates N queries (face, xi, eta) per call into N PatchPoints, equal to
/// evaluatePatches(Backend::Tbb) up to the tolerance stated above. Device buffers for the
/// queries are kept and grown only when N exceeds their capacity: repeated batches of the
/// same or smaller size allocate nothing on the device (the host staging vectors likewise).
/// The kernel works in the cache's precision: double queries are rounded to float for a
/// float cache, exactly as the CPU path does. Errors as OpenCLConstructor.
class OpenCLEvaluator {
 public:
  /// Builds the program for cache.options.precision and uploads the cache.
  explicit OpenCLEvaluator(const PatchCache& cache, const OpenCLOptions& opt = {});
  ~OpenCLEvaluator();
  OpenCLEvaluator(OpenCLEvaluator&&) noexcept;
  OpenCLEvaluator& operator=(OpenCLEvaluator&&) noexcept;

  /// Replaces the uploaded cache (builds the other precision's program if needed). Query
  /// buffers are kept.
  void setCache(const PatchCache& cache);

  /// faces, xi, eta: n each (domain coordinates of the face's regular n-gon, see
  /// domainCorner); out: n results. A face index outside [0, #F) gives status
  /// GP_ST_OUTSIDE and zeros; a point outside the domain gives GP_ST_OUTSIDE.
  void evaluate(const int32_t* faces, const double* xi, const double* eta, size_t n, PatchPoint* out);
  /// The same with float coordinates (no conversion for a float cache).
  void evaluate(const int32_t* faces, const float* xi, const float* eta, size_t n, PatchPoint* out);

  Precision precision() const;
  std::string deviceName() const;
  /// Query capacity of the device buffers (points), and how often they were (re)allocated.
  size_t capacity() const;
  size_t allocations() const;
  /// Program build (or cache load) wall time, s, and whether it came from the binary cache.
  double buildSeconds() const;
  bool programFromCache() const;
  /// Device time of the last setCache upload, s.
  double uploadSeconds() const;
  /// Of the last evaluate(): kernel time; query upload + result download time (profiling
  /// events, device clock); host-side conversion time (wall clock), s.
  double lastKernelSeconds() const;
  double lastTransferSeconds() const;
  double lastHostSeconds() const;
  /// Work-group size of the evaluation kernel in use.
  size_t workGroupSize() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot convenience wrapper around OpenCLEvaluator.
void evaluatePatchesOpenCL(const PatchCache& cache, const int32_t* faces, const double* xi, const double* eta, size_t n,
                           PatchPoint* out, const OpenCLOptions& opt = {});

}  // namespace sf
