// SPDX-License-Identifier: Apache-2.0
// Operation counts of the patch math: kernels/gp_patch.h compiled with GP_REAL a scalar that
// counts what it does, once on the scalar path (branches taken as a point needs them) and
// once on the lane path (GP_LANES: both sides of every select, as each SIMD lane executes).
// The instantiation goes through the same prologue as the SIMD lanes (kernels/gp_instantiate.h:
// overloadable gp_sqrt etc., gp_sel, gp_lane_mask), so it follows the math as it changes.
#pragma once

#include <cmath>

#include <smoothforce/patch/detail/gp_math.h>

namespace sf::flops {

struct Counts {
  long add = 0, mul = 0, div = 0, sqrt = 0, trig = 0, cmp = 0, sel = 0;
  /// + - * / sqrt: the floating-point operations (a select or compare is not one)
  long flops() const { return add + mul + div + sqrt; }
};
inline Counts g;

/// A double that counts its operations into g.
struct R {
  double v;
  R() = default;
  R(double x) : v(x) {}  // NOLINT: implicit, as a built-in real converts
  friend R operator+(R a, R b) { return ++g.add, R(a.v + b.v); }
  friend R operator-(R a, R b) { return ++g.add, R(a.v - b.v); }
  friend R operator*(R a, R b) { return ++g.mul, R(a.v * b.v); }
  friend R operator/(R a, R b) { return ++g.div, R(a.v / b.v); }
  friend R operator-(R a) { return R(-a.v); }  // sign flip: not counted
  R& operator+=(R b) { return *this = *this + b; }
  R& operator-=(R b) { return *this = *this - b; }
  R& operator*=(R b) { return *this = *this * b; }
  friend bool operator<(R a, R b) { return ++g.cmp, a.v < b.v; }
  friend bool operator>(R a, R b) { return ++g.cmp, a.v > b.v; }
  friend bool operator<=(R a, R b) { return ++g.cmp, a.v <= b.v; }
  friend bool operator>=(R a, R b) { return ++g.cmp, a.v >= b.v; }
  friend R gp_sqrt(R a) { return ++g.sqrt, R(std::sqrt(a.v)); }
  friend R gp_cos(R a) { return ++g.trig, R(std::cos(a.v)); }
  friend R gp_sin(R a) { return ++g.trig, R(std::sin(a.v)); }
  friend R gp_fabs(R a) { return R(std::fabs(a.v)); }
};
// ---- the scalar path, with its own domain table (filled before main, not counted) ----
namespace scalar {
#define GP_REAL R
#define GP_IS_DOUBLE 1
#define GP_INST_TABLE 1
#include "gp_instantiate.h"
inline gp_domain domainTable[GP_MAX_N + 1];
inline const bool domainTableFilled = [] {
  for (int n = 3; n <= GP_MAX_N; ++n) gp_domain_init(n, &domainTable[n], 1);
  return true;
}();
inline const gp_domain* gp_domain_table() { return domainTable; }
}  // namespace scalar

// ---- the lane path: one lane of the SIMD evaluation, selects instead of branches ----
namespace lanes {
using sf::gpd::gp_domain;
using sf::gpd::gp_domain_of;
using sf::gpd::gp_quality_sample;
using gp_lane_mask = bool;
using gp_lane_status = gp_uint;
using gp_lane_vid = int;
/// A select of the lane path: both sides were computed; counts one.
inline R gp_sel(bool m, R a, R b) { return ++g.sel, m ? a : b; }
inline gp_uint gp_sel(bool m, gp_uint a, gp_uint b) { return m ? a : b; }
inline bool gp_any(bool m) { return m; }
inline bool gp_all(bool m) { return m; }
#define GP_LANES 1
#define GP_SREAL double
#define GP_REAL R
#define GP_IS_DOUBLE 1
#include "gp_instantiate.h"
}  // namespace lanes

/// A regular n-gon (unit circle, normals tilted outward, so no fallback runs): V, N, vid.
template <class Vec3, class MakeV3>
void regularPolygon(int n, Vec3* V, Vec3* N, int* vid, MakeV3 v3) {
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n, l = std::sqrt(1.0 + 0.09);
    V[k] = v3(R(std::cos(a)), R(std::sin(a)), R(0.0));
    N[k] = v3(R(0.3 * std::cos(a) / l), R(0.3 * std::sin(a) / l), R(1.0 / l));
    vid[k] = k;
  }
}

/// Operations of one evaluation of that patch at an interior point (0.13, -0.21): the scalar
/// path (lanes false) or one SIMD lane (lanes true).
inline Counts countEval(int n, bool lanes) {
  scalar::gp_vec3 V[GP_MAX_N], N[GP_MAX_N];
  int vid[GP_MAX_N];
  regularPolygon(n, V, N, vid, scalar::gp_v3);
  static R recs[GP_MAX_N * GP_E_NFIELDS];
  scalar::gp_build_patch(n, V, N, vid, GP_CT_CORRECTED, recs);
  g = Counts{};
  const R x = 0.13, y = -0.21;
  if (lanes)
    lanes::gp_patch_eval_dom(sf::gpd::gp_domain_of(n, nullptr, 0), recs, GP_CT_CORRECTED, x, y);
  else
    scalar::gp_patch_eval(n, recs, GP_CT_CORRECTED, x, y);
  return g;
}

/// Operations of building that patch with its quality (gp_build_patch + gp_patch_quality:
/// the records and 15 n quality samples).
inline Counts countBuild(int n, bool lanes) {
  static R recs[GP_MAX_N * GP_E_NFIELDS];
  int vid[GP_MAX_N];
  R bulge = 0;
  if (lanes) {
    lanes::gp_vec3 V[GP_MAX_N], N[GP_MAX_N];
    regularPolygon(n, V, N, vid, lanes::gp_v3);
    g = Counts{};
    lanes::gp_build_patch(n, V, N, vid, GP_CT_CORRECTED, recs);
    lanes::gp_patch_quality(n, recs, GP_CT_CORRECTED, &bulge);
  } else {
    scalar::gp_vec3 V[GP_MAX_N], N[GP_MAX_N];
    regularPolygon(n, V, N, vid, scalar::gp_v3);
    g = Counts{};
    scalar::gp_build_patch(n, V, N, vid, GP_CT_CORRECTED, recs);
    scalar::gp_patch_quality(n, recs, GP_CT_CORRECTED, &bulge);
  }
  return g;
}

}  // namespace sf::flops
