// SPDX-License-Identifier: Apache-2.0
// Internal: the per-target entry points of the SIMD paths (patch_simd_eval.cpp,
// patch_simd_build.cpp), looked up by target. Not part of the public API.
#pragma once

#include <cstddef>
#include <cstdint>

#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/patch_simd.h>

namespace sf::simd_detail {

/// Queries on one face f (n sides, 3..GP_MAX_N, built): idx[0..count) index xi, eta, out.
struct EvalGroup {
  int n = 0, mode = 0;
  const void* data = nullptr;  ///< the cache's field-major records, double or float
  size_t numSlots = 0;         ///< #C, the stride of a field
  int first = 0;               ///< first slot of the face
  uint32_t faceStatus = 0;     ///< OR-ed into every point's status; GP_ST_AFFINE selects the affine map
  const uint32_t* idx = nullptr;
  size_t count = 0;
  const double* xi = nullptr;
  const double* eta = nullptr;
  /// the group's points in order (xs[j] = xi[idx[j]]), readable up to count + kPointPad
  const double* xs = nullptr;
  const double* ys = nullptr;
  PatchPoint* out = nullptr;     ///< results: out[idx[j]] ...
  PatchPoint* sorted = nullptr;  ///< ... or sorted[j] when set (the caller copies them to out)
  /// scratch for the face's records as vectors: GP_MAX_N * GP_E_NFIELDS vectors of 64 bytes,
  /// 64-byte aligned; null: a buffer of the calling thread (allocated on its first use)
  void* laneRecs = nullptr;
  /// laneRecs already holds this face's records as this target's vectors (the caller's last
  /// group was the same face, target and cache): they are not broadcast again
  bool laneRecsReady = false;
};
using EvalFn = void (*)(const EvalGroup&);
/// Readable values after the last point of EvalGroup::xs, ys (the widest vector's lanes).
constexpr size_t kPointPad = 64;

/// Builds faces[0..count) of `cache` (all of one size n in 3..GP_MAX_N) as constructPatches
/// does: records, faceStatus, faceBulge.
using BuildFn = void (*)(PatchCache& cache, const int32_t* faces, size_t count);

struct EvalFns {
  EvalFn evalD = nullptr, evalF = nullptr;
  int lanesD = 1, lanesF = 1;
};
struct BuildFns {
  BuildFn buildD = nullptr, buildF = nullptr;
};

/// Entry points of a SIMD target (SSE4, AVX2, AVX512) that this build compiled; nullptr
/// otherwise. The caller checks that the CPU runs it (resolveSimdTarget).
const EvalFns* evalFns(SimdTarget t);
const BuildFns* buildFns(SimdTarget t);

}  // namespace sf::simd_detail
