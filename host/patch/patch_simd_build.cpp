// SPDX-License-Identifier: Apache-2.0
// Patch construction on SIMD lanes: faces of one size side by side, one per lane; each lane
// runs gp_build_patch and gp_patch_quality (the same samples, so the same fold and bulge) as
// the scalar path does. Compiled once per Highway target; patch_build.cpp dispatches.
#include <memory>

#include <smoothforce/patch/detail/gp_math.h>
#include "patch_simd_detail.h"

#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS HWY_SSSE3
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "patch_simd_build.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "gp_lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace sf::HWY_NAMESPACE {
#if HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR

template <class T>
struct BuildMath;
template <>
struct BuildMath<double> {
  using Lane = GpLane<double>;
  using vec3 = gd::gp_vec3;
  static std::vector<double>& data(PatchCache& c) { return c.edgeDataD; }
  static GpUint<double> build(int n, const vec3* V, const vec3* N, const GpInt<double>* vid, int mode, Lane* recs) {
    return gd::gp_build_patch(n, V, N, vid, mode, recs);
  }
  static GpUint<double> quality(int n, const Lane* recs, int mode, Lane* bulge) {
    return gd::gp_patch_quality(n, recs, mode, bulge);
  }
};
template <>
struct BuildMath<float> {
  using Lane = GpLane<float>;
  using vec3 = gf::gp_vec3;
  static std::vector<float>& data(PatchCache& c) { return c.edgeDataF; }
  static GpUint<float> build(int n, const vec3* V, const vec3* N, const GpInt<float>* vid, int mode, Lane* recs) {
    return gf::gp_build_patch(n, V, N, vid, mode, recs);
  }
  static GpUint<float> quality(int n, const Lane* recs, int mode, Lane* bulge) {
    return gf::gp_patch_quality(n, recs, mode, bulge);
  }
};

template <class T>
void BuildFacesT(PatchCache& c, const int32_t* faces, size_t count) {
  using M = BuildMath<T>;
  using Lane = typename M::Lane;
  const hn::ScalableTag<T> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  const hn::RebindToSigned<decltype(d)> di;
  using U = hn::TFromD<decltype(du)>;
  using I = hn::TFromD<decltype(di)>;
  const size_t L = hn::Lanes(d);
  constexpr size_t kMax = HWY_MAX_BYTES / sizeof(T);
  if (count == 0) return;
  const int n = c.faceSize(faces[0]), mode = static_cast<int>(c.options.crossTangent);
  static thread_local std::unique_ptr<Lane[]> recs(new Lane[GP_MAX_N * GP_E_NFIELDS]);
  typename M::vec3 V[GP_MAX_N], N[GP_MAX_N];
  GpInt<T> vid[GP_MAX_N];
  HWY_ALIGN T buf[6][kMax];
  HWY_ALIGN I ibuf[kMax];
  HWY_ALIGN U st[kMax], qst[kMax];
  HWY_ALIGN T bulge[kMax], field[kMax];
  int first[kMax];
  std::vector<T>& data = M::data(c);
  const size_t ns = c.numSlots();
  for (size_t base = 0; base < count; base += L) {
    const size_t valid = count - base < L ? count - base : L;
    for (size_t j = 0; j < L; ++j) first[j] = c.faceOffsets[faces[base + (j < valid ? j : valid - 1)]];
    for (int k = 0; k < n; ++k) {  // gather corner k of each lane's face
      for (size_t j = 0; j < L; ++j) {
        const int v = c.faceVertices[first[j] + k];
        const double* p = &c.positions[3 * static_cast<size_t>(v)];
        const double* nn = &c.cornerNormals[3 * static_cast<size_t>(first[j] + k)];
        for (int a = 0; a < 3; ++a) {
          buf[a][j] = static_cast<T>(p[a]);
          buf[3 + a][j] = static_cast<T>(nn[a]);
        }
        ibuf[j] = static_cast<I>(v);
      }
      V[k] = {Lane(hn::Load(d, buf[0])), Lane(hn::Load(d, buf[1])), Lane(hn::Load(d, buf[2]))};
      N[k] = {Lane(hn::Load(d, buf[3])), Lane(hn::Load(d, buf[4])), Lane(hn::Load(d, buf[5]))};
      vid[k].v = hn::Load(di, ibuf);
    }
    const GpUint<T> s = M::build(n, V, N, vid, mode, recs.get());
    Lane b(0.0);
    const GpUint<T> q = M::quality(n, recs.get(), mode, &b);
    hn::Store(s.v, du, st);
    hn::Store(q.v, du, qst);
    hn::Store(b.v, d, bulge);
    for (int k = 0; k < n; ++k)  // scatter the records field-major
      for (int i = 0; i < GP_E_NFIELDS; ++i) {
        hn::Store(recs[k * GP_E_NFIELDS + i].v, d, field);
        T* out = data.data() + static_cast<size_t>(i) * ns + k;
        for (size_t j = 0; j < valid; ++j) out[first[j]] = field[j];
      }
    for (size_t j = 0; j < valid; ++j) {
      const int f = faces[base + j];
      uint32_t status = static_cast<uint32_t>(st[j]);
      const bool built = !(status & GP_ST_NOT_BUILT);
      if (built) status |= static_cast<uint32_t>(qst[j]);
      c.faceStatus[f] = status;
      c.faceBulge[f] = built ? static_cast<float>(bulge[j]) : 0.f;
    }
  }
}

void BuildFacesD(PatchCache& c, const int32_t* faces, size_t count) { BuildFacesT<double>(c, faces, count); }
void BuildFacesF(PatchCache& c, const int32_t* faces, size_t count) { BuildFacesT<float>(c, faces, count); }

#endif  // HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR
}  // namespace sf::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sf::simd_detail {

const BuildFns* buildFns(SimdTarget t) {
  switch (t) {
#if HWY_TARGETS & HWY_AVX3
    case SimdTarget::AVX512: {
      static const BuildFns f{&N_AVX3::BuildFacesD, &N_AVX3::BuildFacesF};
      return &f;
    }
#endif
#if HWY_TARGETS & HWY_AVX2
    case SimdTarget::AVX2: {
      static const BuildFns f{&N_AVX2::BuildFacesD, &N_AVX2::BuildFacesF};
      return &f;
    }
#endif
#if HWY_TARGETS & HWY_SSE4
    case SimdTarget::SSE4: {
      static const BuildFns f{&N_SSE4::BuildFacesD, &N_SSE4::BuildFacesF};
      return &f;
    }
#endif
    default:
      return nullptr;
  }
}

}  // namespace sf::simd_detail
#endif  // HWY_ONCE
