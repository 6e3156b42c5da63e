// SPDX-License-Identifier: Apache-2.0
// Lane types for the single-source patch math: kernels/gp_patch.h compiled once more per SIMD
// target (Google Highway's HWY_NAMESPACE) and precision, with GP_REAL a vector of the
// target's full width (SSE4: 2 doubles / 4 floats, AVX2: 4 / 8, AVX-512: 8 / 16). Each lane
// computes exactly the scalar operations (kernels/gp_vec.h, "Lanes"; contraction is off), so
// a lane's result is bit-identical to sf::gpd / sf::gpf on the same input.
//
// Gives, inside sf::HWY_NAMESPACE: GpLane<T>, GpMask<T>, GpUint<T> (status bits), GpInt<T>
// (vertex ids) and the namespaces gd (double) and gf (float) with the whole patch math
// (gp_patch_eval_dom, gp_build_patch, gp_patch_quality, ...) on lanes. The domain tables
// are the scalar ones (sf::gpd::gp_domain_of). Include after <hwy/highway.h> and
// "gp_math.h", in a file compiled per target with hwy/foreach_target.h. Per-target include
// guard, as Highway's -inl.h headers have.
#if defined(SF_GP_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SF_GP_LANES_INL_H_
#undef SF_GP_LANES_INL_H_
#else
#define SF_GP_LANES_INL_H_
#endif

// no lanes for Highway's scalar fallbacks: the scalar path is kernels/ as plain C++
#if HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR
HWY_BEFORE_NAMESPACE();
namespace sf::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class T>
struct GpMask {
  using D = hn::ScalableTag<T>;
  hn::Mask<D> m;
  friend HWY_INLINE GpMask operator&&(GpMask a, GpMask b) { return {hn::And(a.m, b.m)}; }
  friend HWY_INLINE GpMask operator||(GpMask a, GpMask b) { return {hn::Or(a.m, b.m)}; }
  friend HWY_INLINE GpMask operator!(GpMask a) { return {hn::Not(a.m)}; }
  friend HWY_INLINE bool gp_any(GpMask a) { return !hn::AllFalse(D(), a.m); }
  friend HWY_INLINE bool gp_all(GpMask a) { return hn::AllTrue(D(), a.m); }
};

/// A real per lane; arithmetic, comparisons, sqrt and fabs as the scalar ones, lane by lane.
template <class T>
struct GpLane {
  using D = hn::ScalableTag<T>;
  using V = hn::Vec<D>;
  V v;
  GpLane() = default;
  HWY_INLINE GpLane(V x) : v(x) {}                                     // NOLINT: implicit
  HWY_INLINE GpLane(double x) : v(hn::Set(D(), static_cast<T>(x))) {}  // NOLINT: like a scalar
  friend HWY_INLINE GpLane operator+(GpLane a, GpLane b) { return a.v + b.v; }
  friend HWY_INLINE GpLane operator-(GpLane a, GpLane b) { return a.v - b.v; }
  friend HWY_INLINE GpLane operator*(GpLane a, GpLane b) { return a.v * b.v; }
  friend HWY_INLINE GpLane operator/(GpLane a, GpLane b) { return a.v / b.v; }
  friend HWY_INLINE GpLane operator-(GpLane a) { return hn::Neg(a.v); }
  HWY_INLINE GpLane& operator+=(GpLane b) { return v = v + b.v, *this; }
  HWY_INLINE GpLane& operator-=(GpLane b) { return v = v - b.v, *this; }
  HWY_INLINE GpLane& operator*=(GpLane b) { return v = v * b.v, *this; }
  friend HWY_INLINE GpMask<T> operator<(GpLane a, GpLane b) { return {a.v < b.v}; }
  friend HWY_INLINE GpMask<T> operator>(GpLane a, GpLane b) { return {a.v > b.v}; }
  friend HWY_INLINE GpMask<T> operator<=(GpLane a, GpLane b) { return {a.v <= b.v}; }
  friend HWY_INLINE GpMask<T> operator>=(GpLane a, GpLane b) { return {a.v >= b.v}; }
  friend HWY_INLINE GpLane gp_sqrt(GpLane a) { return hn::Sqrt(a.v); }
  friend HWY_INLINE GpLane gp_fabs(GpLane a) { return hn::Abs(a.v); }
  friend HWY_INLINE GpLane gp_sel(GpMask<T> m, GpLane a, GpLane b) { return hn::IfThenElse(m.m, a.v, b.v); }
};

/// Status bits per lane: unsigned integers as wide as T (the low 32 bits are used).
template <class T>
struct GpUint {
  using D = hn::RebindToUnsigned<hn::ScalableTag<T>>;
  using V = hn::Vec<D>;
  V v;
  GpUint() = default;
  HWY_INLINE GpUint(V x) : v(x) {}                                                   // NOLINT: implicit
  HWY_INLINE GpUint(unsigned x) : v(hn::Set(D(), static_cast<hn::TFromD<D>>(x))) {}  // NOLINT
  friend HWY_INLINE GpUint operator|(GpUint a, GpUint b) { return a.v | b.v; }
  friend HWY_INLINE GpUint operator&(GpUint a, GpUint b) { return a.v & b.v; }
  HWY_INLINE GpUint& operator|=(GpUint b) { return v = v | b.v, *this; }
  friend HWY_INLINE GpUint gp_sel(GpMask<T> m, GpUint a, GpUint b) {
    return hn::IfThenElse(hn::RebindMask(D(), m.m), a.v, b.v);
  }
};

/// A vertex id per lane (signed integers as wide as T); <= gives a GpMask<T>.
template <class T>
struct GpInt {
  using D = hn::RebindToSigned<hn::ScalableTag<T>>;
  hn::Vec<D> v;
  friend HWY_INLINE GpMask<T> operator<=(GpInt a, GpInt b) {
    return {hn::RebindMask(hn::ScalableTag<T>(), hn::Not(a.v > b.v))};
  }
};

/// Lanes per vector of T on this target.
template <class T>
HWY_INLINE size_t gpLanes() {
  return hn::Lanes(hn::ScalableTag<T>());
}

// ---- the patch math on lanes, once per precision (kernels/gp_instantiate.h) ----
namespace gd {
using sf::gpd::gp_domain;
using sf::gpd::gp_domain_of;
using sf::gpd::gp_quality_sample;
using gp_lane_mask = GpMask<double>;
using gp_lane_status = GpUint<double>;
using gp_lane_vid = GpInt<double>;
#define GP_LANES 1
#define GP_SREAL double
#define GP_REAL GpLane<double>
#define GP_IS_DOUBLE 1
#include "gp_instantiate.h"
}  // namespace gd

namespace gf {
using sf::gpf::gp_domain;
using sf::gpf::gp_domain_of;
using sf::gpf::gp_quality_sample;
using gp_lane_mask = GpMask<float>;
using gp_lane_status = GpUint<float>;
using gp_lane_vid = GpInt<float>;
#define GP_LANES 1
#define GP_SREAL float
#define GP_REAL GpLane<float>
#define GP_IS_DOUBLE 0
#include "gp_instantiate.h"
}  // namespace gf

}  // namespace sf::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();
#endif  // HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR

#endif  // SF_GP_LANES_INL_H_
