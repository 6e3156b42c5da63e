// SPDX-License-Identifier: Apache-2.0
// Patch construction on the CPU with options: backend, threads and SIMD target.
#pragma once

#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/patch/patch_simd.h>

namespace sf {

/// Options of constructPatches.
struct BuildOptions {
  Backend backend = Backend::Tbb;      ///< Serial (the calling thread) or Tbb
  int threads = 0;                     ///< Tbb worker limit (<= 0: oneTBB's default), in a task_arena
  SimdTarget simd = SimdTarget::Auto;  ///< instruction set (patch_simd.h); every one gives the same bits
};

/// Builds every patch and its quality as constructPatches(cache, backend, threads) does (that
/// one is this with SimdTarget::Auto). With a SIMD target, faces of one size are built side by
/// side, one per lane: records, status and bulge are bit-identical to Scalar's (the quality
/// uses the same 15 samples per edge). Throws std::invalid_argument for Backend::OpenCL, a
/// target this CPU or build lacks, or a skeleton cache (no patch arrays).
void constructPatches(PatchCache& cache, const BuildOptions& options);

}  // namespace sf
