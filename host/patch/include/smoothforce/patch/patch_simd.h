// SPDX-License-Identifier: Apache-2.0
// SIMD instruction sets of the CPU paths (evaluation, construction), chosen at run time.
//
// The build targets generic x86-64; the patch math of kernels/ is compiled once more per
// instruction set with Google Highway (host/gp_lanes-inl.h) and the widest one this CPU runs
// is used. Every target computes bit-identical results (same operations per lane,
// contraction off); they differ only in speed.
#pragma once

#include <string>
#include <vector>

#include <smoothforce/patch/patch_options.h>

namespace sf {

/// Instruction set of the CPU paths. Scalar: kernels/ as plain C++ (one point or face at a
/// time); SSE4, AVX2, AVX512: Highway's HWY_SSE4 (SSE4.2), HWY_AVX2 (AVX2 + FMA, BMI2),
/// HWY_AVX3 (AVX-512 F, VL, DQ, BW). Auto: the widest of supportedSimdTargets().
enum class SimdTarget { Auto, Scalar, SSE4, AVX2, AVX512 };

/// "auto", "scalar", "sse4", "avx2", "avx512".
const char* toString(SimdTarget t);
/// Parses the names of toString; throws std::invalid_argument naming the value otherwise.
SimdTarget parseSimdTarget(const std::string& s);

/// The targets compiled into this build that this CPU runs, widest first; always ends with
/// Scalar.
std::vector<SimdTarget> supportedSimdTargets();

/// Auto resolved: the first of supportedSimdTargets(). Any other target is returned as it is
/// when supported; throws std::invalid_argument naming it when this CPU or build lacks it.
SimdTarget resolveSimdTarget(SimdTarget t);

/// Points (evaluation) or faces (construction) per vector of the target in that precision
/// (1 for Scalar). Throws like resolveSimdTarget.
int simdLanes(SimdTarget t, Precision p);

}  // namespace sf
