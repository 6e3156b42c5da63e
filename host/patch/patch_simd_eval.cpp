// SPDX-License-Identifier: Apache-2.0
// Batch evaluation on SIMD lanes: the points of one face side by side, one per lane, its
// records broadcast once per group (read in place from the field-major cache). Compiled once
// per Highway target (hwy/foreach_target.h); patch_eval.cpp dispatches.
#include <cstring>
#include <memory>
#include <type_traits>

#include <smoothforce/patch/detail/gp_math.h>
#include "patch_simd_detail.h"

// SSSE3 adds nothing over the scalar path for doubles; HWY_EMU128 (the baseline) is the
// scalar path's job (kernels/ as plain C++), so no lanes are compiled for it.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS HWY_SSSE3
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "patch_simd_eval.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "gp_lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace sf::HWY_NAMESPACE {
#if HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR

/// The lane instantiation of one precision.
template <class T>
struct LaneMath;
template <>
struct LaneMath<double> {
  using Lane = GpLane<double>;
  using Dom = sf::gpd::gp_domain;
  static const Dom* domain(int n) { return sf::gpd::gp_domain_of(n, nullptr, 1); }
  static gd::gp_eval_result eval(const Dom* dom, const Lane* recs, int mode, Lane x, Lane y) {
    return gd::gp_patch_eval_dom(dom, recs, mode, x, y);
  }
};
template <>
struct LaneMath<float> {
  using Lane = GpLane<float>;
  using Dom = sf::gpf::gp_domain;
  static const Dom* domain(int n) { return sf::gpf::gp_domain_of(n, nullptr, 1); }
  static gf::gp_eval_result eval(const Dom* dom, const Lane* recs, int mode, Lane x, Lane y) {
    return gf::gp_patch_eval_dom(dom, recs, mode, x, y);
  }
};

/// L consecutive points (doubles) as a vector of T: loaded in place, so that no vector load
/// waits on lane-by-lane stores (a failed store forward stalls until every earlier store, the
/// scattered results included, has left the store buffer).
template <class D>
HWY_INLINE hn::Vec<D> LoadPoints(D d, const double* p) {
  if constexpr (std::is_same_v<hn::TFromD<D>, double>) {
    return hn::LoadU(d, p);
  } else {
    const hn::Repartition<double, D> dd;
    const hn::Half<D> dh;
    const auto lo = hn::DemoteTo(dh, hn::LoadU(dd, p));
    const auto hi = hn::DemoteTo(dh, hn::LoadU(dd, p + hn::Lanes(dd)));
    return hn::Combine(d, hi, lo);
  }
}

template <class T>
void EvalGroupT(const simd_detail::EvalGroup& g) {
  using M = LaneMath<T>;
  using Lane = typename M::Lane;
  const hn::ScalableTag<T> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  using U = hn::TFromD<decltype(du)>;
  const size_t L = hn::Lanes(d);
  constexpr size_t kMax = HWY_MAX_BYTES / sizeof(T);
  // the face's records, each field broadcast to all lanes (record-major)
  static_assert(sizeof(Lane) <= 64 && alignof(Lane) <= 64, "EvalGroup::laneRecs holds 64-byte vectors");
  Lane* recs = static_cast<Lane*>(g.laneRecs);
  if (!recs) {
    static thread_local std::unique_ptr<Lane[]> mine(new Lane[GP_MAX_N * GP_E_NFIELDS]);
    recs = mine.get();
  }
  const T* data = static_cast<const T*>(g.data);
  if (!(g.laneRecs && g.laneRecsReady))
    for (int i = 0; i < GP_E_NFIELDS; ++i) {
      const T* field = data + static_cast<size_t>(i) * g.numSlots + g.first;
      for (int k = 0; k < g.n; ++k) recs[k * GP_E_NFIELDS + i] = Lane(hn::Set(d, field[k]));
    }
  const typename M::Dom* dom = M::domain(g.n);
  const int mode = sf::gpd::gp_eval_mode(g.mode, g.faceStatus);
  HWY_ALIGN T res[12][kMax];
  HWY_ALIGN U st[kMax];
  for (size_t base = 0; base < g.count; base += L) {
    const size_t valid = g.count - base < L ? g.count - base : L;
    // the spare lanes of the last vector compute the points after the group (never stored)
    const auto r = M::eval(dom, recs, mode, Lane(LoadPoints(d, g.xs + base)), Lane(LoadPoints(d, g.ys + base)));
    const Lane* comp[12] = {&r.pos.x,  &r.pos.y,  &r.pos.z,  &r.dxi.x,    &r.dxi.y,    &r.dxi.z,
                            &r.deta.x, &r.deta.y, &r.deta.z, &r.normal.x, &r.normal.y, &r.normal.z};
    for (int c = 0; c < 12; ++c) hn::Store(comp[c]->v, d, res[c]);
    hn::Store(r.status.v, du, st);
    for (size_t j = 0; j < valid; ++j) {
      PatchPoint& p = g.sorted ? g.sorted[base + j] : g.out[g.idx[base + j]];
      p.pos = {res[0][j], res[1][j], res[2][j]};
      p.dxi = {res[3][j], res[4][j], res[5][j]};
      p.deta = {res[6][j], res[7][j], res[8][j]};
      p.normal = {res[9][j], res[10][j], res[11][j]};
      p.status = static_cast<uint32_t>(st[j]) | g.faceStatus;
    }
  }
}

void EvalGroupD(const simd_detail::EvalGroup& g) { EvalGroupT<double>(g); }
void EvalGroupF(const simd_detail::EvalGroup& g) { EvalGroupT<float>(g); }
int LanesD() { return static_cast<int>(gpLanes<double>()); }
int LanesF() { return static_cast<int>(gpLanes<float>()); }

#endif  // HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR
}  // namespace sf::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sf::simd_detail {

const EvalFns* evalFns(SimdTarget t) {
  switch (t) {
#if HWY_TARGETS & HWY_AVX3
    case SimdTarget::AVX512: {
      static const EvalFns f{&N_AVX3::EvalGroupD, &N_AVX3::EvalGroupF, N_AVX3::LanesD(), N_AVX3::LanesF()};
      return &f;
    }
#endif
#if HWY_TARGETS & HWY_AVX2
    case SimdTarget::AVX2: {
      static const EvalFns f{&N_AVX2::EvalGroupD, &N_AVX2::EvalGroupF, N_AVX2::LanesD(), N_AVX2::LanesF()};
      return &f;
    }
#endif
#if HWY_TARGETS & HWY_SSE4
    case SimdTarget::SSE4: {
      static const EvalFns f{&N_SSE4::EvalGroupD, &N_SSE4::EvalGroupF, N_SSE4::LanesD(), N_SSE4::LanesF()};
      return &f;
    }
#endif
    default:
      return nullptr;
  }
}

}  // namespace sf::simd_detail
#endif  // HWY_ONCE
