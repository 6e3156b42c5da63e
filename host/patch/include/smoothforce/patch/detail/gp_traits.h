// SPDX-License-Identifier: Apache-2.0
// Picks the float or double instantiation of the shared patch math by type.
#pragma once

#include <smoothforce/patch/detail/gp_math.h>

namespace sf {

template <class Real>
struct Gp;

template <>
struct Gp<float> {
  using vec3 = gpf::gp_vec3;
  using result = gpf::gp_eval_result;
  static vec3 v3(double x, double y, double z) { return gpf::gp_v3(float(x), float(y), float(z)); }
  /// gp_build_patch_with: creased or not, with end tangents TS, TE where given (may be null).
  static gp_uint buildWith(int n, const vec3* V, const vec3* N, const vec3* PS, const vec3* PE, bool creased,
                           const vec3* TS, const vec3* TE, const int* vid, int mode, float* recs) {
    return gpf::gp_build_patch_with(n, V, N, PS, PE, creased ? 1 : 0, TS, TE, vid, mode, recs);
  }
  static gp_uint quality(int n, const float* recs, int mode, float* bulge) {
    return gpf::gp_patch_quality(n, recs, mode, bulge);
  }
  static result eval(int n, const float* recs, int mode, double xi, double eta) {
    return gpf::gp_patch_eval(n, recs, mode, float(xi), float(eta));
  }
  /// The domain table entry of the n-gon, 3 <= n <= GP_MAX_N.
  static const gpf::gp_domain* domain(int n) { return gpf::gp_domain_of(n, nullptr, 1); }
  static result evalDom(const gpf::gp_domain* dom, const float* recs, int mode, double xi, double eta) {
    return gpf::gp_patch_eval_dom(dom, recs, mode, float(xi), float(eta));
  }
  /// The position only (gp_patch_eval_dom_d, deriv 0: the quality check's bulge samples).
  static result evalDomPosition(const gpf::gp_domain* dom, const float* recs, int mode, double xi, double eta) {
    return gpf::gp_patch_eval_dom_d(dom, recs, mode, float(xi), float(eta), 0);
  }
};

template <>
struct Gp<double> {
  using vec3 = gpd::gp_vec3;
  using result = gpd::gp_eval_result;
  static vec3 v3(double x, double y, double z) { return gpd::gp_v3(x, y, z); }
  /// gp_build_patch_with: creased or not, with end tangents TS, TE where given (may be null).
  static gp_uint buildWith(int n, const vec3* V, const vec3* N, const vec3* PS, const vec3* PE, bool creased,
                           const vec3* TS, const vec3* TE, const int* vid, int mode, double* recs) {
    return gpd::gp_build_patch_with(n, V, N, PS, PE, creased ? 1 : 0, TS, TE, vid, mode, recs);
  }
  static gp_uint quality(int n, const double* recs, int mode, double* bulge) {
    return gpd::gp_patch_quality(n, recs, mode, bulge);
  }
  static result eval(int n, const double* recs, int mode, double xi, double eta) {
    return gpd::gp_patch_eval(n, recs, mode, xi, eta);
  }
  static const gpd::gp_domain* domain(int n) { return gpd::gp_domain_of(n, nullptr, 1); }
  static result evalDom(const gpd::gp_domain* dom, const double* recs, int mode, double xi, double eta) {
    return gpd::gp_patch_eval_dom(dom, recs, mode, xi, eta);
  }
  static result evalDomPosition(const gpd::gp_domain* dom, const double* recs, int mode, double xi, double eta) {
    return gpd::gp_patch_eval_dom_d(dom, recs, mode, xi, eta, 0);
  }
};

}  // namespace sf
