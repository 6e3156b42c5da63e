// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/patch_simd.h>

#include <hwy/targets.h>

#include <stdexcept>

#include "patch_simd_detail.h"

namespace sf {

namespace {

int64_t hwyBit(SimdTarget t) {
  switch (t) {
    case SimdTarget::AVX512:
      return HWY_AVX3;
    case SimdTarget::AVX2:
      return HWY_AVX2;
    case SimdTarget::SSE4:
      return HWY_SSE4;
    default:
      return 0;
  }
}

bool runs(SimdTarget t) {
  if (t == SimdTarget::Scalar) return true;
  return simd_detail::evalFns(t) && simd_detail::buildFns(t) && (hwy::SupportedTargets() & hwyBit(t)) != 0;
}

}  // namespace

const char* toString(SimdTarget t) {
  switch (t) {
    case SimdTarget::Auto:
      return "auto";
    case SimdTarget::Scalar:
      return "scalar";
    case SimdTarget::SSE4:
      return "sse4";
    case SimdTarget::AVX2:
      return "avx2";
    case SimdTarget::AVX512:
      return "avx512";
  }
  return "?";
}

SimdTarget parseSimdTarget(const std::string& s) {
  for (SimdTarget t : {SimdTarget::Auto, SimdTarget::Scalar, SimdTarget::SSE4, SimdTarget::AVX2, SimdTarget::AVX512})
    if (s == toString(t)) return t;
  throw std::invalid_argument("SIMD target '" + s + "': expected auto, scalar, sse4, avx2 or avx512");
}

std::vector<SimdTarget> supportedSimdTargets() {
  std::vector<SimdTarget> v;
  for (SimdTarget t : {SimdTarget::AVX512, SimdTarget::AVX2, SimdTarget::SSE4})
    if (runs(t)) v.push_back(t);
  v.push_back(SimdTarget::Scalar);
  return v;
}

SimdTarget resolveSimdTarget(SimdTarget t) {
  if (t == SimdTarget::Auto) {
    static const SimdTarget best = supportedSimdTargets().front();
    return best;
  }
  if (!runs(t))
    throw std::invalid_argument(std::string("SIMD target ") + toString(t) +
                                ": not compiled into this build or not supported by this CPU");
  return t;
}

int simdLanes(SimdTarget t, Precision p) {
  t = resolveSimdTarget(t);
  if (t == SimdTarget::Scalar) return 1;
  const simd_detail::EvalFns* f = simd_detail::evalFns(t);
  return p == Precision::Double ? f->lanesD : f->lanesF;
}

}  // namespace sf
